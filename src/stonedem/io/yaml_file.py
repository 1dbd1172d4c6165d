"""Reading a YAML input file that may be anything: one mapping, or one line saying why not.

Every YAML the user hands us (a scene, a wall case, a study config) goes through
:func:`read_yaml_mapping`: it checks the kind of file (a folder, a NetCDF or other binary
file, an empty file), its size, its encoding (UTF-8, with or without a BOM; UTF-16 and
Latin-1 are named), its nesting depth (PyYAML's scanner is quadratic in depth and its
composer recursive), what its aliases expand to (a 1 kB "billion laughs" of nested
aliases is 10^9 strings to anything that walks it: json.dumps, jsonschema, repr) and
duplicate keys (PyYAML keeps the last one silently), before a single value is used.
"""

from __future__ import annotations

import stat
from pathlib import Path

import yaml

from stonedem.errors import InputError

MAX_NESTING = 32  # containers inside containers; our files need at most 6
# values + characters that aliases (*name) may repeat in one file; config/config.yaml's
# anchors repeat ~1 500, a scene of 1000 bodies aliasing one template ~100 000
MAX_ALIAS_EXPANSION = 1_000_000

# first bytes of files people give by mistake
_MAGIC = (
    (b"\x89HDF\r\n\x1a\n", "a NetCDF-4/HDF5 file"),
    (b"CDF\x01", "a NetCDF file"),
    (b"CDF\x02", "a NetCDF file"),
    (b"\x89PNG", "a PNG image"),
    (b"%PDF", "a PDF file"),
    (b"PK\x03\x04", "a zip archive"),
    (b"\x1f\x8b", "a gzip file"),
    (b"\x7fELF", "a program"),
)


class _StrictLoader(yaml.SafeLoader):
    """safe_load that refuses a key given twice in one mapping."""


def _construct_mapping(loader, node, deep=False):
    seen = set()
    for key_node, _ in node.value:
        if key_node.tag == "tag:yaml.org,2002:merge" or not isinstance(key_node, yaml.ScalarNode):
            continue
        key = (key_node.tag, key_node.value)
        if key in seen:
            raise yaml.constructor.ConstructorError(
                None, None, f"the key {key_node.value!r} is given twice", key_node.start_mark
            )
        seen.add(key)
    return loader.construct_mapping(node, deep=deep)


_StrictLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)


def printable(text) -> str:
    """``text`` with control characters escaped (a hostile file name may hold a newline)."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(text))


class _Refused(yaml.MarkedYAMLError):
    """A document PyYAML would accept but we do not; ``fix`` says what to write instead."""

    def __init__(self, problem: str, mark, fix: str):
        super().__init__(None, None, problem, mark)
        self.fix = fix


def _check_structure(text: str) -> None:
    """Refuse deep nesting and runaway aliases from the event stream, before composing
    ('[' x 1000 took 2.7 s to compose; 9 levels of 10 aliases are 10^9 values).

    Each node's size is 1 (+ its characters for a scalar; + its children's sizes for a
    container); an alias adds its anchor's size, and the sizes aliases add are summed. An
    alias inside its own anchor (a loop, which PyYAML builds) is refused too."""
    opening = (yaml.SequenceStartEvent, yaml.MappingStartEvent)
    closing = (yaml.SequenceEndEvent, yaml.MappingEndEvent)
    stack = [[None, 0]]  # open containers: [anchor, size so far]
    sizes: dict = {}  # anchor -> size of its node, once closed
    expanded = 0
    for event in yaml.parse(text, Loader=_StrictLoader):
        if isinstance(event, opening):
            if len(stack) > MAX_NESTING:
                raise yaml.scanner.ScannerError(
                    None, None, f"nested deeper than {MAX_NESTING} levels", event.start_mark
                )
            stack.append([event.anchor, 1])
            continue
        if isinstance(event, closing):
            anchor, size = stack.pop()
        elif isinstance(event, yaml.ScalarEvent):
            anchor, size = event.anchor, 1 + len(event.value)
        elif isinstance(event, yaml.AliasEvent):
            if event.anchor not in sizes:
                if any(anchor == event.anchor for anchor, _ in stack):
                    raise _Refused(
                        f"the alias *{printable(event.anchor)} is inside its own anchor (a loop)",
                        event.start_mark,
                        "repeat a finished part only",
                    )
                continue  # undefined: the composer names it
            anchor, size = None, sizes[event.anchor]
            expanded += size
            if expanded > MAX_ALIAS_EXPANSION:
                raise _Refused(
                    f"its aliases expand to more than {MAX_ALIAS_EXPANSION} values and characters",
                    event.start_mark,
                    "write the values out instead of repeating them through aliases",
                )
        else:
            continue
        if anchor is not None:
            sizes[anchor] = size
        stack[-1][1] += size


def yaml_problem(err: yaml.YAMLError) -> str:
    """PyYAML's complaint as one line with its line and column."""
    problem = getattr(err, "problem", None)
    mark = getattr(err, "problem_mark", None)
    if problem:
        text = problem
        if mark is not None:
            text += f" (line {mark.line + 1}, column {mark.column + 1})"
    else:
        text = str(err)
    return " ".join(printable(text).split())


def decode_text(data: bytes, where: str, what: str) -> str:
    """UTF-8 text of ``data`` (a BOM is dropped), or an InputError naming the encoding problem."""
    for magic, kind in _MAGIC:
        if data.startswith(magic):
            raise InputError(
                where, f"is {kind}, not {what}", f"give the path of {what} (YAML text)"
            )
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise InputError(where, "is UTF-16 text", f"save {what} as UTF-8")
    if b"\x00" in data[:8192]:
        raise InputError(
            where, "is a binary file (it holds NUL bytes)", f"give the path of {what} (YAML text)"
        )
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        raise InputError(
            where,
            f"is not UTF-8 text (byte 0x{data[err.start]:02x} at offset {err.start}; "
            "Latin-1 or Windows-1252 perhaps)",
            f"save {what} as UTF-8",
        ) from None


def read_bytes_checked(path: str | Path, what: str, max_bytes: int) -> bytes:
    """The bytes of a regular file of at most ``max_bytes``, or an InputError naming it."""
    path = Path(path)
    where = printable(path)
    try:
        info = path.stat()
        if stat.S_ISDIR(info.st_mode):
            raise InputError(where, f"is a folder, not {what}", f"give the path of {what}")
        if not stat.S_ISREG(info.st_mode):  # a FIFO or a device: reading it could hang
            raise InputError(where, "is not a regular file", f"give the path of {what}")
        if info.st_size > max_bytes:
            raise InputError(
                where,
                f"{info.st_size} bytes exceed the limit of {max_bytes} for {what}",
                f"give {what}; is this the right file?",
            )
        with open(path, "rb") as handle:
            return handle.read(max_bytes + 1)[:max_bytes]
    except FileNotFoundError:
        raise InputError(where, f"{what} not found", "check the path") from None
    except OSError as err:  # no permission, a loop of links, a file that went away mid-read
        raise InputError(
            where, f"cannot read {what} ({err.strerror})", "give a readable file"
        ) from None


def parse_yaml_text(text: str, where: str) -> object:
    """The value of a YAML document, or an InputError naming ``where`` and the line."""
    try:
        _check_structure(text)
        return yaml.load(text, Loader=_StrictLoader)
    except _Refused as err:
        raise InputError(where, yaml_problem(err), err.fix) from None
    except yaml.YAMLError as err:
        raise InputError(
            where, f"not valid YAML: {yaml_problem(err)}", "fix the YAML syntax"
        ) from None
    except RecursionError:
        raise InputError(where, "not valid YAML: nested too deeply", "flatten the file") from None


def read_yaml_mapping(
    path: str | Path, what: str, max_bytes: int, fix: str, allow_empty: bool = False
) -> dict:
    """The top-level mapping of a YAML file.

    Parameters
    ----------
    path : str or Path
        The file.
    what : str
        What it should be, for messages ("a scene file").
    max_bytes : int
        The largest file accepted (a size check before reading).
    fix : str
        What to write instead when the file is empty or not a mapping.
    allow_empty : bool
        An empty file (or one of comments only) is ``{}`` instead of an error.

    Raises
    ------
    InputError
        One line naming the file: missing, a folder, binary or NetCDF, too large, not UTF-8,
        invalid or too deeply nested YAML, aliases that expand past MAX_ALIAS_EXPANSION or
        loop, a key given twice, empty, or not a mapping.
    """
    where = printable(path)
    text = decode_text(read_bytes_checked(path, what, max_bytes), where, what)
    spec = parse_yaml_text(text, where)
    if spec is None:
        if allow_empty:
            return {}
        raise InputError(where, "is empty", fix)
    if not isinstance(spec, dict):
        kind = {
            list: "a list",
            str: "a text",
            int: "a number",
            float: "a number",
            bool: "true/false",
        }
        raise InputError(
            where,
            f"is not a YAML mapping (it holds {kind.get(type(spec), type(spec).__name__)})",
            fix,
        )
    return spec
