#!/usr/bin/env bash
# Runs on the GPU machine (docs/gpu.md): the unit and validation tests and the benchmarks of a
# bundle made by bench/gpu/bundle.sh, with the CUDA build ("cuda") and, beside it, the OpenMP
# build ("omp") on the same machine's cores. Writes logs, gtest XML and benchmark JSON to OUT.
#   usage: measure.sh BUNDLE.tar.xz OUT [STAGES]
#   STAGES: any of machine tests sanitizer kernels kernels-large newton operators search cube
set -u
bundle=$1; out=$2; stages=${3:-machine tests kernels kernels-large newton operators search cube}
dir=/tmp/mixcon-bundle
mkdir -p "$dir" "$out"
tar -xJf "$bundle" -C "$dir" 2>/dev/null || python3 -m tarfile -e "$bundle" "$dir"
# The tests read examples/ from the source tree the CUDA build was configured from
# (MIXCON_SOURCE_DIR) and run the program from its build folder: recreate both paths here, the
# sources as this copy of the repository (the current directory).
src=$(cat "$dir/cuda/source_dir") build=$(cat "$dir/cuda/build_dir")
[ -e "$src" ] || { mkdir -p "$(dirname "$src")" && ln -s "$PWD" "$src"; }
mkdir -p "$build/apps" && ln -sf "$dir/cuda/bin/mixcon" "$build/apps/mixcon"
{ nvidia-smi; nvidia-smi --query-gpu=name,clocks.max.sm,clocks.max.mem,memory.total --format=csv
  grep PRETTY /etc/os-release; ldd --version | head -1; nproc; free -g; } > "$out/machine.txt" 2>&1
run() { # variant name timeout command...
  local v=$1 n=$2 t=$3; shift 3
  ( source "$dir/env.sh" "$v"; cd /tmp && timeout "$t" "$@" ) > "$out/$n.log" 2>&1
  echo "$n: rc=$? $(tail -1 "$out/$n.log" | cut -c1-150)"
}
bench() { # variant name timeout program filter [args]
  local v=$1 n=$2 t=$3 p=$4 f=$5; shift 5
  run "$v" "$n" "$t" "$p" --benchmark_filter="$f" --benchmark_out="$out/$n.json" \
    --benchmark_out_format=json --benchmark_min_time=0.2s "$@"
}
export OMP_PROC_BIND=spread OMP_PLACES=threads OMP_NUM_THREADS=$(nproc)
for s in $stages; do case $s in
machine)
  bench cuda machine-cuda 60 mixcon_bench_machine .
  bench omp machine-omp 60 mixcon_bench_machine . ;;
tests)
  run cuda unit-cuda 420 mixcon_unit_tests --gtest_output=xml:"$out/unit-cuda.xml"
  run cuda validation-cuda 300 mixcon_validation_tests --gtest_output=xml:"$out/validation-cuda.xml" ;;
sanitizer) # compute-sanitizer's memcheck and racecheck on the element-kernel tests
  san=$(command -v compute-sanitizer || ls /usr/local/cuda*/bin/compute-sanitizer 2>/dev/null | head -1)
  for tool in memcheck racecheck; do
    run cuda sanitizer-$tool 150 "$san" --tool $tool --error-exitcode 3 mixcon_unit_tests \
      --gtest_filter='*ElementDriver*:*KernelTest*:Hex8*:SolidModel*:SolidLoads*:MixedMatrixFree*:SegmentSearch*'
  done ;;
kernels)
  bench cuda kernels-cuda 240 mixcon_bench_linear_stiffness 'threads'
  bench omp kernels-omp 240 mixcon_bench_linear_stiffness 'threads' ;;
kernels-large) # the ~1e6-element sizes on the CPU too, for the side-by-side figure
  MIXCON_BENCH_FULL=1 bench omp kernels-large-omp 200 mixcon_bench_linear_stiffness \
    'elementMatrices/threads.*(n:1024|n:96)' ;;
newton) # one Newton step of the 2D mixed model on 1e6 Quad4 elements (MIXCON_BENCH_FULL)
  for v in cuda omp; do
    MIXCON_BENCH_FULL=1 bench $v newton-$v 200 mixcon_bench_nonlinear \
      'newtonStep/nodes:4/n:1000/a_percent:5/schur:0/'
  done ;;
operators) # the mixed Jacobian product: matrix-free against CSR SpMV, 1e5 elements
  for v in cuda omp; do
    bench $v operators-$v 120 mixcon_bench_mixed_jacobian 'JX/(matrixFree|csr)/nodes:./n:316'
  done ;;
search) # the node-to-segment grid: build and query, 1e6 and 1e7 segments
  for v in cuda omp; do
    bench $v search-$v 120 mixcon_bench_search 'grid(Build|Query)/(1000000|10000000)'
  done ;;
cube)
  for n in ${CUBE_SIZES:-100}; do
    mkdir -p /tmp/cube$n
    cat > /tmp/cube$n/cube.yaml <<YAML
title: unit cube $n^3 Hex8 (bench/cube_hex8.py)
mesh:
  generator: {type: box, size: [1, 1, 1], divisions: [$n, $n, $n]}
materials:
  - {region: body, type: isotropic, E: 1.0, nu: 0.3}
boundary_conditions:
  - {boundary: xmin, ux: 0, uy: 0, uz: 0}
loads:
  - {boundary: xmax, traction: [0, -1e-3, 0]}
solver: {type: amg, tolerance: 1e-8}
output: {directory: /tmp/cube$n/out, hdf5: false}
YAML
    for v in cuda omp; do
      start=$(date +%s%N)
      run $v cube$n-$v 300 mixcon run /tmp/cube$n/cube.yaml
      echo "wall_ms $(( ($(date +%s%N) - start) / 1000000 ))" >> "$out/cube$n-$v.log"
    done
  done ;;
esac; done
