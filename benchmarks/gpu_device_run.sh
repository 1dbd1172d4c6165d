#!/usr/bin/env bash
# The device checks of issue 33 in one script, sized for a session lent a GPU (15 minutes of
# device time, starts included): the GPU against the CPU (stonedem.bench.gpu_check), the
# throughput against members (stonedem.bench.ensemble) and the full IDA on the GPU, timed.
#
#   bash benchmarks/gpu_device_run.sh          # writes under $OUT (default results/device)
#
# numba-cuda and its compiler (NVVM) must be importable there: the device machine reaches no
# network, so they are installed from a wheelhouse carried in shared/wheels when one is.
set -uo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-results/device}
mkdir -p "$OUT"
nvidia-smi -L 2>&1 | tee "$OUT/device.txt"
if ! python3 -c "import numba_cuda" 2>/dev/null; then
    python3 -m pip install -q --no-index --find-links shared/wheels -e '.[gpu]' 2>&1 | tail -1
fi
python3 -c "import numba_cuda, numba; print('numba', numba.__version__, 'numba-cuda', numba_cuda.__version__)" \
    | tee -a "$OUT/device.txt" || { echo "numba-cuda is not importable: nothing to check" >&2; exit 2; }
start=$(date +%s)
timeout 240 python3 -m stonedem.bench.gpu_check --records 20 --out "$OUT" 2>&1 | tee "$OUT/gpu_check.txt"
echo "gpu_check: $(( $(date +%s) - start )) s" | tee -a "$OUT/gpu_check.txt"
timeout 120 python3 -m stonedem.bench.ensemble --out "$OUT" --figure "$OUT/ensemble_throughput.png" 2>&1 \
    | tail -12 | tee "$OUT/ensemble.txt"
start=$(date +%s)
timeout 300 python3 -m snakemake fragility -j1 --config device=gpu > "$OUT/ida_gpu.log" 2>&1
echo "full IDA, device=gpu: exit $?, $(( $(date +%s) - start )) s" | tee "$OUT/ida_gpu.txt"
cp results/logs/jobs/search_ida_*.log "$OUT/" 2>/dev/null || true
