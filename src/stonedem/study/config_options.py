"""A study config named on a command line (``--config``): read, merged and its cases' scenes
built before anything runs, refused in one line (:mod:`stonedem.options`' conventions)."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from stonedem.errors import InputError
from stonedem.options import input_file


def workflow_config(paths: Iterable[str | Path], field: str = "--config") -> dict:
    """The merged workflow config of ``paths`` (:func:`stonedem.study.grid.load_config`, whose
    reader refuses every unreadable file in one line); a refusal names the option too."""
    from stonedem.study.grid import load_config

    try:
        return load_config(*paths)
    except InputError as err:
        raise InputError(f"{field}: {err.field}", err.problem, err.fix) from None


def study_config(path: str | Path, records: Path, field: str = "--config") -> tuple[dict, list[str]]:
    """(config, its study names): the workflow config ``path`` merged over config.yaml of its
    folder (as Snakemake merges a profile such as config/quick.yaml), refused in one line when
    either file, or the cases' ``records`` folder, is missing."""
    path = Path(path)
    base = path.parent / "config.yaml"
    input_file(path, field, "YAML config file")
    input_file(base, field, "config folder holding config.yaml (the config is merged over it)")
    if not records.is_dir():
        raise InputError("records", f"no folder {records} here (the cases' records)",
                         "run from the repository root")
    config = workflow_config([base, path], field)
    studies = config.get("studies")
    return config, list(studies) if isinstance(studies, dict) else []


def check_case_scenes(cases, records: Path) -> None:
    """Build every case's scene once, as its run will (:func:`stonedem.study.grid.case_scene`),
    without running it: an InputError names the case and the field."""
    from stonedem.study.grid import case_scene

    for case in cases:
        try:
            case_scene(case, records)
        except InputError as err:
            raise InputError(f"{case.study}/{case.id}: {err.field}", err.problem, err.fix) from None
