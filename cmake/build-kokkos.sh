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

if [ ! -f "$cache/$tarball" ] || [ ! -f "$cache/trilinos_${src_version}.dsc" ]; then
  # A private apt configuration that adds bookworm's source index without touching the system's.
  lists="$work/lists"; mkdir -p "$lists/partial"
  uri=$(awk '/^URIs:/{print $2; exit}' /etc/apt/sources.list.d/debian.sources 2>/dev/null || true)
  [ -n "$uri" ] || uri=http://deb.debian.org/debian
  keyring=/usr/share/keyrings/debian-archive-keyring.gpg
  echo "deb-src [signed-by=$keyring] $uri bookworm main" > "$work/sources.list"
  o=(-o "Dir::Etc::SourceList=$work/sources.list" -o "Dir::Etc::SourceParts=/dev/null"
     -o "Dir::State::Lists=$lists")
  apt-get "${o[@]}" update -q
  (cd "$cache" && apt-get "${o[@]}" source --download-only "trilinos=$src_version")
fi

# Verify the tarball against the checksum the (signed) .dsc lists.
want=$(awk -v f="$tarball" '/^Checksums-Sha256:/{s=1; next} /^[A-Z]/{s=0} s && $3==f {print $1}' \
  "$cache/trilinos_${src_version}.dsc")
have=$(sha256sum "$cache/$tarball" | awk '{print $1}')
if [ -z "$want" ] || [ "$want" != "$have" ]; then
  echo "mixcon: checksum mismatch for $tarball (want '$want', have '$have')" >&2
  rm -f "$cache/$tarball"
  exit 1
fi

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
