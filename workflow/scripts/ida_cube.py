"""Snakemake script: the fragility searches -> the IDA cube (stonedem.fragility.ida.ida_cube)."""

import sys

from stonedem.entry import workflow_log

from stonedem.io.netcdf import write_dataset
from stonedem.fragility.ida import ida_cube

workflow_log(snakemake.log[0])  # noqa: F821 - provided by Snakemake
cube = ida_cube(list(snakemake.input), snakemake.params.structures, snakemake.params.suites)  # noqa: F821
write_dataset(cube, snakemake.output[0])  # noqa: F821
print(f"{cube.sizes['structure']} structures x {cube.sizes['record']} records, "
      f"{cube.attrs['n_simulations']} simulations", file=sys.stderr)
