"""Wall time of a whole Snakemake target from a fresh clone, this commit beside its parent (issue
32).

Each commit is cloned afresh into a temporary folder and runs ``python -m snakemake -j2
TARGET`` there with its own, empty Numba cache (so compiling counts, as on a fresh machine)
and its own package on PYTHONPATH. The two run one after the other on the same machine in the
same session, so the parent's time checks the machine's speed. Writes
results/bench/study_time.csv (target, version, commit, wall seconds, exit status, jobs): the
rows of this target and config replace those of an earlier run, the other targets' rows stay.

    python -m benchmarks.study_time [--parent 55e0c02|none] [--target all] [--configfile
    config/quick.yaml]
                                    [--out results/bench/study_time.csv] [--out-clones FOLDER]

The full study takes 6-7 min per commit on 2 cores; the full IDA (``--target fragility``)
about 68 min for 55e0c02's parent, so ``--parent none`` times this commit alone (check the
machine's speed with the study's row, or a few IDA jobs of both commits).
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# run as a file (python benchmarks/x.py) as well as a module (python -m benchmarks.x)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import options
from stonedem.entry import check_output_path
from stonedem.errors import InputError

ROOT = Path(__file__).resolve().parents[1]


def commit_of(rev: str) -> str:
    """The full hash of ``rev`` (:func:`benchmarks.kernel.resolve_commit`), or one line naming
    the option."""
    from benchmarks.kernel import ParentUnavailable, resolve_commit

    try:
        return resolve_commit(rev, ROOT)
    except ParentUnavailable as exc:
        raise InputError(
            "--parent" if rev != "HEAD" else "checkout",
            str(exc),
            "give a commit of this repository's history",
        ) from None


FIELDS = ("target", "config", "version", "commit", "wall_seconds", "exit_status", "jobs", "machine")


def earlier_rows(path: Path) -> list[dict]:
    """The rows of an earlier run's CSV at path; none if it is missing or not one of ours."""
    import csv

    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
    except (OSError, UnicodeDecodeError, csv.Error):
        return []
    return rows if rows and set(rows[0]) == set(FIELDS) else []


def run_target(commit: str, target: str, configfiles: list[str], workdir: Path) -> dict:
    """Clone ``commit`` into workdir and time ``snakemake -j2 target`` there."""
    clone = workdir / commit[:10]
    subprocess.run(["git", "clone", "--quiet", str(ROOT), str(clone)], check=True)
    subprocess.run(["git", "-C", str(clone), "checkout", "--quiet", commit], check=True)
    env = dict(
        os.environ,
        PYTHONPATH=str(clone / "src"),
        XDG_CACHE_HOME=str(workdir / f"cache-{commit[:10]}"),
    )
    env.pop("NUMBA_CACHE_DIR", None)
    command = [sys.executable, "-m", "snakemake", "-j2", target]
    for path in configfiles:
        command += ["--configfile", path]
    log = clone / "study_time.log"
    start = time.perf_counter()
    with open(log, "w") as out:
        status = subprocess.run(
            command, cwd=clone, env=env, stdout=out, stderr=subprocess.STDOUT
        ).returncode
    wall = time.perf_counter() - start
    jobs = sum(
        1
        for line in log.read_text(errors="replace").splitlines()
        if line.startswith("Finished job")
    )
    return {"wall_seconds": round(wall, 1), "exit_status": status, "jobs": jobs}


def main(argv=None) -> int:
    parser = options.parser("python -m benchmarks.study_time", __doc__)
    parser.add_argument(
        "--parent",
        default="HEAD~1",
        help="the commit to compare against (default HEAD~1), or none: this commit alone",
    )
    parser.add_argument(
        "--target",
        default="all",
        choices=("all", "fragility"),
        help="the Snakemake target: all (the study, default) or fragility (the IDA)",
    )
    parser.add_argument(
        "--configfile",
        action="append",
        default=[],
        help="extra config files, as snakemake takes them",
    )
    parser.add_argument(
        "--out", type=options.path_arg, default=ROOT / "results/bench/study_time.csv"
    )
    parser.add_argument(
        "--out-clones",
        type=options.path_arg,
        default=None,
        help="clone into this new folder and keep it (its results/ to compare); default: a "
        "temporary one",
    )
    args = parser.parse_args(argv)

    def command():
        path = options.output_file(args.out, "--out", suffixes=(".csv",))
        if args.out_clones is not None:
            check_output_path(args.out_clones, "--out-clones")  # writable, creates nothing
            if args.out_clones.exists():
                raise InputError(
                    "--out-clones",
                    f"{args.out_clones} exists",
                    "give a folder that does not exist yet",
                )
        for config in args.configfile:
            options.input_file(ROOT / config, "--configfile", "YAML config file")
        if args.configfile:  # read as the workflow reads it: a file it cannot take is refused here
            options.workflow_config(
                [ROOT / "config/config.yaml"] + [ROOT / c for c in args.configfile], "--configfile"
            )
        commits = {"current": commit_of("HEAD")}
        if args.parent.lower() != "none":
            commits["parent"] = commit_of(args.parent)
        config = " ".join(args.configfile) or "config/config.yaml"
        rows = [
            row
            for row in earlier_rows(path)
            if (row.get("target"), row.get("config")) != (args.target, config)
        ]
        with tempfile.TemporaryDirectory(prefix="stonedem-study-time-") as tmp:
            if args.out_clones is not None:
                args.out_clones.mkdir(parents=True)
                tmp = args.out_clones
            for version, commit in commits.items():
                print(
                    f"{version} {commit[:10]}: snakemake -j2 {args.target} ...",
                    file=sys.stderr,
                    flush=True,
                )
                timing = run_target(commit, args.target, args.configfile, Path(tmp))
                print(
                    f"  {timing['wall_seconds']:.0f} s, exit {timing['exit_status']}, "
                    f"{timing['jobs']} jobs",
                    file=sys.stderr,
                    flush=True,
                )
                rows.append(
                    {
                        "target": args.target,
                        "config": config,
                        "version": version,
                        "commit": commit[:10],
                        **timing,
                        "machine": f"{os.cpu_count()} cores",
                    }
                )
        new = rows[-len(commits) :]
        options.write_csv(path, rows, fieldnames=FIELDS)
        line = f"{args.target}: {new[0]['wall_seconds']:.0f} s"
        if len(new) == 2:
            line += (
                f", parent {new[1]['wall_seconds']:.0f} s "
                f"(x{new[1]['wall_seconds'] / new[0]['wall_seconds']:.2f})"
            )
        print(f"{line}; wrote {path}")
        return 0 if all(row["exit_status"] == 0 for row in new) else 1

    return options.run(command)


if __name__ == "__main__":
    sys.exit(main())
