"""Snakemake script: a colonnade study cube -> epistyle displacement per case (thesis 7.3-7.8)."""

import sys

import xarray as xr

from dem.reduce import epistyle_response, write_csv

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
with xr.open_dataset(snakemake.input[0]) as cube:  # noqa: F821
    write_csv(epistyle_response(cube.load()), snakemake.output[0])  # noqa: F821
