"""The ensemble throughput printed on a lent GPU, as one table (benchmarks/device/<run>/ensemble.csv).

The device's runs were cut off by their time limits before the benchmark wrote its dataset,
so what they measured is in the lines it printed as it went (``ensemble_run*.txt``, kept as
printed). This reads those lines back; the settings of each section are the run's own, from
the folder's README.

    python benchmarks/device_logs.py [benchmarks/device/h100-2026-11-27]
"""

import csv
import re
import sys
from pathlib import Path

LINE = re.compile(r"^\s+(\S+)\s+(\d+) members\s+(\S+) member-steps/s\s+(\S+) ns each$")
# (log, the section's marker or None for the whole log): layout, NVVM contraction, members per block
SECTIONS = {
    ("ensemble_run1.txt", None): ("per member (C order)", "fused", 64),
    ("ensemble_run2.txt", "ens64"): ("member index fastest (F order)", "two roundings", 64),
    ("ensemble_run2.txt", "ens32"): ("member index fastest (F order)", "two roundings", 32),
}
COLUMNS = ["log", "layout", "multiply_add", "threads_per_block", "backend", "members", "member_steps_per_s",
           "ns_per_member_step"]


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
                out.append(dict(zip(COLUMNS, (log, layout, fma if backend == "gpu" else "", block if backend == "gpu" else "",
                                              backend, int(members), float(rate), float(ns)))))
    return out


def main(argv: list[str]) -> int:
    folder = Path(argv[0] if argv else "benchmarks/device/h100-2026-11-27")
    if not (folder / "ensemble_run1.txt").is_file():
        print(f"error: {folder}: no ensemble_run1.txt there; give a folder of benchmarks/device", file=sys.stderr)
        return 2
    table = rows(folder)
    path = folder / "ensemble.csv"
    tmp = path.with_suffix(".csv.tmp")
    with tmp.open("w", newline="") as f:
        writer = csv.DictWriter(f, COLUMNS)
        writer.writeheader()
        writer.writerows(table)
    tmp.replace(path)
    print(f"wrote {path}: {len(table)} rows")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
