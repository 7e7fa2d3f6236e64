#!/usr/bin/env bash
# Installs the Debian 12 packages mixcon needs (build, tests, benchmarks, plotting).
# Idempotent: packages already present are not touched, and apt is not called at all then.
# Usage: cmake/install-deps.sh            (as root, or with sudo available)
set -euo pipefail

packages=(
  build-essential cmake git ca-certificates pkg-config patch
  libeigen3-dev libhypre-dev libopenmpi-dev openmpi-bin libhdf5-dev
  libbenchmark-dev libgtest-dev libyaml-cpp-dev libcli11-dev libmetis-dev libsuitesparse-dev
  libopenblas0-serial
  python3-matplotlib python3-h5py python3-numpy
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "mixcon: all Debian dependencies present"
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then sudo="sudo"; else
    echo "mixcon: missing packages (${missing[*]}) and not root; install them and retry" >&2
    exit 1
  fi
fi
echo "mixcon: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
