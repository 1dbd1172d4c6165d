"""Snakemake script: a catalogue table's input cubes -> its CSV (dem.figures.tables)."""

import sys

from dem.figures import tables

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
tables()[snakemake.wildcards.table].write(list(snakemake.input), snakemake.output[0])  # noqa: F821
