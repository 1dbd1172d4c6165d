"""Snakemake script: fragility curves per structure, the medians / pulse figure and the
compared structures' curves (stonedem.figures.fragility)."""

from stonedem.entry import workflow_log
from stonedem.figures.fragility import (
    comparison_figure,
    fragility_curves_figure,
    medians_figure,
)
from stonedem.io.netcdf import open_result

workflow_log(snakemake.log[0])
inputs, params = snakemake.input, snakemake.params
with open_result(inputs.cube) as cube, open_result(inputs.fits) as fits:
    cube, fits = cube.load(), fits.load()
pulse = None
if inputs.pulse:
    with open_result(inputs.pulse[0]) as pulse:
        pulse = pulse.load()
for structure, path in zip(params.structures, snakemake.output.curves):
    fragility_curves_figure(cube, fits, structure, path)
medians_figure(fits, pulse, snakemake.output.medians)
for structures, path in zip(params.compared, snakemake.output.compared):
    comparison_figure(fits, structures, path)
