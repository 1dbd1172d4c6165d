"""Inputs stored as JSON in a dataset's attributes (provenance), of bounded size.

json.dumps of a structure that repeats shared parts (a YAML alias bomb built in Python)
expands every repeat in C, holding the interpreter: 10^9 strings never end and no signal
is acted on. :func:`bounded_json` first measures the text on a walk that stops at the limit.
"""

from __future__ import annotations

import json

from stonedem.errors import InputError

MAX_PROVENANCE_CHARS = 4_000_000  # the largest scene file (MAX_SCENE_BYTES) as JSON


def json_size_over(value, limit: int, check=None) -> bool:
    """Whether ``value`` as JSON is longer than ``limit`` characters (a lower bound of its
    length is counted; the walk stops at the limit, so its cost is bounded too). ``check`` is
    called every 4096 nodes (``stonedem.entry.check_interrupt``: a SIGTERM acts there)."""
    left = limit
    stack = [value]
    visited = 0
    while stack:
        item = stack.pop()
        visited += 1
        if isinstance(item, dict):
            left -= 2 + 4 * len(item)
            for key, sub in item.items():
                stack.append(key)
                stack.append(sub)
        elif isinstance(item, (list, tuple)):
            left -= 2 + len(item)
            stack.extend(item)
        elif isinstance(item, str):
            left -= 2 + len(item)
        else:
            left -= 1
        if left < 0:
            return True
        if check is not None and visited % 4096 == 0:
            check()
    return False


def bounded_json(value, field: str, limit: int = MAX_PROVENANCE_CHARS, check=None) -> str:
    """``json.dumps(value, sort_keys=True, default=str)``, or an InputError naming ``field``
    when it would be longer than ``limit`` characters (``check``: as in :func:`json_size_over`)."""
    if json_size_over(value, limit, check):
        raise InputError(
            field,
            f"is over {limit} characters as JSON (stored as provenance in the output)",
            "shorten its free text or lists",
        )
    return json.dumps(value, sort_keys=True, default=str)
