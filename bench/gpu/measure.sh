#!/usr/bin/env bash
# Runs on the GPU machine (docs/gpu.md): the unit and validation tests and the benchmarks of a
# bundle made by bench/gpu/bundle.sh, with the CUDA build ("cuda") and, beside it, the OpenMP
# build ("omp") on the same machine's cores. Writes logs, gtest XML and benchmark JSON to OUT.
#   usage: measure.sh BUNDLE.tar.xz OUT [STAGES]
#   STAGES: any of machine tests sanitizer kernels kernels-large team newton newton-large
#           operators search cube mixed3d
# Sizes: CUBE_SIZES (default 100; also CUBE_KEYS, CUBE_VARIANTS, CUBE_TIMEOUT),
# NEWTON_LARGE_N (the 2D mixed step, default 2000; its builds:
# NEWTON_LARGE_VARIANTS, default cuda),
# MIXED3D_RUNS (element:N pairs of the 3D mixed Newton increment, default hex8:48).
# DEADLINE (seconds since the epoch), if set, cuts every run's time limit to end before it.
# Each mixcon run is timed by the bundle's GNU time (peak host memory), with the GPU's memory in
# use sampled every 0.2 s (nvidia-smi) beside it: OUT/NAME.gpumem, its largest value in MiB.
set -u
bundle=$1; out=$2; stages=${3:-machine tests kernels kernels-large newton operators search cube}
dir=/tmp/mixcon-bundle
mkdir -p "$dir" "$out"
[ -f "$dir/env.sh" ] || tar -xJf "$bundle" -C "$dir" 2>/dev/null ||
  python3 -m tarfile -e "$bundle" "$dir"
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
  if [ -n "${DEADLINE:-}" ]; then # a whole session's end (seconds since the epoch): stop before it
    local rest=$(( DEADLINE - $(date +%s) ))
    [ "$rest" -lt "$t" ] && t=$(( rest > 1 ? rest : 1 ))
  fi
  ( source "$dir/env.sh" "$v"; cd /tmp && timeout "$t" "$@" ) > "$out/$n.log" 2>&1
  echo "$n: rc=$? $(tail -1 "$out/$n.log" | cut -c1-150)"
}
timed_run() { # variant name timeout command...: run, with wall time, peak host and GPU memory
  local n=$2 start
  nvidia-smi --query-gpu=memory.used --format=csv,noheader,nounits -lms 200 > "$out/$n.gpumem" \
    2>/dev/null &
  local sampler=$!
  start=$(date +%s%N)
  run "$1" "$n" "$3" "$dir/sys/bin/time" -v "${@:4}"
  kill $sampler 2>/dev/null
  echo "wall_ms $(( ($(date +%s%N) - start) / 1000000 ))" >> "$out/$n.log"
  echo "$n: wall $(tail -1 "$out/$n.log" | cut -d' ' -f2) ms, peak host" \
    "$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$out/$n.log") kB, peak GPU" \
    "$(sort -n "$out/$n.gpumem" | tail -1) MiB"
}
cube_yaml() { # N FILE [SOLVER_KEYS]: bench/cube_hex8.py's problem, extra solver keys (e.g.
  # "amg_cycle: hypre") appended to its solver line
  cat > "$2" <<YAML
title: unit cube $1^3 Hex8 (bench/cube_hex8.py)
mesh:
  generator: {type: box, size: [1, 1, 1], divisions: [$1, $1, $1]}
materials:
  - {region: body, type: isotropic, E: 1.0, nu: 0.3}
boundary_conditions:
  - {boundary: xmin, ux: 0, uy: 0, uz: 0}
loads:
  - {boundary: xmax, traction: [0, -1e-3, 0]}
solver: {type: amg, tolerance: 1e-8${3:+, $3}}
output: {directory: $(dirname "$2")/out, hdf5: false}
YAML
}
mixed3d_yaml() { # ELEMENT N FILE: bench/mixed3d_newton.py's problem and its default solver keys
  cat > "$3" <<YAML
title: One Newton increment of the 3D mixed model, cube $2^3 $1 (bench/mixed3d_newton.py)
mesh:
  generator: {type: box, size: [1, 1, 1], divisions: [$2, $2, $2], element: $1}
model: {formulation: mixed, geometric_nonlinearity: true, stabilization: 0.05}
materials:
  - {region: body, type: isotropic, E: 1000, nu: 0.3}
boundary_conditions:
  - {boundary: xmin, ux: 0, uy: 0, uz: 0}
loads:
  - {boundary: xmax, traction: [0, 0, -20]}
steps: {increments: 1}
solver: {type: amg, aggressive_levels: 1, interpolation_max_elements: 4}
output: {directory: $(dirname "$3")/out, hdf5: false}
YAML
}
bench() { # variant name timeout program filter [args]; BENCH_RUN=timed_run: with peak memory
  local v=$1 n=$2 t=$3 p=$4 f=$5; shift 5
  ${BENCH_RUN:-run} "$v" "$n" "$t" "$p" --benchmark_filter="$f" --benchmark_out="$out/$n.json" \
    --benchmark_out_format=json --benchmark_min_time=0.2s "$@"
}
export OMP_PROC_BIND=spread OMP_PLACES=threads OMP_NUM_THREADS=$(nproc)
for s in $stages; do case $s in
machine)
  bench cuda machine-cuda 60 mixcon_bench_machine .
  bench omp machine-omp 60 mixcon_bench_machine . ;;
tests) # the two programs side by side (one GPU, 8 host threads each), their OpenMP threads
  # unbound and waiting passively: spinning threads of two programs on shared cores took one
  # validation test from 14 s to over 390 s here (as in CI, docs/performance.md). In a subshell:
  # the later stages keep the settings above.
  (
    export OMP_PROC_BIND=false OMP_WAIT_POLICY=passive OMP_NUM_THREADS=$(( $(nproc) / 2 ))
    # UNIT_SHARDS (default 1) unit-test programs side by side, each a gtest shard.
    shards=${UNIT_SHARDS:-1}
    export OMP_NUM_THREADS=$(( $(nproc) / (shards + 1) ))
    for ((k = 0; k < shards; ++k)); do
      GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$k run cuda unit-cuda-$k ${TEST_TIMEOUT:-420} \
        mixcon_unit_tests --gtest_output=xml:"$out/unit-cuda-$k.xml" &
    done
    run cuda validation-cuda ${TEST_TIMEOUT:-420} mixcon_validation_tests \
      --gtest_output=xml:"$out/validation-cuda.xml"
    wait
  ) ;;
team) # the two stiffness kernels side by side on the GPU: SIMD lanes (one element per thread
  # there) and one team per element, at the largest sizes (TEAM_FILTER)
  bench cuda team-cuda ${TEAM_TIMEOUT:-240} mixcon_bench_linear_stiffness \
    "${TEAM_FILTER:-(lanes|team)/nodes:(4|8)/n:(1024|96)|(lanes|team)/nodes:(20|10)/n:48|(lanes|team)/nodes:4/n:96}" ;;
sanitizer) # compute-sanitizer's memcheck and racecheck on the element-kernel tests
  san=$(command -v compute-sanitizer || ls /usr/local/cuda*/bin/compute-sanitizer 2>/dev/null | head -1)
  for tool in memcheck racecheck; do
    run cuda sanitizer-$tool ${SANITIZER_TIMEOUT:-150} "$san" --tool $tool --error-exitcode 3 \
      mixcon_unit_tests --gtest_filter="${SANITIZER_FILTER:-*ElementDriver*:*KernelTest*:Hex8*:SolidModel*:SolidLoads*:MixedMatrixFree*:SegmentSearch*:SolidMixedMatrixFree*:SolidNonlinear*:SolidReportTangent*:*TeamStiffness*}"
  done ;;
kernels)
  bench cuda kernels-cuda 240 mixcon_bench_linear_stiffness 'threads'
  bench omp kernels-omp 240 mixcon_bench_linear_stiffness 'threads' ;;
kernels-large) # the ~1e6-element sizes on the CPU too, for the side-by-side figure
  MIXCON_BENCH_FULL=1 bench omp kernels-large-omp 200 mixcon_bench_linear_stiffness \
    'elementMatrices/threads.*(n:1024|n:96|nodes:(20|10)/n:48)' ;;
newton) # one Newton step of the 2D mixed model on 1e6 Quad4 elements (MIXCON_BENCH_FULL)
  for v in cuda omp; do
    MIXCON_BENCH_FULL=1 bench $v newton-$v 200 mixcon_bench_nonlinear \
      'newtonStep/nodes:4/n:1000/a_percent:5/schur:0/'
  done ;;
newton-large) # the same step on the largest mesh of this run (NEWTON_LARGE_N), timed as a run
  # (peak host and GPU memory) in each of NEWTON_LARGE_VARIANTS (default: the GPU only)
  n=${NEWTON_LARGE_N:-2000}
  for v in ${NEWTON_LARGE_VARIANTS:-cuda}; do
    MIXCON_BENCH_NEWTON_N=$n MIXCON_BENCH_FULL=1 BENCH_RUN=timed_run bench $v newton-large-$n-$v \
      500 mixcon_bench_nonlinear "newtonStep/nodes:4/n:$n/a_percent:5/schur:0/"
  done ;;
operators) # the mixed Jacobian product: matrix-free against CSR SpMV, 1e5 elements
  for v in cuda omp; do
    bench $v operators-$v 120 mixcon_bench_mixed_jacobian 'JX/(matrixFree|csr)/nodes:./n:316'
  done ;;
search) # the node-to-segment grid: build and query, 1e6 and 1e7 segments
  for v in cuda omp; do
    bench $v search-$v 120 mixcon_bench_search 'grid(Build|Query)/(1000000|10000000)'
  done ;;
cube) # CUBE_KEYS: solver-key sets separated by ';' (default: one run with the defaults), each
  # run as cube<N>-<variant>-k<index> (index 0: the defaults)
  IFS=';' read -ra keysets <<< "${CUBE_KEYS:-}"
  [ ${#keysets[@]} -eq 0 ] && keysets=("")
  for n in ${CUBE_SIZES:-100}; do
    for k in "${!keysets[@]}"; do
      mkdir -p /tmp/cube$n-k$k && cube_yaml $n /tmp/cube$n-k$k/cube.yaml "${keysets[$k]}"
      echo "cube$n-*-k$k: solver keys '${keysets[$k]}'"
      for v in ${CUBE_VARIANTS:-cuda omp}; do
        timed_run $v cube$n-$v-k$k ${CUBE_TIMEOUT:-400} mixcon run /tmp/cube$n-k$k/cube.yaml
      done
    done
  done ;;
mixed3d) # one Newton increment of the 3D mixed model
  for r in ${MIXED3D_RUNS:-hex8:48}; do
    e=${r%%:*} n=${r#*:}
    mkdir -p /tmp/m3d-$e-$n && mixed3d_yaml $e $n /tmp/m3d-$e-$n/problem.yaml
    for v in ${MIXED3D_VARIANTS:-cuda omp}; do
      timed_run $v mixed3d-$e-$n-$v 400 mixcon run /tmp/m3d-$e-$n/problem.yaml -v
    done
  done ;;
esac; done
