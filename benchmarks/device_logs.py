"""The ensemble throughput printed on a lent GPU, as one table
(benchmarks/device/<run>/ensemble.csv).

The device's runs were cut off by their time limits before the benchmark wrote its dataset,
so what they measured is in the lines it printed as it went (``ensemble_run*.txt``, kept as
printed). This reads those lines back; the settings of each section are the run's own, from
the folder's README.

    python -m benchmarks.device_logs [--folder benchmarks/device/h100-2026-11-27]
"""

import re
import sys
from pathlib import Path

# run as a file (python benchmarks/x.py) as well as a module (python -m benchmarks.x)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import options

LINE = re.compile(r"^\s+(\S+)\s+(\d+) members\s+(\S+) member-steps/s\s+(\S+) ns each$")
# (log, the section's marker or None for the whole log): layout, NVVM contraction, members per block
SECTIONS = {
    ("ensemble_run1.txt", None): ("per member (C order)", "fused", 64),
    ("ensemble_run2.txt", "ens64"): ("member index fastest (F order)", "two roundings", 64),
    ("ensemble_run2.txt", "ens32"): ("member index fastest (F order)", "two roundings", 32),
}
# rows whose timing is known to hold something else (the folder's README says how it is known)
NOTES = {
    (
        "ensemble_run2.txt",
        "ens64",
        "gpu",
        256,
    ): "includes a kernel compile (a one-member warm-up was typed C-ordered)"
}
COLUMNS = [
    "log",
    "layout",
    "multiply_add",
    "threads_per_block",
    "backend",
    "members",
    "member_steps_per_s",
    "ns_per_member_step",
    "note",
]


def rows(folder: Path) -> list[dict]:
    out = []
    for (log, marker), (layout, fma, block) in SECTIONS.items():
        section = None
        for line in (folder / log).read_text().splitlines():
            if line.startswith("["):  # "[169 s] ens32": a new section
                section = line.split()[-1]
                continue
            match = LINE.match(line)
            if match and (marker is None or section == marker):
                backend, members, rate, ns = match.groups()
                note = NOTES.get((log, marker, backend, int(members)), "")
                out.append(
                    dict(
                        zip(
                            COLUMNS,
                            (
                                log,
                                layout,
                                fma if backend == "gpu" else "",
                                block if backend == "gpu" else "",
                                backend,
                                int(members),
                                float(rate),
                                float(ns),
                                note,
                            ),
                        )
                    )
                )
    return out


def build_parser():
    parser = options.parser("python -m benchmarks.device_logs", __doc__)
    parser.add_argument(
        "--folder",
        type=options.path_arg,
        default=Path("benchmarks/device/h100-2026-11-27"),
        help="a run's folder of benchmarks/device (it gets ensemble.csv)",
    )
    return parser


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)

    def command():
        for log in sorted({log for log, _ in SECTIONS}):
            options.input_file(args.folder / log, "--folder", f"folder holding {log}")
        path = options.output_file(args.folder / "ensemble.csv", "--folder", suffixes=(".csv",))
        table = rows(args.folder)
        options.write_csv(path, table)
        print(f"wrote {path}: {len(table)} rows")
        return 0

    return options.run(command)


if __name__ == "__main__":
    sys.exit(main())
