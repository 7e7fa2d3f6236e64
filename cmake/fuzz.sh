#!/usr/bin/env bash
# Bounded fuzzing of the input parsers (fuzz/README.md): builds the libFuzzer targets with clang in
# build-fuzz/ (ASan + UBSan), then runs each for a fixed time on a scratch copy of its seed corpus
# (fuzz/corpus plus the examples' problem files, meshes and measurement files). Fails, naming the
# reproducer, on any crash, sanitizer report, leak, timeout (-timeout=10 s per input) or input
# over -rss_limit_mb=2048.
# Usage: cmake/fuzz.sh [seconds-per-target]      (default 60; CI: bash cmake/fuzz.sh 60)
# Environment: Kokkos_ROOT (else cmake/build-kokkos.sh), MIXCON_FUZZ_BUILD_DIR, MIXCON_FUZZ_WORK
# (scratch folder, kept for inspection; default a fresh mktemp -d).
set -euo pipefail
seconds=${1:-60}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${MIXCON_FUZZ_BUILD_DIR:-$root/build-fuzz}

# clang and its runtime libraries (libFuzzer, ASan, UBSan; libomp for Kokkos' OpenMP headers).
bash "$root/cmake/install-deps.sh"
fuzz_packages=(clang libclang-rt-14-dev libomp-dev)
missing=()
for p in "${fuzz_packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  echo "mixcon fuzz: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -q
  $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
if [ -z "${Kokkos_ROOT:-}" ]; then
  Kokkos_ROOT=$(bash "$root/cmake/build-kokkos.sh" | tail -n 1)
fi

mkdir -p "$build"
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
  -DCMAKE_CXX_COMPILER=clang++ -DKokkos_ROOT="$Kokkos_ROOT" -DMIXCON_ENABLE_FUZZERS=ON \
  -DMIXCON_ENABLE_TESTS=OFF -DMIXCON_ENABLE_BENCHMARKS=OFF -DMIXCON_ENABLE_APPS=OFF \
  "${launcher[@]}" >"$build/configure.log" 2>&1 || {
  cat "$build/configure.log" >&2
  exit 1
}
targets=(problem gmsh measurements)
cmake --build "$build" -j "$(nproc)" --target "${targets[@]/#/mixcon_fuzz_}"

work=${MIXCON_FUZZ_WORK:-$(mktemp -d "${TMPDIR:-/tmp}/mixcon-fuzz.XXXXXX")}
mkdir -p "$work"
# Seeds: the committed corpus and the examples. Problem files lose their comments and every '/'
# (the target skips inputs holding one: paths stay inside its scratch folder).
for t in "${targets[@]}"; do
  mkdir -p "$work/$t/corpus" "$work/$t/artifacts"
  cp "$root/fuzz/corpus/$t"/* "$work/$t/corpus/"
done
while IFS= read -r f; do
  name=$(echo "${f#"$root"/examples/}" | tr / _)
  grep -v '^[[:space:]]*#' "$f" | sed 's|/|_|g' >"$work/problem/corpus/$name"
done < <(find "$root/examples" -name '*.yaml')
find "$root/examples" -name '*.msh' -exec cp {} "$work/gmsh/corpus/" \;
find "$root/examples" -name '*.csv' -exec cp {} "$work/measurements/corpus/" \;

# MPI and hypre are linked but never started; leaks in the parsers are reported.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1
export OMP_NUM_THREADS=1
# A fixed seed by default, so that a CI run repeats the exploration of the runs checked before it
# landed (MIXCON_FUZZ_SEED=0: a new random seed, for longer exploratory runs).
seed=${MIXCON_FUZZ_SEED:-1}
status=0
for t in "${targets[@]}"; do
  extra=()
  if [ -f "$root/fuzz/$t.dict" ]; then extra=(-dict="$root/fuzz/$t.dict"); fi
  echo "mixcon fuzz: $t for ${seconds} s (log: $work/$t/log.txt)"
  if (cd "$work/$t" && "$build/fuzz/mixcon_fuzz_$t" corpus "${extra[@]}" \
    -max_total_time="$seconds" -seed="$seed" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$work/$t/artifacts/" >log.txt 2>&1); then
    grep -E '^stat::(number_of_executed_units|new_units_added)' "$work/$t/log.txt" | sed 's/^/  /'
  else
    status=1
    echo "mixcon fuzz: $t FAILED; the end of its log:" >&2
    tail -n 60 "$work/$t/log.txt" >&2
    for a in "$work/$t/artifacts"/*; do
      [ -e "$a" ] && echo "mixcon fuzz: reproducer $a (run: $build/fuzz/mixcon_fuzz_$t $a)" >&2
    done
  fi
done
if [ $status -eq 0 ]; then
  echo "mixcon fuzz: no crash, sanitizer report, leak or timeout"
  [ -n "${MIXCON_FUZZ_WORK:-}" ] || rm -rf "$work"
fi
exit $status
