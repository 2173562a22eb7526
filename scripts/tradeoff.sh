#!/usr/bin/env bash
# The explicit path's speed/accuracy trade against the quasi-static reference, for one scene:
# the scene solved by -solver static at -balance_tol 1e-8 is the reference; each row runs the
# explicit path as set (the scene, and the options given) with one knob changed (balance tolerance, te safety, prediction, rank
# propagation, sleeping, the relaxation scheme) and gives its wall time, te steps, whether every
# load step balanced, and its error against the reference: the largest relative force error
# over the curve's rows (the pushing test: from 5 mm of travel on, where the force is above 1 N)
# and, for the bias test, the largest error of the centre's shear angle; for the drape (one load
# step, no force) the error of the drape coefficient in points of %, the folds and the error of
# the largest drop. The drape's reference is TAO's trust region (-static_minimizer tao -tao_type
# ntr), the minimizer that balances it (docs/static.md). All runs on 2 ranks in
# one run of this script: compare the times within its table only.
#   scripts/tradeoff.sh pushing|bias|drape [table.csv [options...]]   (RANKS=ranks, default 2; LIMIT_S=a
#   run's limit, 300 s). The options go to every run before the row's own (a row's knob wins; the
#   reference leaves out the explicit relaxation's):
#   scripts/tradeoff.sh pushing t.csv -predict linear -balance_tol 1e-3 measures the knobs around
#   that setting instead of the scene's.
# /usr/bin/python3 scripts/plot_tradeoff.py table.csv -o figure.png draws error against time.
set -eu
case "${1:-}" in
  -h | --help) sed -n '2,/^[^#]/{/^[^#]/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;;
  "") echo "scripts/tradeoff.sh: usage: scripts/tradeoff.sh pushing|bias|drape [table.csv [options...]] (--help)" >&2; exit 2 ;;
esac
here="$(cd "$(dirname "$0")/.." && pwd)"
fabric="${FABRIC:-$here/build/fabric}"
if [[ -n "${FABRIC:-}" ]]; then # the user's binary, as given
  [[ -f "$FABRIC" && -x "$FABRIC" ]] || { echo "scripts/tradeoff.sh: FABRIC '$FABRIC': not an executable file" >&2; exit 2; }
  fabric="$(cd "$(dirname "$FABRIC")" && pwd)/$(basename "$FABRIC")"
elif [[ ! -x "$fabric" ]]; then
  bash "$here/scripts/setup.sh" >/dev/null
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
scene="$1"
case "$scene" in pushing | bias | drape) ;; *) echo "scripts/tradeoff.sh: scene '$scene': one of pushing, bias, drape" >&2; exit 2 ;; esac
csv="${2:-}"
# the table's file is checked before the runs (it was written after them: a traceback then), and an
# option in its place (the file forgotten) is not taken for it
if [[ $csv == -* ]]; then
  echo "scripts/tradeoff.sh: table.csv '$csv': an option, not a file name (give the table's file first, or \"\" for none)" >&2; exit 2
fi
if [[ -n $csv ]]; then
  why=""
  if [[ -d $csv ]]; then why="a directory"
  elif [[ ! -d "$(dirname -- "$csv")" ]]; then why="no directory $(dirname -- "$csv")"
  elif [[ -e $csv ]]; then : 2>/dev/null >>"$csv" || why="cannot be written"
  else { : 2>/dev/null >"$csv" && rm -f -- "$csv"; } || why="cannot be written"
  fi
  [[ -z $why ]] || { echo "scripts/tradeoff.sh: table.csv '$csv': $why" >&2; exit 2; }
fi
base=("${@:3}")
ranks="${RANKS:-2}"
limit="${LIMIT_S:-300}" # seconds a run may take
[[ $ranks =~ ^[1-9][0-9]*$ ]] || { echo "scripts/tradeoff.sh: RANKS '$ranks': the number of ranks, a positive integer" >&2; exit 2; }
# as timeout reads it (a number, an exponent, a unit s, m, h or d); 0 would be no limit at all
[[ $limit =~ ^([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?[smhd]?$ ]] && awk -v v="${limit%[smhd]}" 'BEGIN {exit !(v + 0 > 0)}' ||
  { echo "scripts/tradeoff.sh: LIMIT_S '$limit': a run's time limit, a positive number of seconds (or with a unit: 5m)" >&2; exit 2; }
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
trap 'echo "scripts/tradeoff.sh: interrupted" >&2; exit 130' INT TERM

run() { # name, options...: a run that the solver stops (its message in NAME.error), or that
         # passes the time limit, is a row too (timeout in the foreground: Ctrl-C reaches the run; a run still there 30 s after its limit is killed)
  local name="$1" rc=0; shift
  timeout --foreground -k 30 "$limit" mpiexec -n "$ranks" "$fabric" -scene "$here/inputs/$scene.yaml" -output_every 0 -quiet \
    -output_dir "$work/$name" "${base[@]}" "$@" >"$work/$name.log" 2>&1 || rc=$?
  ((rc == 0)) && return
  if ((rc == 124)); then echo "fabric: stopped by the script's time limit of $limit s" >"$work/$name.error"; return; fi
  grep -m1 '^fabric: error' "$work/$name.log" >"$work/$name.error" || { echo "run $name failed: $(tail -3 "$work/$name.log")" >&2; exit 1; }
}

# knob|value|options; the first row is the reference, the second the explicit path as set (the
# scene and the options given)
if [[ $scene == drape ]]; then
  # one load step from the flat specimen: no prediction to vary; the front and sleeping follow
  # jaws or a ball, which the drape has not (refused: the sleeping row shows the message); the
  # damped and paper schemes at the damping the scene shipped with before FIRE (0.003, te
  # safety 0.75) and ten times it
  runs=("reference|static tao 1e-8|-solver static -static_minimizer tao -tao_type ntr -tao_max_it 3000 -balance_tol 1e-8"
        "base|-|"
        "balance_tol|1e-4|-balance_tol 1e-4" "balance_tol|1e-5|-balance_tol 1e-5"
        "balance_tol|1e-7|-balance_tol 1e-7 -max_inner_steps 1000000"
        "te_safety|0.5|-te_safety 0.5" "te_safety|0.95|-te_safety 0.95"
        "sleep_tol|1e-7|-sleep_tol 1e-7"
        "integrator|damped 0.003|-integrator damped -damping_ratio 0.003 -te_safety 0.75"
        "integrator|damped 0.03|-integrator damped -damping_ratio 0.03 -te_safety 0.75"
        "integrator|paper 0.003|-integrator paper -damping_ratio 0.003 -te_safety 0.75")
else
  runs=("reference|static 1e-8|-solver static -balance_tol 1e-8"
        "base|-|"
        "balance_tol|1e-2|-balance_tol 1e-2" "balance_tol|3e-3|-balance_tol 3e-3"
        "balance_tol|3e-4|-balance_tol 3e-4 -max_inner_steps 400000"
        "balance_tol|1e-4|-balance_tol 1e-4 -max_inner_steps 400000"
        "te_safety|0.5|-te_safety 0.5" "te_safety|0.95|-te_safety 0.95"
        "predict|none|-predict none" "predict|linear|-predict linear" "predict|extrapolate|-predict extrapolate"
        "front|on|-front" "sleep_tol|1e-4|-sleep_tol 1e-4"
        "integrator|damped 0.05|-integrator damped -damping_ratio 0.05 -max_inner_steps 400000"
        "integrator|paper 0.05|-integrator paper -damping_ratio 0.05 -max_inner_steps 400000")
fi
# the reference takes the options given except the explicit relaxation's knobs, which -solver static
# refuses (src/scene.c, CheckSolverOptions)
relaxation=" -integrator -front -sleep_tol -kinetic_damping -damping_ratio -balance_hold -balance_floor -speed_tol -energy_watch -early_exit -te_safety -grip_ramp_steps "
all=("${base[@]}") static_base=()
for ((k = 0; k < ${#all[@]}; k++)); do
  if [[ "$relaxation" == *" ${all[k]} "* ]]; then # the knob, and its value if one follows
    if ((k + 1 < ${#all[@]})) && [[ "${all[k + 1]}" != -[a-z]* ]]; then k=$((k + 1)); fi
    continue
  fi
  static_base+=("${all[k]}")
done
i=0
for r in "${runs[@]}"; do
  opts="${r#*|}"; opts="${opts#*|}"
  if ((i == 0)); then base=("${static_base[@]}"); else base=("${all[@]}"); fi
  # shellcheck disable=SC2086
  run "r$i" $opts
  # the rows are measured against the reference: it must have balanced every load step
  if ((i == 0)); then
    why=""
    if [[ -s "$work/r0.error" ]]; then why="stopped: $(cat "$work/r0.error")"
    elif [[ ! -f "$work/r0/summary.json" ]]; then why="left no summary.json"
    elif ! grep -q '"converged": true' "$work/r0/summary.json"; then why="did not balance every load step (summary.json: converged false)"
    elif [[ $scene == pushing ]] && ! awk -F, 'NR > 1 && $3 >= 5 - 1e-9 {ok = 1} END {exit !ok}' "$work/r0/curve.csv"; then
      why="reaches no load step at 5 mm of travel or more (the force error is taken from 5 mm on)"
    fi
    if [[ -n $why ]]; then echo "scripts/tradeoff.sh: the reference run ($opts ${base[*]}) $why; nothing to measure against" >&2; exit 1; fi
  fi
  i=$((i + 1))
done

/usr/bin/python3 - "$work" "$scene" "$csv" "${runs[@]}" <<'PY'
import csv, json, sys
work, scene, out, runs = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
def load(i):
    s = json.load(open(f"{work}/r{i}/summary.json"))
    return s, list(csv.DictReader(open(f"{work}/r{i}/curve.csv")))
ref_s, ref = load(0)
keep = lambda r: float(r["travel_mm"]) >= 5 - 1e-9 if scene == "pushing" else True
extra = {"bias": ["shear_err_deg"], "drape": ["dc_err_pts", "folds", "drop_err_mm"]}.get(scene, [])
head = ["knob", "value", "balanced", "wall_s", "te_steps"] + (["force_err_pct"] if scene != "drape" else []) + extra
print(" ".join(f"{h:>13}" for h in head))
table = []
for i, r in enumerate(runs):
    knob, value = r.split("|")[:2]
    try:
        err = open(f"{work}/r{i}.error").read()
    except OSError:
        err = ""
    if err:  # stopped with a message (the energy watch, say): no curve to compare
        row = [knob, value, "timeout" if "time limit" in err else "stopped"] + ["-"] * (len(head) - 3)
        table.append(row)
        print(" ".join(f"{c:>13}" for c in row) + "   " + err.strip()[:60] + "...")
        continue
    s, rows = load(i)
    if len(rows) != len(ref):  # ended early (a rupture, say): its rows are not the reference's
        row = [knob, value, "stopped"] + ["-"] * (len(head) - 3)
        table.append(row)
        print(" ".join(f"{c:>13}" for c in row) + f"   {len(rows)} load steps, the reference has {len(ref)}")
        continue
    pairs = [(a, b) for a, b in zip(rows, ref) if keep(b)]
    row = [knob, value, str(s["converged"]).lower(), f"{s['wall_s']:.2f}", str(s.get("te_steps") or "-")]
    if scene == "drape":
        row += [f"{abs(s['drape_coefficient_pct'] - ref_s['drape_coefficient_pct']):.3f}", str(s["folds"]),
                f"{abs(float(rows[-1]['drop_mm']) - float(ref[-1]['drop_mm'])):.3f}"]
    else:
        # relative to the reference's force; where that is 0, a force that is not 0 has no finite error
        rel = lambda a, b: (abs(a - b) / abs(b) if b else (0.0 if a == b else float("inf")))
        ferr = max((rel(float(a["force_N"]), float(b["force_N"])) for a, b in pairs), default=0.0)
        row.append(f"{100 * ferr:.4f}")
    if scene == "bias":
        row.append(f"{max(abs(float(a['center_shear_deg']) - float(b['center_shear_deg'])) for a, b in pairs):.5f}")
    table.append(row)
    print(" ".join(f"{c:>13}" for c in row))
if out:
    with open(out, "w", newline="") as f:
        w = csv.writer(f); w.writerow(head); w.writerows(table)
PY
