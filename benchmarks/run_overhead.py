"""Python and output per run of the quick IDA, this commit beside its parent (issue 45, item 4).

Each commit runs the quick IDA's threshold searches (``config/config.yaml`` with
``config/quick.yaml``'s ``fragility:``: 4 records, the 1-drum column) in one process of its own
(a git worktree on PYTHONPATH, the shared Numba cache), as a search job does, after one
search that warms the records and the compiled loop. What a run costs beyond stepping is the
process's wall time less the compiled loop's (each run's ``wall_seconds`` and
``compile_seconds``, summed), divided by the runs: building the scene and its plan, the checks,
the dataset or piece, and the files written. The commits alternate, best of ``--repeats``.
Writes ``results/bench/run_overhead.nc`` and prints one line per commit and the ratio.

    python -m benchmarks.run_overhead [--parent HEAD~1|none] [--repeats 3] [--out
    results/bench/run_overhead.nc]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

# run as a file (python benchmarks/x.py) as well as a module (python -m benchmarks.x)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

ROOT = Path(__file__).resolve().parents[1]

# runs in the commit's own checkout (PYTHONPATH): prints one JSON line
WORKER = r"""
import io, json, sys, tempfile, time
from pathlib import Path
import yaml
import stonedem.engine.run as run_module
import stonedem.engine.simulate as simulate_module
from stonedem.fragility.ida import fragility_config
from stonedem.study.grid import config_cases
from stonedem.study import runner

root = Path(sys.argv[1])
config = yaml.safe_load((root / "config/config.yaml").read_text())
config["fragility"].update(yaml.safe_load((root / "config/quick.yaml").read_text())["fragility"])
systems = [c for cases in config_cases(fragility_config(config)).values() for c in cases]
stepping = [0.0, 0]
real = simulate_module.simulate

def timed(scene, *args, **kwargs):
    result = real(scene, *args, **kwargs)
    stepping[0] += result.wall_seconds + result.compile_seconds
    stepping[1] += 1
    return result

run_module.simulate = timed
store = runner.CaseStore(None, str(root / "records"))
slim = hasattr(__import__("stonedem.study.cube", fromlist=["x"]), "RunPiece")
with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    def search_all(tag, chosen):
        for i, system in enumerate(chosen):
            runs = None if slim else tmp / f"{tag}{i}"
            runner.run_search(system, runs, tmp / f"{tag}{i}.nc", store, io.StringIO())
    search_all("warm", systems[:1])
    stepping[:] = [0.0, 0]
    start = time.perf_counter()
    search_all("timed", systems)
    wall = time.perf_counter() - start
print(json.dumps({"wall": wall, "stepping": stepping[0], "runs": stepping[1],
                  "searches": len(systems), "files_per_run": not slim}))
"""


def checkout(commit: str, folder: Path) -> Path:
    """A worktree of ``commit`` in ``folder`` (removed by the caller's temporary folder)."""
    path = folder / commit[:10]
    subprocess.run(
        ["git", "-C", str(ROOT), "worktree", "add", "--detach", str(path), commit],
        check=True,
        capture_output=True,
    )
    return path


def measure(tree: Path) -> dict:
    env = {**os.environ, "PYTHONPATH": str(tree / "src")}
    proc = subprocess.run(
        [sys.executable, "-c", WORKER, str(ROOT)], env=env, capture_output=True, text=True, cwd=tree
    )
    if proc.returncode != 0:
        raise SystemExit(
            f"error: the worker failed in {tree}: {proc.stderr.strip().splitlines()[-1:]}"
        )
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--parent", default="HEAD~1", help="the commit to compare against, or none")
    parser.add_argument(
        "--repeats", type=int, default=3, help="alternating runs per commit; best kept"
    )
    parser.add_argument(
        "--out", default="results/bench/run_overhead.nc", help="the dataset to write"
    )
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error("--repeats: give a whole number >= 1")
    from stonedem.entry import guarded

    return guarded(lambda: measure_commits(args))


def commit_of(rev: str, field: str) -> str:
    """The full hash of ``rev``, or a one-line InputError naming ``field``."""
    from benchmarks.kernel import ParentUnavailable, resolve_commit
    from stonedem.errors import InputError

    try:
        return resolve_commit(rev, ROOT)
    except ParentUnavailable as exc:
        raise InputError(
            field, str(exc), "give a commit of this repository's history, or --parent none"
        ) from None


def measure_commits(args) -> int:
    import numpy as np
    import xarray as xr

    from stonedem.entry import check_output_path
    from stonedem.io.netcdf import code_version, write_dataset

    out = Path(args.out)
    check_output_path(out, "--out", suffixes=(".nc",))  # before minutes of measuring
    commits = {"this": commit_of("HEAD", "checkout")}
    if args.parent != "none":
        commits["parent"] = commit_of(args.parent, "--parent")
    with tempfile.TemporaryDirectory() as folder:
        trees = {name: checkout(commit, Path(folder)) for name, commit in commits.items()}
        best: dict[str, dict] = {}
        try:
            for k in range(args.repeats):
                for name, tree in trees.items():
                    got = measure(tree)
                    got["per_run_ms"] = 1e3 * (got["wall"] - got["stepping"]) / got["runs"]
                    print(
                        f"[{k + 1}/{args.repeats}] {name} {commits[name][:10]}: {got['runs']} "
                        "runs in "
                        f"{got['searches']} searches, {got['wall']:.2f} s, stepping "
                        f"{got['stepping']:.2f} s, "
                        f"{got['per_run_ms']:.1f} ms a run beyond it",
                        flush=True,
                    )
                    if name not in best or got["per_run_ms"] < best[name]["per_run_ms"]:
                        best[name] = got
        finally:
            for tree in trees.values():
                subprocess.run(
                    ["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)],
                    capture_output=True,
                )
    names = list(best)
    ds = xr.Dataset(
        {
            "python_ms_per_run": (
                "version",
                [best[n]["per_run_ms"] for n in names],
                {
                    "units": "ms",
                    "long_name": "wall time per run beyond the compiled loop "
                    "(scene, plan, checks, dataset or piece, files)",
                },
            ),
            "runs": (
                "version",
                np.array([best[n]["runs"] for n in names], dtype=np.int32),
                {"units": "1", "long_name": "runs of the quick IDA's searches"},
            ),
            "stepping_seconds": (
                "version",
                [best[n]["stepping"] for n in names],
                {"units": "s", "long_name": "the compiled loop's wall time, summed"},
            ),
            "wall_seconds": (
                "version",
                [best[n]["wall"] for n in names],
                {"units": "s", "long_name": "the searches' wall time"},
            ),
        },
        coords={
            "version": (
                "version",
                np.array(names, dtype=object),
                {"long_name": "this commit or its parent"},
            ),
            "commit": (
                "version",
                np.array([commits[n] for n in names], dtype=object),
                {"long_name": "git commit"},
            ),
        },
        attrs={
            "title": "stonedem benchmark: Python and output per run of the quick IDA",
            "source": code_version(),
            "repeats": args.repeats,
            "method": __doc__.split("\n\n")[1],
        },
    )
    out.parent.mkdir(parents=True, exist_ok=True)
    write_dataset(ds, out)
    if "parent" in best:
        ratio = best["parent"]["per_run_ms"] / best["this"]["per_run_ms"]
        print(
            f"per run beyond the kernel: {best['this']['per_run_ms']:.1f} ms, parent "
            f"{best['parent']['per_run_ms']:.1f} ms (x{ratio:.2f} less); wrote {out}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
