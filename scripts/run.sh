#!/usr/bin/env bash
# Run a scene on 2 ranks (NP=... to change): scripts/run.sh [scene.yaml] [extra options]
# Installs and builds what is missing first. Results go to results/<scene name>/.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$ROOT/scripts/setup.sh"
scene="${1:-$ROOT/inputs/strip_warp.yaml}"
[[ $# -gt 0 ]] && shift
name="$(basename "$scene")"; name="${name%.*}"
out="$ROOT/results/$name"
mpiexec -n "${NP:-2}" "$ROOT/build/fabric" -scene "$scene" -output_dir "$out" "$@"
