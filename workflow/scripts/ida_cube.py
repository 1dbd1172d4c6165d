"""Snakemake script: the fragility searches -> the IDA cube (stonedem.fragility.ida.ida_cube)."""

import sys

from stonedem.entry import workflow_log
from stonedem.fragility.ida import ida_cube
from stonedem.io.netcdf import write_dataset

workflow_log(snakemake.log[0])
cube = ida_cube(list(snakemake.input), snakemake.params.structures, snakemake.params.suites)
write_dataset(cube, snakemake.output[0])
print(
    f"{cube.sizes['structure']} structures x {cube.sizes['record']} records, "
    f"{cube.attrs['n_simulations']} simulations",
    file=sys.stderr,
)
