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


import dem.figures
import dem.study

FIGURE_NAMES = list(dem.figures.FIGURES)

STUDIES = {
    name: {case.id: case for case in dem.study.case_table(name, spec, config.get("defaults"))}
    for name, spec in config["studies"].items()
}


wildcard_constraints:
    study="|".join(STUDIES),
    figure="|".join(dem.figures.FIGURES),
    case="[A-Za-z0-9_.+-]+",


def case_files(wildcards):
    return [f"results/cases/{wildcards.study}/{case}.nc" for case in STUDIES[wildcards.study]]


# colonnade studies that vary one parameter at a time (thesis 7.3-7.8)
EPISTYLE_STUDIES = [s for s in STUDIES if s.startswith("colonnade_") and s != "colonnade_records"]


def case_record(wildcards):
    case = STUDIES[wildcards.study][wildcards.case]
    record = case.params.get("record") or case.scene.get("excitation", {}).get("file")
    return [f"records/{record}.nc"] if record else []


def case_of(wildcards):
    case = STUDIES[wildcards.study][wildcards.case]
    return {"study": case.study, "id": case.id, "params": case.params, "scene": case.scene}



def figure_input(wildcards):
    return dem.figures.FIGURES[wildcards.figure][1]
