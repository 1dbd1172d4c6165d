"""The benchmarks' command lines: :mod:`stonedem.options` (every option and output path checked
before anything runs) and :mod:`stonedem.study.config_options` (a study config on the command
line), under the name the benchmark modules and scripts import."""

from stonedem.options import (
    chosen,
    input_file,
    number,
    output_file,
    output_folder,
    parser,
    path_arg,
    read_netcdf,
    run,
    save_figure,
    write_csv,
    write_text,
)
from stonedem.study.config_options import (
    add_study_arguments,
    check_case_scenes,
    chosen_cases,
    study_config,
    workflow_config,
)

__all__ = [
    "chosen",
    "input_file",
    "number",
    "output_file",
    "output_folder",
    "parser",
    "path_arg",
    "read_netcdf",
    "run",
    "save_figure",
    "write_csv",
    "write_text",
    "add_study_arguments",
    "check_case_scenes",
    "chosen_cases",
    "study_config",
    "workflow_config",
]
