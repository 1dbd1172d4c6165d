"""Snakemake script: harmonic cube -> sliding and rocking vs frequency (thesis Fig. 6.1, 6.5, 6.6)."""

import sys

import xarray as xr

from dem.reduce import frequency_response, write_csv

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
with xr.open_dataset(snakemake.input[0]) as cube:  # noqa: F821
    write_csv(frequency_response(cube.load()), snakemake.output[0])  # noqa: F821
