"""Snakemake script: the IDA cube -> lognormal fits, their table, the physics checks
(stonedem.fragility.fit.fragility_dataset, stonedem.fragility.checks)."""

import sys

from stonedem.entry import workflow_log
from stonedem.fragility.checks import ordering_checks, pulse_check, pulse_rows
from stonedem.fragility.fit import fragility_dataset, fragility_table
from stonedem.io.atomic import write_csv
from stonedem.io.netcdf import open_result, write_dataset

workflow_log(snakemake.log[0])
params, output = snakemake.params, snakemake.output
cube = open_result(snakemake.input[0])
fits = fragility_dataset(cube, samples=params.bootstrap)
write_dataset(fits, output.fits)
write_csv(output.table, fragility_table(fits))
rows = ordering_checks(cube, fits, params.structures)
if params.pulse_structure:
    check = pulse_check(
        cube, params.pulse_structure, params.structures[params.pulse_structure]["structure"]
    )
    write_dataset(check, output.pulse[0])
    rows += pulse_rows(check)
write_csv(output.checks, rows)
for row in rows:
    print(f"{row['check']}: {row['subject']}: {row['measured']} -> {row['holds']}", file=sys.stderr)
