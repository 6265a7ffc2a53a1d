#!/usr/bin/env bash
# The GPU checks in one call, each under its own time limit, for a machine lent for minutes:
#   1. the validation tests on the GPU (INTRUSIM_TI_ARCH): restarts bit for bit with the 64-bit
#      fixed-point atomic sums, and every physical check of tests/validation;
#   2. bench_mpm.py on the GPU: the step from 64k to 4M points, fixed-point against float atomics,
#      and the paper's wheel with its dynamics on the device against on the host, in the same run;
#   3. gpu_check.py: the paper's wheel on the CPU and on the GPU from the same state.
# Each writes its output to OUT_DIR (default: ./gpu_checks) as it goes, so a check cut short by its
# limit still leaves what it printed. About 9 min in all on an H200 at the default limits.
#
#   bash benchmarks/gpu_checks.sh [OUT_DIR] [ARCH]     # ARCH: cuda (default), vulkan, metal
set -u
out=${1:-gpu_checks}
arch=${2:-cuda}
py=${PYTHON:-python}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
{
  date -u
  nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv 2>/dev/null || echo "no nvidia-smi"
  "$py" -c "import sys, numpy, taichi; print(sys.version.split()[0], 'numpy', numpy.__version__, 'taichi', taichi.__version__)"
  git -C "$here" rev-parse --short HEAD 2>/dev/null
} >"$out/machine.txt" 2>&1
cat "$out/machine.txt"

run() {  # name, limit (s), command...
  local name=$1 limit=$2
  shift 2
  local t0=$SECONDS
  timeout "$limit" "$@" >"$out/$name.txt" 2>&1
  local rc=$?
  echo "$name: exit $rc after $((SECONDS - t0)) s (limit $limit s)" | tee -a "$out/summary.txt"
  tail -n 25 "$out/$name.txt"
}

cd "$here" || exit 1
run validation 240 env INTRUSIM_TI_ARCH="$arch" "$py" -m pytest -q -p no:cacheprovider tests/validation
run bench_mpm 200 "$py" benchmarks/bench_mpm.py --arch "$arch" --threads all --no-numpy --cases 64k,160k,1M,4M --wheel
run gpu_check 120 "$py" benchmarks/gpu_check.py --arch "$arch" --t-end 0.2 --json "$out/gpu_check.json"
cat "$out/summary.txt"
