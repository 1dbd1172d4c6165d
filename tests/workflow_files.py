"""The workflow's file patterns, read from its rule files: where the catalogue's inputs lie
(``CATALOGUE_PATHS`` in workflow/rules/common.smk) and what the rules' outputs are."""

from __future__ import annotations

import ast
import re
from pathlib import Path

RULES = Path(__file__).resolve().parents[1] / "workflow" / "rules"


def catalogue_paths() -> dict:
    """{kind: path pattern} of the catalogue's inputs, as common.smk maps them."""
    block = re.search(
        r"^CATALOGUE_PATHS = (\{.*?^\})", (RULES / "common.smk").read_text(), re.M | re.S
    )
    return ast.literal_eval(block.group(1))


def rule_outputs() -> list[re.Pattern]:
    """Every output pattern of workflow/rules/*.smk under results/ or records/: the strings of
    the rules' output sections and of the ``*_path`` functions they call (a case's file); a
    wildcard or an f-string field matches one path component."""
    patterns = []
    for smk in sorted(RULES.glob("*.smk")):
        text = smk.read_text()
        for _, section in re.findall(r"^( +)output:\n((?:\1 +.*\n|\s*\n)+)", text, re.M):
            patterns += re.findall(r'"((?:results|records)/[^"]*)"', section)
        path_functions = (
            r'^def \w+_path\(.*\):\n(?:    .*\n)*?    return f"((?:results|records)/[^"]*)"'
        )
        patterns += re.findall(path_functions, text, re.M)
    return [re.compile("[^/]+".join(map(re.escape, re.split(r"\{[^}]*\}", p)))) for p in patterns]


def made_by_a_rule(path: str, outputs: list[re.Pattern]) -> bool:
    return any(pattern.fullmatch(path) for pattern in outputs)
