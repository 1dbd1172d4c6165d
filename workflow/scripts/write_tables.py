"""Snakemake script: a batch of catalogue tables' input cubes -> their CSVs (stonedem.figures.tables)."""

import sys

from stonedem.entry import workflow_log

from stonedem.figures import tables

workflow_log(snakemake.log[0])  # noqa: F821 - provided by Snakemake
catalogue = tables()
for (name, inputs), output in zip(snakemake.params.tables.items(), snakemake.output):  # noqa: F821
    catalogue[name].write(list(inputs), output)
