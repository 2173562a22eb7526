#!/usr/bin/env bash
# Install what is missing (Debian packages, as root; present ones are skipped),
# then configure and build into build/. Sourced by run.sh, test.sh and bench.sh.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [[ ${BASH_SOURCE[0]} == "$0" && $# -gt 0 ]]; then # run itself, not sourced: it takes no argument
  case "$1" in -h | --help) sed -n '2,/^[^#]/{/^[^#]/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;; esac
  echo "setup.sh: usage: scripts/setup.sh (no arguments; --help)" >&2; exit 2
fi

# Open MPI refuses root and more ranks than cores unless told (CI runs as root on 2 cores)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1

# paraview + python3-paraview: pvpython and pvbatch (scripts/render.py, the output tests); xvfb and
# xauth: xvfb-run, a display for pvbatch; python3-h5py/numpy/matplotlib: the scripts and tests
packages=(build-essential cmake pkg-config petsc-dev libyaml-dev libhdf5-openmpi-dev libgsl-dev openmpi-bin hdf5-tools valgrind
  paraview python3-paraview xvfb xauth python3-h5py python3-numpy python3-matplotlib ${FABRIC_EXTRA_PACKAGES:-})
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  if [[ $(id -u) -eq 0 ]]; then SUDO=""; elif command -v sudo >/dev/null; then SUDO="sudo"; else
    echo "setup: missing packages ${missing[*]}: run as root or install them with apt-get" >&2; exit 1
  fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

[[ -e $ROOT/build/CMakeCache.txt ]] || echo "setup: building into build/ (a minute or two the first time)" >&2
cmake -S "$ROOT" -B "$ROOT/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$ROOT/build" -j "$(nproc)" >/dev/null
