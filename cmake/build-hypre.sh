#!/usr/bin/env bash
# Builds a threaded hypre (OpenMP) from Debian bookworm's hypre 2.26.0-3 source package and installs
# it into a cache directory. Debian's binary libhypre-dev is sequential (no OpenMP), and about 75% of
# the 2D Hertz run is spent in it (issue 20). The configuration matches Debian's where it matters for
# the ABI (/usr/include/hypre/HYPRE_config.h: 32-bit HYPRE_Int and HYPRE_BigInt, no mixed int, MPI
# with Open MPI, host memory), plus OpenMP. Built with hypre's CMake: a shared libHYPRE and a
# HYPREConfig.cmake that cmake/FindHYPRE.cmake finds through HYPRE_ROOT. One fix is applied to the
# source: cmake/patches/hypre-2.26.0-chebyshev-estimate.patch (hypre's Chebyshev eigenvalue
# estimate looped forever on BoomerAMG levels with an empty row; mixcon probes for the fix at run
# time and otherwise takes Gershgorin's bound). Idempotent: a finished install (of this patch
# level) is detected and reused.
#
# Usage: cmake/build-hypre.sh [PREFIX]
#   PREFIX defaults to ${MIXCON_CACHE:-$HOME/.cache/mixcon}/hypre-2.26.0-openmp
# Prints the install prefix on its last line (pass it as -DHYPRE_ROOT=...).
set -euo pipefail

cache=${MIXCON_CACHE:-$HOME/.cache/mixcon}
prefix=${1:-$cache/hypre-2.26.0-openmp}
patch_file="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/patches/hypre-2.26.0-chebyshev-estimate.patch"
# The stamp names the patch (a hash of its text): an install of another patch level is rebuilt in
# place. The unpatched installs of earlier checkouts stamp `.mixcon-hypre-complete`; its presence
# means one of them rebuilt this prefix since, so it is rebuilt again.
stamp="$prefix/.mixcon-hypre-complete-$(sha256sum "$patch_file" | cut -c1-12)"
if [ -f "$stamp" ] && [ ! -e "$prefix/.mixcon-hypre-complete" ] &&
  [ -f "$prefix/lib/cmake/HYPRE/HYPREConfig.cmake" ]; then
  echo "mixcon: hypre already installed"
  echo "$prefix"
  exit 0
fi

mkdir -p "$cache"
work=$(mktemp -d "$cache/hypre-build.XXXXXX")
trap 'rm -rf "$work"' EXIT
src_version=2.26.0-3
tarball=hypre_2.26.0.orig.tar.gz

bash "$(dirname "${BASH_SOURCE[0]}")/fetch-debian-source.sh" "$cache" "$work" hypre "$src_version" "$tarball"

tar -C "$work" -xzf "$cache/$tarball"
srcdir=$(ls -d "$work"/hypre-*/src)
patch -p1 --forward --batch -d "$srcdir/.." < "$patch_file"
rm -f "$prefix"/.mixcon-hypre-complete* # a half-done reinstall carries no stamp
# Debian's ABI: HYPRE_Int = HYPRE_BigInt = int (no HYPRE_ENABLE_BIGINT / MIXEDINT), MPI on, double
# precision, host memory. Its SuperLU_dist coupling is left out (mixcon does not call it). The
# install's RPATH points at its own lib directory, so programs linking it need no LD_LIBRARY_PATH.
cmake -S "$srcdir" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  -DHYPRE_ENABLE_SHARED=ON -DHYPRE_WITH_OPENMP=ON -DHYPRE_WITH_MPI=ON \
  -DHYPRE_ENABLE_BIGINT=OFF -DHYPRE_ENABLE_MIXEDINT=OFF -DHYPRE_ENABLE_SINGLE=OFF \
  -DHYPRE_BUILD_EXAMPLES=OFF -DHYPRE_BUILD_TESTS=OFF \
  -DCMAKE_INSTALL_PREFIX="$prefix" -DCMAKE_INSTALL_RPATH="$prefix/lib" \
  -DCMAKE_C_FLAGS="-w"
cmake --build "$work/build" -j "$(nproc)"
cmake --install "$work/build"
touch "$stamp"
echo "$prefix"
