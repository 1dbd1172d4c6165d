"""Snakemake script: study cubes -> thesis Table 7.1 as CSV (dem.reduce.table_7_1)."""

import sys

import xarray as xr

from dem.reduce import table_7_1, write_csv

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
with xr.open_dataset(snakemake.input.standalone) as s, xr.open_dataset(snakemake.input.colonnade) as c:  # noqa: F821
    write_csv(table_7_1(s.load(), c.load()), snakemake.output[0])  # noqa: F821
