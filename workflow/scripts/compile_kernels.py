"""Snakemake script: one of the engine's compiled time loops compiled (or loaded from Numba's cache)
before the jobs that run the engine start (stonedem.engine.run.warm_compile); writes the marker they
wait for."""

import time

import numba

from stonedem.engine.run import warm_compile
from stonedem.entry import workflow_log
from stonedem.io.atomic import write_text

log = workflow_log(snakemake.log[0])
start = time.perf_counter()
loop = snakemake.wildcards.loop
seconds = warm_compile([loop])[loop]
text = (
    f"{loop}: {seconds:.1f} s compile, {time.perf_counter() - start:.1f} s in all; "
    f"cache {numba.config.CACHE_DIR}\n"
)
print(text, end="", file=log)
write_text(snakemake.output[0], text)
