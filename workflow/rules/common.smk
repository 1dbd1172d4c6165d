from snakemake.utils import validate


validate(config, schema="../schemas/config.schema.yaml")

RECORDS = config["records"]
RECORD_NAMES = list(RECORDS)


wildcard_constraints:
    name="|".join(RECORD_NAMES),


def record_params(wildcards):
    return RECORDS[wildcards.name]
