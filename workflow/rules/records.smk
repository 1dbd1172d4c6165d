# records/ is committed and is what the study reads: the rule that made it is switched on
# only on request, so a fresh clone never tries to rebuild it (that needs the optional
# extra: pip install -e '.[records]'):
#   snakemake -j1 --config extract_records=true --forcerun extract_record
if EXTRACT_RECORDS:

    rule extract_record:
        output:
            "records/{name}.nc",
        params:
            record=record_params,
        log:
            "results/logs/records/{name}.log",
        conda:
            "../envs/dem.yaml"
        script:
            "../scripts/extract_record.py"
