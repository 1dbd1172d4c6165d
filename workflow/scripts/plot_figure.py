"""Snakemake script: inputs -> one figure (dem.figures.FIGURES)."""

import sys

from dem.figures import FIGURES

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
draw, _ = FIGURES[snakemake.wildcards.figure]  # noqa: F821
draw(snakemake.input[0], snakemake.output[0])  # noqa: F821
