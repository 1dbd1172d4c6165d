"""The catalogue of figures and tables (stonedem.figures): every entry of the study's configs
resolves to files the workflow makes, and the library names no results/ path."""

from pathlib import Path

import pytest

import stonedem
from stonedem.figures import figure_table, figures, input_paths, reduction_table
from stonedem.study.grid import config_cases, load_config
from tests.workflow_files import catalogue_paths, made_by_a_rule, rule_outputs

ROOT = Path(__file__).resolve().parents[2]
# command-line entry points whose default output folder is under results/
CLI_DEFAULTS = {
    "cli.py",
    "motion/cli.py",
    "study/equivalence.py",
}  # command lines: a default output


@pytest.mark.parametrize("profile", [None, "config/quick.yaml"])
def test_every_figure_and_table_resolves_to_files_a_rule_makes(profile):
    config = load_config(ROOT / "config" / "config.yaml", *([ROOT / profile] if profile else []))
    studies = {name: {c.id: c for c in cases} for name, cases in config_cases(config).items()}
    tables, figs = reduction_table(studies), figure_table(studies, config)
    if profile is None:  # the full study makes every entry of the catalogue
        assert set(figs) == set(figures(config)) and len(tables) >= 13 and len(figs) >= 90
    patterns, outputs = catalogue_paths(), rule_outputs()
    made = [f"results/tables/{name}.csv" for name in tables] + [
        f"results/figures/{name}.png" for name in figs
    ]
    for path in made:
        assert made_by_a_rule(path, outputs), path
    for name, entry in {**tables, **figs}.items():
        for path in input_paths(entry.inputs, patterns):
            assert made_by_a_rule(path, outputs) or path in made, (
                f"{name} reads {path}, which no rule makes"
            )


def test_no_library_module_names_a_results_path():
    package = Path(stonedem.__file__).parent
    found = [
        str(p.relative_to(package))
        for p in package.rglob("*.py")
        if p.relative_to(package).as_posix() not in CLI_DEFAULTS
        and p.relative_to(package).parts[0] != "bench"
        and "results/" in p.read_text()
    ]
    assert not found, f"results/ paths belong in the workflow (workflow/rules/common.smk): {found}"


def test_fig_7_22_from_searches_without_histories_names_the_setting(tmp_path):
    """search: {histories: false} keeps a search's measures only; Fig. 7.22 draws histories, so
    it says which setting to change instead of failing on a missing variable."""
    import numpy as np
    import xarray as xr

    from stonedem.errors import InputError
    from stonedem.figures.chapter7 import _standalone_vs_colonnade

    paths = []
    for study in ("standalone_records", "colonnade_records"):
        cube = xr.Dataset(
            {"collapsed": (("record", "n_drums", "run"), np.zeros((1, 1, 2)))},
            coords={
                "record": ["athens_standin_kocaeli_arc000"],
                "n_drums": [1],
                "pga": (("record", "n_drums", "run"), [[[1.0, 2.0]]]),
            },
            attrs={"study": study},
        )
        paths.append(tmp_path / f"{study}.nc")
        cube.to_netcdf(paths[-1])
    with pytest.raises(InputError, match=r"studies\.standalone_records\.search\.histories"):
        _standalone_vs_colonnade(paths, tmp_path / "fig.png")
    assert not (tmp_path / "fig.png").exists()
