"""Snakemake script: a batch of catalogue figures -> their PNGs (dem.figures.figures), one log line each."""

import sys
import time

from dem.entry import progress_print
from dem.figures import figures

sys.stderr = open(snakemake.log[0], "w", buffering=1)  # noqa: F821 - provided by Snakemake
catalogue = figures(snakemake.config)  # noqa: F821
for (name, inputs), output in zip(snakemake.params.figures.items(), snakemake.output):  # noqa: F821
    start = time.perf_counter()
    catalogue[name].draw(list(inputs), output)
    progress_print(sys.stderr, f"{name}: {time.perf_counter() - start:.2f} s")
