#!/usr/bin/env bash
# Run a scene on 2 ranks (NP=... to change): scripts/run.sh [scene.yaml] [extra options]
# Without a scene (no argument, or the first one an option) runs inputs/strip_warp.yaml.
# Installs and builds what is missing first. Results go to results/<scene name>/.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/{/^[^#]/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;; esac
[[ ${NP:-2} =~ ^[1-9][0-9]*$ ]] || { echo "run.sh: NP '${NP}': the number of ranks, a positive integer" >&2; exit 2; }
source "$ROOT/scripts/setup.sh"
scene="$ROOT/inputs/strip_warp.yaml"
if [[ $# -gt 0 && $1 != -* ]]; then scene="$1"; shift; fi
name="$(basename "$scene")"; name="${name%.*}"
out="$ROOT/results/$name"
mpiexec -n "${NP:-2}" "$ROOT/build/fabric" -scene "$scene" -output_dir "$out" "$@"
