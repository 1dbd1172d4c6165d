"""Snakemake script: wall datasets -> damage maps or pushover curves (dem.wall.figures.plot_from_files)."""

import sys

from dem.wall.figures import plot_from_files

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
plot_from_files(snakemake.input, snakemake.output[0], kind=snakemake.params.kind)  # noqa: F821
