#!/usr/bin/env bash
# Builds a threaded Kokkos (OpenMP + Serial backends) from the Kokkos sources shipped inside
# Debian bookworm's trilinos 13.2.0 source package, and installs it into a cache directory.
# Debian's binary libtrilinos-kokkos-dev is Serial-only (and its CMake config is broken), so mixcon
# builds its own. Idempotent: a finished install is detected and reused.
#
# Usage: cmake/build-kokkos.sh [PREFIX]
#   PREFIX defaults to ${MIXCON_CACHE:-$HOME/.cache/mixcon}/kokkos-3.4.01-openmp
# Prints the install prefix on its last line (pass it as -DKokkos_ROOT=...).
set -euo pipefail

cache=${MIXCON_CACHE:-$HOME/.cache/mixcon}
prefix=${1:-$cache/kokkos-3.4.01-openmp}
stamp="$prefix/.mixcon-kokkos-complete"
if [ -f "$stamp" ] && [ -f "$prefix/lib/cmake/Kokkos/KokkosConfig.cmake" ]; then
  echo "mixcon: Kokkos already installed"
  echo "$prefix"
  exit 0
fi

mkdir -p "$cache"
work=$(mktemp -d "$cache/kokkos-build.XXXXXX")
trap 'rm -rf "$work"' EXIT
src_version=13.2.0-4
tarball=trilinos_13.2.0.orig.tar.gz

bash "$(dirname "${BASH_SOURCE[0]}")/fetch-debian-source.sh" "$cache" "$work" trilinos "$src_version" "$tarball"

tar -C "$work" -xzf "$cache/$tarball" --wildcards '*/packages/kokkos/*'
srcdir=$(ls -d "$work"/*/packages/kokkos)
cmake -S "$srcdir" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  -DKokkos_ENABLE_OPENMP=ON -DKokkos_ENABLE_SERIAL=ON -DCMAKE_CXX_STANDARD=17 \
  -DBUILD_SHARED_LIBS=ON -DCMAKE_INSTALL_PREFIX="$prefix" -DKokkos_ENABLE_TESTS=OFF \
  -DCMAKE_CXX_FLAGS="-w"
cmake --build "$work/build" -j "$(nproc)"
cmake --install "$work/build"
touch "$stamp"
echo "$prefix"
