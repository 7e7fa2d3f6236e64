#!/usr/bin/env bash
# One entry point for the README's quick start and for CI, on a fresh Debian 12 machine:
# installs missing Debian packages, builds Kokkos (OpenMP + Serial) into a cache if no
# Kokkos_ROOT is given, builds a threaded hypre (OpenMP, from Debian's hypre 2.26 source package,
# cmake/build-hypre.sh, about 2 minutes on 2 cores) into the same cache unless told otherwise,
# configures and builds mixcon against them, then:
#   example   runs the main example (Hertz contact) and prints its comparison with the closed form
#   test      runs the whole test suite (ctest: unit, validation, install test)
#   sanitize  Debug build with AddressSanitizer + UndefinedBehaviorSanitizer, runs the unit tests
#   bench     runs the Google Benchmark programs (results in build/bench/*.json)
# Environment: Kokkos_ROOT (use your own Kokkos, e.g. a CUDA build), MIXCON_BUILD_DIR,
# MIXCON_CACHE (where Kokkos and hypre are built), OMP_NUM_THREADS, and for hypre:
#   (nothing)            the threaded hypre of cmake/build-hypre.sh (the default)
#   HYPRE_ROOT=<prefix>  your own hypre (its HYPREConfig.cmake, or include/ and lib/)
#   MIXCON_HYPRE=debian  Debian's sequential libhypre-dev (the fallback)
# Whichever it is, the installed mixconConfig.cmake finds that same hypre, and the programs find
# libHYPRE through their RPATH (no LD_LIBRARY_PATH).
set -euo pipefail
mode=${1:-example}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
jobs=$(nproc)

bash "$root/cmake/install-deps.sh"
if [ -z "${Kokkos_ROOT:-}" ]; then
  Kokkos_ROOT=$(bash "$root/cmake/build-kokkos.sh" | tail -n 1)
fi
# hypre: forget a previous configure's choice (a cache entry would win over a changed
# HYPRE_ROOT), then pass the one asked for; Debian's is found in the system paths.
hypre_args=(-UHYPRE_DIR -UHYPRE_INCLUDE_DIR -UHYPRE_LIBRARY -UHYPRE_ROOT)
if [ "${MIXCON_HYPRE:-}" = debian ]; then
  echo "mixcon: Debian's sequential hypre (MIXCON_HYPRE=debian)"
  unset HYPRE_ROOT # CMake would search an exported HYPRE_ROOT first
elif [ -n "${MIXCON_HYPRE:-}" ]; then
  echo "mixcon: MIXCON_HYPRE='$MIXCON_HYPRE' is not 'debian' (unset it for the threaded hypre)" >&2
  exit 2
else
  if [ -z "${HYPRE_ROOT:-}" ]; then
    HYPRE_ROOT=$(bash "$root/cmake/build-hypre.sh" | tail -n 1)
  fi
  hypre_args+=(-DHYPRE_ROOT="$HYPRE_ROOT")
fi

build_targets=() # empty: all; else the targets to build (sanitize: the unit tests only)
configure_and_build() { # build-dir, extra cmake args...
  local dir=$1
  shift
  mkdir -p "$dir"
  # The configure log stays inside the build directory (never next to it, in the source tree).
  local log=$dir/configure.log
  cmake -S "$root" -B "$dir" -DKokkos_ROOT="$Kokkos_ROOT" "${hypre_args[@]}" "$@" > "$log" 2>&1 ||
    { cat "$log"; exit 1; }
  cmake --build "$dir" -j "$jobs" ${build_targets[@]+--target "${build_targets[@]}"}
}

case "$mode" in
example)
  build=${MIXCON_BUILD_DIR:-$root/build}
  mkdir -p "$build"
  configure_and_build "$build" -DCMAKE_BUILD_TYPE=Release
  # The main example: Hertz contact of a cylinder on a rigid plane (docs/contact.md), run on the
  # report's 84-element mesh and a graded Quad8 mesh, compared with the closed form.
  "$build/apps/mixcon" run "$root/examples/hertz/hertz_refined.yaml" --output "$root/out/hertz/refined"
  /usr/bin/python3 "$root/examples/hertz_study.py" --mixcon "$build/apps/mixcon" --out "$root/out/hertz/study"
  ;;
test)
  build=${MIXCON_BUILD_DIR:-$root/build}
  mkdir -p "$build"
  configure_and_build "$build" -DCMAKE_BUILD_TYPE=Release
  cd "$build"
  export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2}
  export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive} # see sanitize below
  # The `slow` label (scaling to 1e6 unknowns, minutes) stays out: `ctest -L slow` runs it.
  ctest --output-on-failure -j "$jobs" -LE slow
  ;;
sanitize)
  build=${MIXCON_BUILD_DIR:-$root/build}-sanitize
  mkdir -p "$build"
  # -O1, as AddressSanitizer's documentation advises for a usable speed (assertions stay on):
  # at -O0 the Kokkos kernels of the 3D mixed tests ran 10 minutes and more each
  # (SolidMixedSolve.*Cantilever*), and CI's 5400 s ran out at stop 42. -g1: line tables, all
  # the sanitizers' stack traces use (file:line of each frame); full -g made the compile 1.4x
  # longer and the objects 3x larger (test_element_driver.cpp: 138 s against 98 s, 59 MB
  # against 20 MB). Only what `ctest -L unit` runs is built (the unit tests, the program).
  build_targets=(mixcon_unit_tests mixcon_app)
  configure_and_build "$build" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-g1 -O1" \
    -DMIXCON_ENABLE_SANITIZERS=ON -DMIXCON_ENABLE_BENCHMARKS=OFF
  cd "$build"
  export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2}
  # ctest -j runs two tests of two OpenMP threads each on 2 cores: threads spinning at the end
  # of every small kernel then wait for a partner that is not scheduled. Measured, Debug + ASan,
  # SolidMixedSolve.LinearCantileverAsTheDirectSolve beside another test: 672 s spinning (the
  # default), 167 s passive; alone 100 s and 109 s (docs/performance.md).
  export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
  # MPI and hypre keep allocations until exit by design; leaks are not what this run looks for.
  export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1
  # Two tests stay out: the 3D mixed cantilevers solved three ways (direct, assembled and matrix-
  # free AMG), 398 s and 685 s here at -O1 beside each other, against 10 minutes for all others.
  # The Release run (`test`) has them. Under the sanitizers their paths run in smaller tests:
  # SolidMixedSolve.PatchTestWithTheAmgSolve (the assembled block-triangular AMG solve),
  # SolidMixedSolve.FailingIterativeSolveFallsBackToTheDirectLu (both models, AMG then the LU)
  # and SolidMixedMatrixFree.ProductsAreThoseOfTheAssembledJacobian (the matrix-free products).
  ctest --output-on-failure -j "$jobs" -L unit \
    -E '^SolidMixedSolve[.](Linear|Nonlinear)CantileverAsTheDirectSolve$'
  ;;
bench)
  build=${MIXCON_BUILD_DIR:-$root/build}
  mkdir -p "$build"
  configure_and_build "$build" -DCMAKE_BUILD_TYPE=Release
  for b in "$build"/bench/mixcon_bench_*; do
    "$b" --benchmark_out="$b.json" --benchmark_out_format=json
  done
  ;;
*)
  echo "usage: cmake/quickstart.sh example|test|sanitize|bench" >&2
  exit 2
  ;;
esac
