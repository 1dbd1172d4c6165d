"""The one exception type for bad user input.

Every message is one line: the offending field (dotted path into the scene or case file),
what is wrong with it, and how to fix it. The command-line driver prints it and exits 2.
"""


class InputError(ValueError):
    """Bad input, as one line: ``"<field>: <problem>; <fix>"``.

    Parameters
    ----------
    field : str
        Where the input is wrong, e.g. ``"contact.k_n"`` or ``"bodies[2].mass"``.
    problem : str
        What is wrong with it.
    fix : str, optional
        How to mend it.

    Examples
    --------
    >>> str(InputError("solver.dt", "must be positive", "give dt in s"))
    'solver.dt: must be positive; give dt in s'
    """

    def __init__(self, field: str, problem: str, fix: str = ""):
        self.field = field
        self.problem = problem
        self.fix = fix
        message = f"{field}: {problem}"
        if fix:
            message += f"; {fix}"
        super().__init__(one_line(message))


def one_line(text: str, limit: int = 600) -> str:
    """``text`` as one printable line: control characters escaped (a file name or a key
    from hostile input may hold a newline or an ANSI escape), cut at ``limit`` characters."""
    if not text.isprintable():
        text = "".join(
            c if c.isprintable() else c.encode("unicode_escape").decode("ascii") for c in text
        )
    return text if len(text) <= limit else text[: limit - 3] + "..."


def doc_summary(doc: str | None) -> str:
    """A docstring's summary: its first paragraph as one line (a long summary is wrapped over
    several lines in the source), "" for none."""
    return " ".join((doc or "").strip().split("\n\n")[0].split())


def plain_number(value):
    """A number of any kind Python or numpy has (``np.float32(0.6)``, ``np.int64(3)``, a 0-d
    array) as a Python int or float, so that checkers need know only those two; anything else,
    bools (``np.True_`` too) included, comes back unchanged for the checker to refuse."""
    import numbers

    if (
        getattr(value, "ndim", None) == 0
        and hasattr(value, "item")
        and not isinstance(value, (int, float))
    ):
        value = value.item()  # numpy scalars and 0-d arrays; np.bool_ gives a bool
    if type(value) in (bool, int, float):
        return value
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    return value


def check_text(value, field: str, max_len: int, one_line: bool = True, describe=None) -> str:
    """Free text of at most ``max_len`` printable characters (``one_line=False``: line breaks
    and tabs too), or an InputError naming ``field``; ``describe(value)`` words a non-text
    value in the message (default: its type's name)."""
    if not isinstance(value, str):
        got = describe(value) if describe else type(value).__name__
        raise InputError(field, f"expected text, got {got}", "give text in quotes")
    if len(value) > max_len:
        raise InputError(field, f"{len(value)} characters exceed the limit {max_len}", "shorten it")
    bad = next((c for c in value if not c.isprintable() and (one_line or c not in "\n\t")), None)
    if bad is not None:
        raise InputError(
            field,
            f"contains the control character {bad!r}",
            "give printable text" + (" on one line" if one_line else ""),
        )
    return value


def check_number(value, field: str, positive: bool = False, nonnegative: bool = False) -> float:
    """A finite float from a YAML value, or an InputError naming ``field``.

    YAML 1.1 reads ``1.0e9`` (no sign in the exponent) as a string, so numeric strings
    are accepted; so are numpy's numbers (:func:`plain_number`), from a script's arrays.
    """
    import math

    value = plain_number(value)
    if isinstance(value, str):
        try:
            value = float(value)
        except ValueError:
            pass
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(field, f"expected a number, got {value!r}", "give a number in SI units")
    value = float(value)
    if not math.isfinite(value):
        raise InputError(field, f"{value} is not finite", "give a finite number")
    if positive and value <= 0.0:
        raise InputError(field, f"must be > 0, got {value}", "give a positive value")
    if nonnegative and value < 0.0:
        raise InputError(field, f"must be >= 0, got {value}", "give a non-negative value")
    return value
