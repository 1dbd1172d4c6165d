"""Snakemake script: fragility curves per structure and the medians / pulse figure
(stonedem.figures.fragility)."""

import sys

import xarray as xr

from stonedem.figures.fragility import fragility_curves_figure, medians_figure

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
inputs, params = snakemake.input, snakemake.params  # noqa: F821
with xr.open_dataset(inputs.cube) as cube, xr.open_dataset(inputs.fits) as fits:
    cube, fits = cube.load(), fits.load()
pulse = None
if inputs.pulse:
    with xr.open_dataset(inputs.pulse[0]) as pulse:
        pulse = pulse.load()
for structure, path in zip(params.structures, snakemake.output.curves):  # noqa: F821
    fragility_curves_figure(cube, fits, structure, path)
medians_figure(fits, pulse, snakemake.output.medians)  # noqa: F821
