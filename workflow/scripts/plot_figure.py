"""Snakemake script: a catalogue figure's input files -> its PNG (dem.figures.figures)."""

import sys

from dem.figures import figures

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
figures(snakemake.config)[snakemake.wildcards.figure].draw(list(snakemake.input), snakemake.output[0])  # noqa: F821
