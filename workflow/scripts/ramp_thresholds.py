"""Snakemake script: ramp cubes -> PGA to initiate rocking and to overturn (thesis Fig. 6.10, 6.13)."""

import sys

import xarray as xr

from dem.reduce import ramp_thresholds, write_csv

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
for key, along in (("drums", "n_drums"), ("taper", "taper")):
    with xr.open_dataset(snakemake.input[key]) as cube:  # noqa: F821
        write_csv(ramp_thresholds(cube.load(), along), snakemake.output[key])  # noqa: F821
