"""A study config named on a command line (``--config``): read, merged and its cases' scenes
built before anything runs, refused in one line (:mod:`stonedem.options`' conventions)."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from stonedem.errors import InputError
from stonedem.options import chosen, input_file, path_arg


def workflow_config(paths: Iterable[str | Path], field: str = "--config") -> dict:
    """The merged workflow config of ``paths`` (:func:`stonedem.study.grid.load_config`, whose
    reader refuses every unreadable file in one line); a refusal names the option too."""
    from stonedem.study.grid import load_config

    try:
        return load_config(*paths)
    except InputError as err:
        raise _under(field, err) from None


def study_config(
    path: str | Path, records: Path, field: str = "--config"
) -> tuple[dict, list[str]]:
    """(config, its study names): the workflow config ``path`` merged over config.yaml of its
    folder (as Snakemake merges a profile such as config/quick.yaml), refused in one line when
    either file, or the cases' ``records`` folder, is missing."""
    path = Path(path)
    base = path.parent / "config.yaml"
    input_file(path, field, "YAML config file")
    input_file(base, field, "config folder holding config.yaml (the config is merged over it)")
    if not records.is_dir():
        raise InputError(
            "records",
            f"no folder {records} here (the cases' records)",
            "run from the repository root",
        )
    config = workflow_config([base, path], field)
    studies = config.get("studies")
    return config, list(studies) if isinstance(studies, dict) else []


def check_case_scenes(cases, records: Path) -> None:
    """Build every case's scene once, as its run will (:func:`stonedem.study.runner.case_scene`),
    without running it: an InputError names the case and the field."""
    from stonedem.study.runner import case_scene

    for case in cases:
        try:
            case_scene(case, records)
        except InputError as err:
            raise _under(f"{case.study}/{case.id}", err) from None


def _under(name: str, err: InputError) -> InputError:
    """``err`` with its field named under ``name`` (an option, or a case)."""
    return InputError(f"{name}: {err.field}", err.problem, err.fix)


def add_study_arguments(parser) -> None:
    """``--config`` and ``--studies``, as the commands over a study config take them."""
    parser.add_argument(
        "--config",
        type=path_arg,
        default=Path("config/config.yaml"),
        help="config file, merged over config.yaml of its folder (default config/config.yaml)",
    )
    parser.add_argument(
        "--studies",
        nargs="*",
        default=None,
        help="studies of the config (default: every study of the rigid-block engine)",
    )


def chosen_cases(
    config: dict, known: list[str], studies, records: Path, limit: int = 0
) -> tuple[list, list]:
    """(grid cases, search systems) of the ``--studies`` chosen (all when None), at most
    ``limit`` of each (0: all), their scenes built once (:func:`check_case_scenes`); an
    InputError when they hold no case."""
    from stonedem.study.grid import config_cases

    cases, systems = [], []
    for group in config_cases(
        config, chosen(studies if studies is not None else known, "--studies", known)
    ).values():
        for case in group:
            (systems if case.search is not None else cases).append(case)
    if limit:
        cases, systems = cases[:limit], systems[:limit]
    if not cases and not systems:
        raise InputError(
            "--studies", "no cases in the studies chosen", "give studies that have cases"
        )
    check_case_scenes(cases + systems, records)  # a system's scene holds its search's start
    return cases, systems
