from snakemake.utils import validate


validate(config, schema="../schemas/config.schema.yaml")

RECORDS = config["records"]
# --config extract_records=true arrives as a string
EXTRACT_RECORDS = str(config.get("extract_records", False)).lower() == "true"
RECORD_NAMES = list(RECORDS)


wildcard_constraints:
    name="|".join(RECORD_NAMES),


def record_params(wildcards):
    return RECORDS[wildcards.name]
