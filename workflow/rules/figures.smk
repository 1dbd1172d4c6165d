rule plot_figure:
    input:
        figure_input,
    output:
        report(
            "results/figures/{figure}.png",
            caption="../report/figure.rst",
            category="Thesis figures",
            labels={"figure": "{figure}"},
        ),
    params:
        caption=figure_caption,
    log:
        "results/logs/figures/{figure}.log",
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/plot_figure.py"
