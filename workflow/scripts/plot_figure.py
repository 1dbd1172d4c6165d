"""Snakemake script: inputs -> one figure (dem.figures.figure_table)."""

import sys

from dem.figures import figure_table
from dem.study import case_table

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
config = snakemake.config  # noqa: F821
studies = {name: {c.id: c for c in case_table(name, spec, config.get("defaults"))}
           for name, spec in config["studies"].items()}
figure = figure_table(studies, config)[snakemake.wildcards.figure]  # noqa: F821
figure.draw(list(snakemake.input), snakemake.output[0])  # noqa: F821
