rule plot_figure:
    input:
        figure_input,
    output:
        "results/figures/{figure}.png",
    log:
        "results/logs/figures/{figure}.log",
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/plot_figure.py"
