"""Snakemake script: a batch of catalogue figures -> their PNGs (stonedem.figures.figures), one log
line each."""

import sys

from stonedem.entry import logged_seconds, workflow_log
from stonedem.figures import figures

workflow_log(snakemake.log[0])
catalogue = figures(snakemake.config)
for (name, inputs), output in zip(snakemake.params.figures.items(), snakemake.output):
    with logged_seconds(sys.stderr, name):
        catalogue[name].draw(list(inputs), output)
