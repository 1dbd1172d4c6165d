"""Snakemake script: a batch of catalogue tables' input cubes -> their CSVs
(stonedem.figures.tables)."""

from stonedem.entry import workflow_log
from stonedem.figures import tables

workflow_log(snakemake.log[0])
catalogue = tables()
for (name, inputs), output in zip(snakemake.params.tables.items(), snakemake.output):
    catalogue[name].write(list(inputs), output)
