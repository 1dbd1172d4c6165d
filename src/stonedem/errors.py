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
