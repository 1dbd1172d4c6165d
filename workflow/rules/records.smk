# records/ is committed and is what the study reads: the rule that made it is switched on
# only on request, so a fresh clone never tries to rebuild it (that needs the optional
# extra: pip install -e '.[records]'):
#   snakemake -j1 --config extract_records=true --forcerun extract_record extract_suite
if EXTRACT_RECORDS:

    # all 100 horizontal components of the FEMA P695 sets, one file per set (stonedem.motion.suites)
    rule extract_suite:
        output:
            "records/suites/{suite}.nc",
        log:
            "results/logs/records/suite_{suite}.log",
        wildcard_constraints:
            suite="far_field|near_field_pulse|near_field_no_pulse",
        conda:
            "../envs/stonedem.yaml"
        script:
            "../scripts/extract_suite.py"

    rule extract_record:
        output:
            "records/{name}.nc",
        log:
            "results/logs/records/{name}.log",
        conda:
            "../envs/stonedem.yaml"
        params:
            record=record_params,
        script:
            "../scripts/extract_record.py"
