#!/usr/bin/env bash
# Same results as a reference revision, bit for bit: scripts/identity_check.sh [REV] [-quick] [-h]
#
# Builds REV (default: HEAD, the last commit) into build-ref/REV/ beside the working tree's build/,
# runs the shipped scenes (shortened where a full run takes minutes) with both binaries on 1, 2
# and 3 ranks, and compares the final positions (cmp), curve.csv (cmp), summary.json (without
# its wall-clock fields), fabric.h5 and checkpoint.h5 (h5diff, exact). A restructuring that
# changes no physics must print PASS for every case; the exit status is the number of failures.
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
rev="" quick=0
for a in "$@"; do
  case "$a" in
    -h | --help) sed -n '2,/^[^#]/{/^[^#]/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;;
    -quick) quick=1 ;;
    -*) echo "identity_check: unknown option '$a' (usage: scripts/identity_check.sh [REV] [-quick] [-h])" >&2; exit 2 ;;
    *) [[ -z "$rev" ]] || { echo "identity_check: revision '$a': one revision only (already $rev)" >&2; exit 2; }
       rev="$a" ;;
  esac
done
rev="${rev:-HEAD}"
source "$ROOT/scripts/setup.sh"

# one source and build folder per revision (git archive keeps the commit's file times, so a
# folder shared between revisions would keep stale objects)
hash="$(git -C "$ROOT" rev-parse -q --short --verify "$rev^{commit}")" || { echo "identity_check: no revision (commit) $rev" >&2; exit 1; }
ref_src="$ROOT/build-ref/$hash/src" ref_build="$ROOT/build-ref/$hash/build"
if [[ ! -x "$ref_build/fabric" ]]; then
  rm -rf "$ROOT/build-ref/$hash"; mkdir -p "$ref_src"
  git -C "$ROOT" archive "$rev" | tar -x -C "$ref_src" || { echo "identity_check: cannot export $rev" >&2; exit 1; }
  { cmake -S "$ref_src" -B "$ref_build" -DCMAKE_BUILD_TYPE=Release >/dev/null &&
    cmake --build "$ref_build" -j "$(nproc)" --target fabric >/dev/null; } ||
    { rm -rf "$ROOT/build-ref/$hash"; echo "identity_check: $rev does not build" >&2; exit 1; }
fi
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
trap 'echo "identity_check: interrupted: no verdict" >&2; exit 130' INT TERM # an interrupted run is no case that passed
# copies, so that a rebuild while the cases run does not mix binaries
cp "$ref_build/fabric" "$work/fabric.ref"; cp "$ROOT/build/fabric" "$work/fabric.new"
ref="$work/fabric.ref"; new="$work/fabric.new"
IN="$ROOT/inputs"

# name | ranks | options; @IN@ stands for $IN, put in after the options are split into words
# (the checkout's path may hold spaces)
cases=(
  "strip_warp|1 2 3|-scene @IN@/strip_warp.yaml -checkpoint_every 10"
  "strip_table|1 3|-scene @IN@/strip_warp.yaml -warp_law_csv @IN@/yarns/cotton_20tex.csv -weft_law_csv @IN@/yarns/cotton_20tex.csv"
  "strip_weft|1|-scene @IN@/strip_weft.yaml"
  "strip_paper|1 2|-scene @IN@/strip_warp.yaml -integrator paper -load_steps 3 -max_inner_steps 400"
  "strip_kinetic|1 3|-scene @IN@/strip_warp.yaml -gauge_mm 20 -width_mm 5 -integrator damped -kinetic_damping -load_steps 3 -early_exit 0 -max_inner_steps 500"
  "strip_fixed|1 2 3|-scene @IN@/strip_warp.yaml -predict none -load_steps 2 -early_exit 0 -max_inner_steps 300 -point_load_N 0,0,0.02"
  "strip_path|1 2|-scene @IN@/strip_warp.yaml -gauge_mm 40 -width_mm 10 -grip_path_mm 2,0,0,2,1,0.5 -load_steps 4"
  "strip_break|1 2|-scene @IN@/strip_warp.yaml -gauge_mm 20 -width_mm 5 -elongation_pct 20 -load_steps 20 -max_inner_steps 2000"
  "bias|1 2|-scene @IN@/bias.yaml -load_steps 2 -max_inner_steps 3000"
  "square_net|1 2 3|-scene @IN@/square_net.yaml -max_inner_steps 3000"
  "pushing|1 2|-scene @IN@/pushing.yaml -load_steps 2 -max_inner_steps 3000 -output_te_every 1000"
  "pushing_friction|1 2|-scene @IN@/pushing.yaml -load_steps 2 -max_inner_steps 2000 -friction_mu 0.3"
  "drape|1 2|-scene @IN@/drape.yaml -max_inner_steps 3000 -checkpoint_every 1"
  "large|2|-scene @IN@/large.yaml -gauge_mm 100 -width_mm 100 -max_inner_steps 200"
  "local|1|-scene @IN@/local_2000.yaml -yarns 200 -gauge_mm 83 -max_inner_steps 100"
)
((quick)) && cases=("${cases[@]:0:5}")

fail=0
# summary.json without its wall-clock figures, the echo of the options and the builds' revisions
strip_json() {
  /usr/bin/python3 -c 'import json, sys
d = json.load(open(sys.argv[1]))
for k in ("wall_s", "point_updates_per_s", "options", "fabric_revision", "petsc_version", "mpi_library"): d.pop(k, None)
print(json.dumps(d, sort_keys=True, indent=1))' "$1"
}
# exact h5diff, apart from the checkpoint's wall-clock attribute wall_s and the checksum of the
# attributes, which covers it (every other attribute is compared itself), and fabric.h5's
# fabric_revision and scene_hash (the two builds'; scene_hash hashes the option table's keys)
h5same() {
  diff -q <(h5ls -r "$1" 2>&1) <(h5ls -r "$2" 2>&1) >/dev/null || return 1
  { h5diff -v "$1" "$2" 2>&1 || true; } | awk '/^attribute: <(wall_s|attributes_checksum|fabric_revision|scene_hash) / {skip = 1} /^[1-9][0-9]* differences found/ && !skip {bad = 1}
    /differences found/ {skip = 0} /^(file1|Not comparable|Objects are not)/ {} END {exit bad}'
}
compare() { # name dir_ref dir_new
  local n="$1" a="$2" b="$3" bad=""
  if [[ -f "$a/pos.bin" || -f "$b/pos.bin" ]]; then cmp -s "$a/pos.bin" "$b/pos.bin" || bad+=" positions"
  else # neither wrote positions (both stopped with an error): the same error
    diff -q <(grep '^fabric: error:' "$a/log") <(grep '^fabric: error:' "$b/log") >/dev/null || bad+=" error"
  fi
  cmp -s "$a/out/curve.csv" "$b/out/curve.csv" || bad+=" curve.csv"
  diff -q <(strip_json "$a/out/summary.json") <(strip_json "$b/out/summary.json") >/dev/null || bad+=" summary.json"
  for h in fabric.h5 checkpoint.h5; do
    [[ -f "$a/out/$h" || -f "$b/out/$h" ]] || continue
    h5same "$a/out/$h" "$b/out/$h" || bad+=" $h"
  done
  cmp -s "$a/out/fabric.xmf" "$b/out/fabric.xmf" 2>/dev/null || [[ ! -f "$a/out/fabric.xmf" ]] || bad+=" fabric.xmf"
  if [[ -z "$bad" ]]; then echo "PASS $n"; else echo "FAIL $n:$bad differ"; fail=$((fail + 1)); fi
}
for c in "${cases[@]}"; do
  IFS='|' read -r name ranks opts <<<"$c"
  read -ra args <<<"$opts"
  args=("${args[@]//@IN@/"$IN"}")
  for np in $ranks; do
    for which in ref new; do
      bin="$ref"; [[ $which == new ]] && bin="$new"
      d="$work/$name.$np.$which"; mkdir -p "$d"
      mpiexec -n "$np" "$bin" "${args[@]}" -quiet -output_dir "$d/out" -positions_out "$d/pos.bin" >"$d/log" 2>&1 ||
        echo "note: $name on $np ranks ($which) exited non-zero: $(tail -n 1 "$d/log")"
    done
    compare "$name on $np ranks" "$work/$name.$np.ref" "$work/$name.$np.new"
  done
done
echo "identity_check: $fail case(s) differ from $rev"
exit "$fail"
