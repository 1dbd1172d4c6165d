"""Snakemake script: wall datasets -> every selected manuscript figure (damage maps, pushover
curves; stonedem.wall.figures.plot_from_files), one log line each."""

import sys

from stonedem.entry import logged_seconds, workflow_log
from stonedem.wall.figures import plot_from_files

sm = snakemake
workflow_log(sm.log[0])
for (number, figure), output in zip(sm.params.figures.items(), sm.output):
    with logged_seconds(sys.stderr, f"manuscript Fig. {number}"):
        plot_from_files(figure["inputs"], output, kind=figure["kind"])
