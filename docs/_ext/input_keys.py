"""Sphinx directive ``input-keys``: the key table of an input kind, generated from its spec.

Every key a user may write is declared once, as a :class:`stonedem.io.spec.Field` row; the
tables on the guide pages are printed from those rows when the docs are built, never typed.
In MyST::

    ```{input-keys} stonedem.engine.scene:SCENE
    :prefix: solver.
    ```

The argument is ``module:name``, then ``.attribute`` or ``[key]`` steps to a
:class:`~stonedem.io.spec.Spec` (``stonedem.engine.laws:LAWS[point].spec``); ``prefix`` is put
before every key. A path that names no spec fails the build: the page has drifted from the
code.
"""

from __future__ import annotations

import importlib
import re

from docutils import nodes
from docutils.parsers.rst import directives
from docutils.statemachine import StringList
from sphinx.util.docutils import SphinxDirective

_STEP = re.compile(r"\.([A-Za-z_]\w*)|\[([^\]]+)\]")


def resolve(path: str):
    """The object ``module:name.attr[key]...`` names."""
    module, _, rest = path.partition(":")
    head = re.match(r"[A-Za-z_]\w*", rest)
    if not head:
        raise ValueError(f"{path}: expected module:name")
    obj = getattr(importlib.import_module(module), head.group(0))
    tail = rest[head.end() :]
    for m in _STEP.finditer(tail):
        obj = getattr(obj, m.group(1)) if m.group(1) else obj[m.group(2)]
    if "".join(m.group(0) for m in _STEP.finditer(tail)) != tail:
        raise ValueError(f"{path}: cannot read {tail!r}")
    return obj


class InputKeys(SphinxDirective):
    required_arguments = 1
    option_spec = {"prefix": directives.unchanged}

    def run(self):
        from stonedem.io.spec import Spec, key_table

        spec = resolve(self.arguments[0])
        if not isinstance(spec, Spec):
            raise self.error(f"{self.arguments[0]} is a {type(spec).__name__}, not a Spec")
        lines = key_table(spec, self.options.get("prefix", ""))
        node = nodes.container()
        self.state.nested_parse(StringList(lines, source="input-keys"), self.content_offset, node)
        return node.children


def setup(app):
    app.add_directive("input-keys", InputKeys)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
