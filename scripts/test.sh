#!/usr/bin/env bash
# Build (installing what is missing) and run the whole CTest suite: unit, verification,
# MPI (1, 2 and 3 ranks) and bad-input tests. Exits non-zero if anything fails.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$ROOT/scripts/setup.sh"
cd "$ROOT/build"
ctest --output-on-failure "$@"
