"""The Snakemake workflow: lint clean, config validated, committed records up to date."""

import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def snakemake(*args, cwd=ROOT):
    return subprocess.run(
        [sys.executable, "-m", "snakemake", *args], cwd=cwd, capture_output=True, text=True
    )


def test_lint_is_clean():
    for args in ((), ("--config", "extract_records=true")):
        proc = snakemake("--lint", *args)
        assert proc.returncode == 0, proc.stdout + proc.stderr


def test_committed_records_need_no_rerun():
    assert len(list((ROOT / "records").glob("*.nc"))) == 4
    proc = snakemake("-n", "--configfile", "tests/workflow/config.yaml")
    assert proc.returncode == 0, proc.stderr
    assert "extract_record" not in proc.stdout, proc.stdout


def test_extraction_rule_on_request():
    proc = snakemake("-n", "--config", "extract_records=true", "--forcerun", "extract_record")
    assert proc.returncode == 0, proc.stderr
    assert "extract_record" in proc.stdout


def test_bad_config_is_refused(tmp_path):
    for item in ("Snakefile", "workflow", "records"):
        src = ROOT / item
        (shutil.copytree if src.is_dir() else shutil.copy)(src, tmp_path / item)
    (tmp_path / "config").mkdir()
    (tmp_path / "config" / "config.yaml").write_text(
        "records:\n  x: {set: farfield, id: 0, component: c}\n"
    )
    proc = snakemake("-n", cwd=tmp_path)
    assert proc.returncode != 0
    assert "Bad config: records.x." in proc.stderr, proc.stdout + proc.stderr


# --- issue 13: the study config is refused at DAG time, by its path
# (stonedem.study.grid.check_config) ----


def _small_workflow(tmp_path, mutate=None):
    """The workflow in tmp_path with a small config (three tiny studies, no walls, no
    validations), changed by ``mutate(config)``."""
    import yaml

    from stonedem.study.grid import load_config

    for item in ("Snakefile", "workflow", "records", "config", "profiles"):
        src = ROOT / item
        (shutil.copytree if src.is_dir() else shutil.copy)(src, tmp_path / item)
    config = load_config(
        ROOT / "config" / "config.yaml", ROOT / "tests" / "workflow" / "config.yaml"
    )
    config["studies"] = {
        k: config["studies"][k] for k in ("standalone_records", "harmonic_drums", "ramp_drums")
    }
    config.update(wall_cases=[], run_validation=False)
    if mutate:
        mutate(config)
    (tmp_path / "config" / "config.yaml").write_text(yaml.safe_dump(config, sort_keys=False))
    return tmp_path


def _assert_refused(proc, field):
    """Non-zero exit, and the last line printed names the field: no traceback."""
    out = proc.stdout + proc.stderr
    assert proc.returncode != 0, out
    last = proc.stderr.strip().splitlines()[-1]
    assert last.startswith(f"Bad config: {field}: "), out
    assert "Traceback" not in out and "File " not in out, out
    return last


def test_dry_run_refuses_bad_grid_values_by_their_config_path(tmp_path):
    def mutate(config):
        config["studies"]["standalone_records"]["grid"]["pga"] = [2.0, -2.0]

    proc = snakemake("-n", cwd=_small_workflow(tmp_path, mutate))
    assert "must be > 0, got -2 m s-2" in _assert_refused(
        proc, "studies.standalone_records.grid.pga[1]"
    )
    (tmp_path / "config" / "bad.yaml").write_text(
        "studies: {ramp_drums: {grid: {n_drums: [high]}}}\n"
    )
    proc = snakemake("-n", "--configfile", "config/bad.yaml", cwd=tmp_path)
    _assert_refused(proc, "studies.ramp_drums.grid.n_drums[0]")


def test_dry_run_refuses_unknown_records(tmp_path):
    def mutate(config):
        config["studies"]["standalone_records"]["grid"]["record"] = [
            "mexico_standin_chichi_tcu102",
            "nope",
        ]

    proc = snakemake("-n", cwd=_small_workflow(tmp_path, mutate))
    assert "unknown record 'nope'" in _assert_refused(
        proc, "studies.standalone_records.grid.record[1]"
    )


def test_dry_run_refuses_a_study_without_a_structure_and_a_negative_stiffness(tmp_path):
    proc = snakemake(
        "-n", cwd=_small_workflow(tmp_path, lambda c: c["studies"]["ramp_drums"].pop("structure"))
    )
    _assert_refused(proc, "studies.ramp_drums.structure")
    (tmp_path / "config" / "bad.yaml").write_text(
        "studies: {ramp_drums: {structure: {kind: column, width: 1.0}}}\ndefaults: {contact: "
        "{k_n: -1.0e+9}}\n"
    )
    proc = snakemake("-n", "--configfile", "config/bad.yaml", cwd=tmp_path)
    _assert_refused(proc, "defaults.contact.k_n")


def test_dry_run_refuses_a_search_tolerance_finer_than_the_rounding(tmp_path):
    # values run have 4 significant digits: 1e-6 would end "bracketed" at ~1e-3 (issue 43)
    def mutate(config):
        config["studies"]["standalone_records"]["search"]["tolerance"] = 1.0e-6

    proc = snakemake("-n", cwd=_small_workflow(tmp_path, mutate))
    assert "give tolerance >= 0.001" in _assert_refused(
        proc, "studies.standalone_records.search.tolerance"
    )
    (tmp_path / "config" / "bad.yaml").write_text(
        "studies: {standalone_records: {search: {tolerance: 0.02}}}\nfragility: {search: "
        "{tolerance: 5.0e-4}}\n"
    )
    proc = snakemake("fragility", "-n", "--configfile", "config/bad.yaml", cwd=tmp_path)
    # the schema checks fragility: before its cases, naming the same floor
    assert "minimum of 0.001" in _assert_refused(proc, "fragility.search.tolerance")


def test_dry_run_builds_the_dag_after_grid_keys_are_added_and_reordered(tmp_path):
    """A grid key added to a study (harmonic_drums had only n_drums) is part of its case ids;
    the snapshot figures of that study name the configured case files (thesis Fig. 6.7-6.8)."""

    def mutate(config):
        config["studies"]["harmonic_drums"]["grid"] = {"friction": [0.48], "n_drums": [2, 4]}
        grid = config["studies"]["standalone_records"]["grid"]
        config["studies"]["standalone_records"]["grid"] = {
            "friction": [0.4, 0.485],
            "record": grid["record"],
            "n_drums": grid["n_drums"],
        }

    proc = snakemake("-n", cwd=_small_workflow(tmp_path, mutate))
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    for path in (
        "results/cases/harmonic_drums/mu-0.48_drums-4.nc",
        "results/figures/thesis_fig_6_7.png",
        "results/searches/standalone_records/mu-0.4_rec-mexico_standin_chichi_tcu102_drums-1.nc",
    ):
        assert path in proc.stdout, path


def _tiny_copy(tmp_path):
    for item in ("Snakefile", "workflow", "records", "config", "profiles"):
        src = ROOT / item
        (shutil.copytree if src.is_dir() else shutil.copy)(src, tmp_path / item)
    shutil.copy(ROOT / "tests" / "workflow" / "config.yaml", tmp_path / "tiny.yaml")


def _expected_figures():
    import yaml
    from snakemake.utils import update_config

    from stonedem.figures import figure_table
    from stonedem.study.grid import case_table

    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    update_config(config, yaml.safe_load((ROOT / "tests" / "workflow" / "config.yaml").read_text()))
    studies = {
        n: {c.id: c for c in case_table(n, s, config["defaults"])}
        for n, s in config["studies"].items()
    }
    return sorted(f"{name}.png" for name in figure_table(studies, config))


def test_tiny_study_runs_end_to_end_with_figures_tables_and_report(tmp_path):
    _tiny_copy(tmp_path)
    proc = snakemake("-j2", "--configfile", "tiny.yaml", cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    import xarray as xr

    with xr.open_dataset(tmp_path / "results/cubes/colonnade_records.nc") as cube:
        # a threshold search: its runs on a run dimension, the searched pga a coordinate
        assert (
            cube["pga"].dims == ("record", "n_drums", "run")
            and cube["epistyle_displacement"].dims[-1] == "time"
        )
        assert int(cube["n_runs"].sum()) == cube.sizes["run"] == 2 and str(
            cube["search_status"].values.flat[0]
        )
    # a search writes one file (search_runs: summary), no case file per run
    assert not (tmp_path / "results/cases/colonnade_records").exists()
    assert (
        (tmp_path / "results/tables/table_7_1.csv").read_text().startswith("system,n_drums,record")
    )
    figures = sorted(p.name for p in (tmp_path / "results/figures").glob("*.png"))
    walls = ["manuscript_fig_21.png", "manuscript_fig_22.png"]  # the tiny config's one wall case
    expected = sorted(_expected_figures() + walls)
    assert len(expected) >= 25 and figures == expected, set(expected) ^ set(figures)
    wall_table = (tmp_path / "results/tables/manuscript_table_3.csv").read_text().splitlines()
    assert len(wall_table) == 2 and "within_tolerance" in wall_table[0] and "10-11" in wall_table[1]

    # the HTML report: every figure, with its caption
    proc = snakemake("--configfile", "tiny.yaml", "--report", "report.zip", cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    import zipfile

    with zipfile.ZipFile(tmp_path / "report.zip") as archive:
        names = archive.namelist()
        pngs = [n for n in names if n.endswith(".png")]
        assert len(pngs) >= len(expected), f"report holds {len(pngs)} of {len(expected)} figures"
        text = "".join(
            archive.read(n).decode("utf-8", "ignore") for n in names if n.endswith((".html", ".js"))
        )
        assert "Regenerates thesis Fig. 6.10" in text, "the report carries the figure captions"


# a run killed part-way and its rerun: tests/faults/test_study_faults.py (three SIGKILLs)


def test_slurm_profile_dry_run():
    import re

    from stonedem.kernels import sources_key

    # --forceall: the whole plan, whatever results/ of this checkout already holds (its compile
    # markers)
    proc = snakemake(
        "-n",
        "--forceall",
        "--profile",
        "config/profiles/slurm",
        "--configfile",
        "tests/workflow/config.yaml",
    )
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    assert "dry-run" in proc.stdout + proc.stderr
    assert "search_ida_" not in proc.stdout  # the IDA is planned only when asked for
    # the engine compiled once, a job per time loop, before the jobs that run it
    # (workflow/rules/compile.smk)
    blocks = re.findall(r"^( *)rule (\w+):\n((?:\1    .*\n)+)", proc.stdout, re.M)
    markers = [
        f"results/compiled/{sources_key()}/{loop}.txt" for loop in ("contact_graph", "general")
    ]
    assert (
        sorted(
            re.search(r"output: (.*)", text).group(1)
            for _, name, text in blocks
            if name == "compile_kernels"
        )
        == markers
    )
    engine = [
        (name, text.split("output:")[0])
        for _, name, text in blocks
        if name.startswith(("simulate_", "search_", "stripes_", "validate_"))
    ]
    assert len(engine) >= 20 and all(m in inputs for _, inputs in engine for m in markers), engine


def test_fragility_dry_run_packs_the_searches_into_tens_of_jobs():
    # the full IDA's plan: 628 searches (6 structures x 100 records, the block x 28) packed by
    # fragility.job_seconds into tens of jobs
    from stonedem.fragility.ida import fragility_config
    from stonedem.study.grid import config_cases, load_config
    from stonedem.study.jobs import plan_jobs

    studies = config_cases(fragility_config(load_config(ROOT / "config" / "config.yaml")))
    assert sum(len(cases) for cases in studies.values()) == 628
    jobs = plan_jobs(studies, ROOT / "records", search_seconds=300.0)
    assert 40 <= len(jobs) <= 150 and all(job.is_search for job in jobs), len(jobs)
    # the quick profile on the cluster profile: two structures, four records, nothing else
    proc = snakemake(
        "fragility", "-n", "--profile", "config/profiles/slurm", "--configfile", "config/quick.yaml"
    )
    out = proc.stdout + proc.stderr
    assert proc.returncode == 0, out[-2000:]
    assert (
        "search_ida_column_1_drum_0" in out
        and "search_ida_colonnade" not in out
        and "simulate_" not in out
    )


def test_an_ensemble_study_gives_collapse_fractions_and_member_zero_is_todays_run(tmp_path):
    """ensemble: {members: 2} (issue 44): every case twice, the cube's verdicts on a member
    dimension beside their fraction, Table 7.1 with a50; member 0 as the study without members."""

    def mutate(config):
        from stonedem.study.grid import load_config

        tiny = load_config(
            ROOT / "config" / "config.yaml", ROOT / "tests" / "workflow" / "config.yaml"
        )["studies"]
        config["studies"] = {
            k: tiny[k] for k in ("standalone_records", "colonnade_records", "harmonic_frequency")
        }
        config["studies"]["harmonic_frequency"]["grid"]["frequency"] = [20.0]

    root = _small_workflow(tmp_path, mutate)
    case = "A-0.25_f-20_mu-0.48"
    proc = snakemake(
        "-j2", f"results/cases/harmonic_frequency/{case}.nc", cwd=root
    )  # the plain case alone
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    import numpy as np
    import xarray as xr

    with xr.open_dataset(root / f"results/cases/harmonic_frequency/{case}.nc") as ds:
        today = ds.load()
    (root / "ensemble.yaml").write_text("ensemble: {members: 2}\n")
    proc = snakemake("-j2", "--configfile", "config/config.yaml", "ensemble.yaml", cwd=root)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    with xr.open_dataset(root / f"results/cases/harmonic_frequency/{case}_m-0.nc") as member:
        assert int(member["member"]) == 0
        for name in today.data_vars:
            np.testing.assert_array_equal(member[name].values, today[name].values, err_msg=name)
    with xr.open_dataset(root / "results/cubes/harmonic_frequency.nc") as cube:
        assert cube["collapsed"].dims[-1] == "member" and cube.sizes["member"] == 2
        assert float(cube["collapse_fraction"].max()) == 1.0  # 20 Hz, 0.25 m: the column falls
    with xr.open_dataset(root / "results/cubes/standalone_records.nc") as cube:
        assert "member" in cube["collapse_threshold"].dims
    import csv

    rows = list(csv.DictReader((root / "results/tables/table_7_1.csv").open()))
    assert "a50_m_s2" in rows[0] and "a_first_m_s2" in rows[0] and len(rows) == 2
    # the stripes: every value a member ran inside the zone, run by both members
    for path in sorted((root / "results/stripes").glob("*/*.nc")):
        with xr.open_dataset(path) as fills:
            system = path.stem
            searches = [
                xr.open_dataset(root / f"results/searches/{path.parent.name}/{system}_m-{j}.nc")
                for j in (0, 1)
            ]
            ran = [set(np.asarray(s[s.attrs["search_parameter"]].values, float)) for s in searches]
            low = min(float(s.survived_below_threshold) for s in searches)
            high = max(float(s.collapse_threshold) for s in searches)
            zone = {v for v in ran[0] | ran[1] if low <= v <= high}
            for j in (0, 1):
                mine = set(fills.stripe_value.values[fills.stripe_member.values == j].tolist())
                assert mine == zone - ran[j], (system, j)
                assert not (mine & ran[j])
    fills_made = [r for r in rows if r["stripes"] == "search runs and stripe fills"]
    assert len(list((root / "results/stripes").glob("*/*.nc"))) == 2 and fills_made == rows
    assert (root / "results/figures/thesis_fig_6_5.png").stat().st_size > 10_000
