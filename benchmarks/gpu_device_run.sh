#!/usr/bin/env bash
# The device checks of issue 33 in one script, sized for a session lent a GPU (15 minutes of
# device time, starts included):
#   1. the full IDA on the GPU (`snakemake fragility --config device=gpu`), timed from cold
#      caches: compile included;
#   2. the GPU against the CPU ensemble and the engine (benchmarks.gpu_check);
#   3. throughput against members (benchmarks.ensemble).
#
#   bash benchmarks/gpu_device_run.sh          # writes under $OUT (default results/device)
#
# The device machine reaches no network. Its image has numba and numba-cuda; what the project
# needs beside them (snakemake, netCDF4 and their dependencies) is installed from wheels
# carried in .whl (docs/method/engine.md, "Many runs at once"), only when missing.
set -uo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-results/device}
mkdir -p "$OUT"
export PYTHONUNBUFFERED=1
t0=$(date +%s)
stamp() { echo "[$(($(date +%s) - t0)) s] $*"; }
{ nvidia-smi -L; echo "cores: $(nproc)"; python3 --version; } 2>&1 | tee "$OUT/device.txt"
if [ -d .whl ] && ! python3 -c "import snakemake, netCDF4" 2>/dev/null; then
    python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl 2>&1 | tail -3
    export PYTHONPATH=/tmp/site
fi
export PYTHONPATH=$PWD/src${PYTHONPATH:+:$PYTHONPATH}
python3 -c "import numpy, numba, numba_cuda, snakemake, netCDF4, xarray; print('numpy', numpy.__version__, 'numba', numba.__version__, 'numba-cuda', numba_cuda.__version__, 'snakemake', snakemake.__version__, 'xarray', xarray.__version__)" 2>&1 \
    | tee -a "$OUT/device.txt"
python3 -c "from stonedem.kernels.gpu import gpu_available; print(gpu_available())" 2>&1 | tee -a "$OUT/device.txt"

stamp "1. full IDA on the GPU, cold caches"
start=$(date +%s)
timeout "${IDA_SECONDS:-300}" python3 -m snakemake fragility --cores "$(nproc)" --config device=gpu >"$OUT/ida_gpu.log" 2>&1
code=$?
echo "full IDA, device=gpu: exit $code, $(($(date +%s) - start)) s wall" | tee "$OUT/ida_gpu.txt"
tail -5 "$OUT/ida_gpu.log"
grep -h "device\|finished\|searches" results/logs/jobs/search_ida_*.log 2>/dev/null | tail -12

stamp "2. GPU against CPU (gpu_check)"
timeout "${CHECK_SECONDS:-150}" python3 -m benchmarks.gpu_check --records "${CHECK_RECORDS:-20}" --out "$OUT" 2>&1 \
    | tee "$OUT/gpu_check.txt"

stamp "3. throughput against members"
timeout "${ENSEMBLE_SECONDS:-100}" python3 -m benchmarks.ensemble --out "$OUT" --figure "$OUT/ensemble_throughput.png" 2>&1 \
    | tee "$OUT/ensemble.txt"
stamp "done"
# at most 8 files come back: the small ones above, and one archive of the IDA's outputs and logs
tar czf "$OUT/ida_gpu.tar.gz" results/fragility results/tables/fragility*.csv results/logs/jobs results/logs/fragility \
    2>/dev/null || true
ls -la "$OUT"
