"""Snakemake script: one FEMA P695 record -> records/<name>.nc (stonedem.motion.fema_p695)."""

from stonedem.entry import workflow_log
from stonedem.io.netcdf import write_dataset
from stonedem.motion.fema_p695 import extract_record

workflow_log(snakemake.log[0])
spec = dict(snakemake.params.record)
ds = extract_record(
    spec.pop("set"),
    spec.pop("id"),
    spec.pop("component"),
    name=snakemake.wildcards.name,
    extra_attrs=spec,
)
write_dataset(ds, snakemake.output[0])
