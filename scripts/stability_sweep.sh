#!/usr/bin/env bash
# Stability sweep (docs/stability.md): te safety, damping, yarn modulus, bending, grids from
# 3 x 3 to 2000 x 2000, loads up to breaking and both integrators, one axis at a time around
# base cases with exact answers (MODEL.md 12), plus corners. Each run has a time limit and is
# classified BALANCED-RIGHT, STOPPED-CLEAR, NOT-BALANCED-FLAGGED or BAD; prints a markdown
# table and exits non-zero if any case is BAD.
#   scripts/stability_sweep.sh [-fast] [--only REGEX] [--keep DIR] [--fabric PATH] [--nice N] [--list]
# -fast: the quick cases only (the test suite's, under a minute); without it the whole sweep
# (4-6 minutes on 2 shared cores). Runs use at most 2 ranks, at nice 10.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# Open MPI refuses root and more ranks than cores unless told
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
exec /usr/bin/python3 "$ROOT/scripts/stability_sweep.py" "$@"
