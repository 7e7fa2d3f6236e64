#!/usr/bin/env bash
# Packs built mixcon programs with every shared library they load (the ldd closure, glibc left
# out) and Open MPI's plugins into one relocatable tarball, to run them on a machine that has
# none of mixcon's Debian dependencies (the GPU machine of docs/gpu.md). On that machine:
#   tar xf bundle.tar.xz -C DIR && source DIR/env.sh <variant>   (variant: a BUILD name below)
# then run DIR/<variant>/bin/PROGRAM.
#   usage: bundle.sh OUT.tar.xz NAME=BUILD_DIR[:PROGRAM,...] ...
# PROGRAM paths are relative to BUILD_DIR (e.g. apps/mixcon,tests/mixcon_unit_tests).
set -euo pipefail
out=$(realpath -m "$1"); shift
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
glibc='^(libc|libm|libdl|libpthread|librt|libresolv|libutil|ld-linux-x86-64)\.so'
closure() { # the non-glibc libraries that the given ELF files load
  ldd "$@" 2>/dev/null | awk '/=> \//{print $3}' | sort -u | while read -r f; do
    basename "$f" | grep -Eq "$glibc" || echo "$f"
  done
}
copy_libs() { # dest files...
  local dest=$1; shift
  mkdir -p "$dest"
  for f in "$@"; do cp -Ln "$f" "$dest/$(basename "$f")"; done
}
for spec in "$@"; do
  name=${spec%%=*}; rest=${spec#*=}; dir=${rest%%:*}; progs=${rest#*:}
  mkdir -p "$stage/$name/bin"
  # Where the build and its sources were: the tests read examples/ and run apps/mixcon there.
  realpath "$dir" > "$stage/$name/build_dir"
  sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$dir/CMakeCache.txt" > "$stage/$name/source_dir"
  bins=()
  for p in ${progs//,/ }; do cp -L "$dir/$p" "$stage/$name/bin/"; bins+=("$dir/$p"); done
  # Each build's own libraries (libmixcon_*, Kokkos) apart: two builds share their sonames.
  mapfile -t libs < <(closure "${bins[@]}")
  own=(); sys=()
  for l in "${libs[@]}"; do
    case $l in /usr/*|/lib/*) sys+=("$l") ;; *) own+=("$l") ;; esac
  done
  copy_libs "$stage/$name/lib" "${own[@]}"
  copy_libs "$stage/sys/lib" "${sys[@]}"
done
# GNU time (glibc only) for the runs' peak memory: the GPU machine has none.
mkdir -p "$stage/sys/bin" && cp /usr/bin/time "$stage/sys/bin/time"
# Open MPI 4 (Debian layout, relocated by OPAL_PREFIX): plugins, their libraries, help texts.
ompi=/usr/lib/x86_64-linux-gnu/openmpi/lib/openmpi3
mkdir -p "$stage/ompi/lib/x86_64-linux-gnu/openmpi/lib" "$stage/ompi/share"
cp -r "$ompi" "$stage/ompi/lib/x86_64-linux-gnu/openmpi/lib/"
cp -r /usr/share/openmpi "$stage/ompi/share/"
mapfile -t plug < <(closure "$ompi"/*.so)
copy_libs "$stage/sys/lib" "${plug[@]}"
cat > "$stage/env.sh" <<'ENV'
# source env.sh VARIANT: libraries of VARIANT first, then the shared system ones.
_b=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
export LD_LIBRARY_PATH=$_b/$1/lib:$_b/sys/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
for _d in /usr/local/nvidia/lib64 /usr/local/nvidia/lib /usr/local/cuda/compat; do # libcuda.so.1
  [ -d "$_d" ] && LD_LIBRARY_PATH=$LD_LIBRARY_PATH:$_d
done
export PATH=$_b/$1/bin:$PATH
export OPAL_PREFIX=$_b/ompi OMPI_MCA_ess_singleton_isolated=1 OMPI_ALLOW_RUN_AS_ROOT=1 \
  OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,vader OMPI_MCA_pml=ob1
ENV
tar -C "$stage" -cf - . | xz -9 -T0 > "$out"
du -h "$out"
