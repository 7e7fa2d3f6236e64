#!/usr/bin/env bash
# Fails (exit 1) when a library source includes Eigen and also holds device code (a Kokkos
# lambda, a KOKKOS_*FUNCTION or a parallel_for/reduce/scan launch). Eigen is host-only in mixcon:
# the CUDA build compiles every translation unit with nvcc, which would compile Eigen for the
# device too (and warn); host algebra goes through solver/HostAlgebra.hpp or its own translation
# unit. Tests and benchmarks may use Eigen beside device code (host references; EIGEN_NO_CUDA is
# set for every Eigen user). Run by ctest (repo.eigen_host_only, label unit).
# Usage: cmake/check-eigen-host.sh [repository root] (default: this script's).
set -euo pipefail
root=${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)}
cd "$root"
device='KOKKOS_LAMBDA|KOKKOS_(INLINE_)?FUNCTION|KOKKOS_CLASS_LAMBDA|parallel_(for|reduce|scan)[[:space:]]*\('
bad=""
for f in $(grep -rlE '#include[[:space:]]*<Eigen/' --include='*.cpp' --include='*.hpp' \
             core mesh kernels solver contact io apps || true); do
  if grep -qE "$device" "$f"; then
    bad+="  $f: $(grep -nE "$device" "$f" | head -1)"$'\n'
  fi
done
if [ -n "$bad" ]; then
  echo "check-eigen-host: Eigen included beside device code (move the host algebra to" >&2
  echo "solver/HostAlgebra.hpp or a translation unit of its own):" >&2
  printf '%s' "$bad" >&2
  exit 1
fi
echo "check-eigen-host: no library source includes Eigen beside device code"
