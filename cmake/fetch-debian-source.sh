#!/usr/bin/env bash
# Downloads one Debian bookworm source package's .dsc and upstream tarball into a cache directory
# (once) through a private apt configuration that adds bookworm's source index without touching
# the system's, and verifies the tarball against the checksum the (signed) .dsc lists. Shared by
# cmake/build-kokkos.sh and cmake/build-hypre.sh.
#
# Usage: cmake/fetch-debian-source.sh CACHE WORK PACKAGE VERSION TARBALL
#   CACHE where the files are kept, WORK a scratch directory (apt lists), e.g. hypre 2.26.0-3
#   hypre_2.26.0.orig.tar.gz. Exits 1 (and removes the tarball) on a checksum mismatch.
set -euo pipefail
cache=$1 work=$2 package=$3 version=$4 tarball=$5
dsc="$cache/${package}_${version}.dsc"

if [ ! -f "$cache/$tarball" ] || [ ! -f "$dsc" ]; then
  lists="$work/lists"; mkdir -p "$lists/partial"
  uri=$(awk '/^URIs:/{print $2; exit}' /etc/apt/sources.list.d/debian.sources 2>/dev/null || true)
  [ -n "$uri" ] || uri=http://deb.debian.org/debian
  keyring=/usr/share/keyrings/debian-archive-keyring.gpg
  echo "deb-src [signed-by=$keyring] $uri bookworm main" > "$work/sources.list"
  o=(-o "Dir::Etc::SourceList=$work/sources.list" -o "Dir::Etc::SourceParts=/dev/null"
     -o "Dir::State::Lists=$lists")
  apt-get "${o[@]}" update -q
  (cd "$cache" && apt-get "${o[@]}" source --download-only "$package=$version")
fi

want=$(awk -v f="$tarball" '/^Checksums-Sha256:/{s=1; next} /^[A-Z]/{s=0} s && $3==f {print $1}' \
  "$dsc")
have=$(sha256sum "$cache/$tarball" | awk '{print $1}')
if [ -z "$want" ] || [ "$want" != "$have" ]; then
  echo "mixcon: checksum mismatch for $tarball (want '$want', have '$have')" >&2
  rm -f "$cache/$tarball"
  exit 1
fi
