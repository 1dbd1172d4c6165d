"""Snakemake script: wall datasets -> every selected manuscript figure (damage maps, pushover
curves; dem.wall.figures.plot_from_files), one log line each."""

import sys
import time

from dem.entry import progress_print
from dem.wall.figures import plot_from_files

sm = snakemake  # noqa: F821 - provided by Snakemake
sys.stderr = open(sm.log[0], "w", buffering=1)
for (number, figure), output in zip(sm.params.figures.items(), sm.output):
    start = time.perf_counter()
    plot_from_files(figure["inputs"], output, kind=figure["kind"])
    progress_print(sys.stderr, f"manuscript Fig. {number}: {time.perf_counter() - start:.2f} s")
