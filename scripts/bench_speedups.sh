#!/usr/bin/env bash
# The measured speed-versus-accuracy trade of the paper's speed-ups (rank propagation,
# early exit, prediction) and sleeping. Prints three tables and writes a PNG; see
# scripts/bench_speedups.py. Takes about 15-25 minutes on 2 cores.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# the usage without installing or building
for a in "$@"; do [[ $a == -h || $a == --help ]] && exec /usr/bin/python3 "$ROOT/scripts/bench_speedups.py" -h; done
FABRIC_EXTRA_PACKAGES="python3-matplotlib python3-numpy" source "$ROOT/scripts/setup.sh"
cd "$ROOT"
exec /usr/bin/python3 scripts/bench_speedups.py "$@"
