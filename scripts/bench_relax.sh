#!/usr/bin/env bash
# The explicit path's relaxation without hand tuning (docs/relaxation.md): FIRE, the default,
# against the damped scheme with the damping a user had to find.
#  Table 1: the square net scaled to 101 x 101 crossings (inputs/square_net.yaml, 41.67 mm) in one
#           load step, balanced to 1e-6: the damped scheme over a sweep of -damping_ratio, and FIRE.
#  Table 2: the shipped scenes as they ship (FIRE, no damping key) against the damped scheme with
#           the damping (and te safety) the scenes carried before FIRE.
# te steps do not depend on the machine; compare wall times only within one run of the script.
# usage: [KEEP=DIR] scripts/bench_relax.sh [--table 1|2] [--np N]   (about 15 minutes on 2 idle cores)
source "$(dirname "$0")/bench_env.sh"
tables="1 2"; np=2
while (($#)); do
  case "$1" in
    --table | --np) (($# >= 2)) || { echo "bench_relax.sh: $1 without its value (--table 1|2, --np N)" >&2; exit 2; } ;;&
    --table) [[ $2 == [12] ]] || { echo "bench_relax.sh: --table '$2': 1 or 2" >&2; exit 2; }
             tables="$2"; shift 2 ;;
    --np) [[ $2 =~ ^[1-9][0-9]*$ ]] || { echo "bench_relax.sh: --np '$2': a positive number of ranks" >&2; exit 2; }
          np="$2"; shift 2 ;;
    *) echo "bench_relax.sh: unknown argument '$1' (--table 1|2, --np N)" >&2; exit 2 ;;
  esac
done
# KEEP=DIR keeps every run's output in DIR/<case>/
if [[ -n "${KEEP:-}" ]]; then # an absolute path: the runs go on from the repository
  work="$(mkdir -p -- "$KEEP" 2>/dev/null && cd -- "$KEEP" && pwd)" ||
    { echo "bench_relax.sh: KEEP '$KEEP': cannot make that directory" >&2; exit 2; }
else work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT; fi
cd "$here"

# run NAME OPTIONS...: one run on $np ranks; prints te_steps wall_s converged and the last curve row
run() {
  local name="$1"; shift
  local t0 t1
  t0=$(date +%s.%N)
  mpiexec -n "$np" "$fabric" "$@" -output_dir "$work/$name" -output_every 0 -quiet >"$work/$name.log" 2>&1 || true
  t1=$(date +%s.%N)
  /usr/bin/python3 - "$work/$name" "$t0" "$t1" <<'PY'
import csv, json, sys
d, t0, t1 = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
try:
    s = json.load(open(d + "/summary.json"))
    rows = list(csv.DictReader(open(d + "/curve.csv")))
except Exception:
    print("- %.1f failed -" % (t1 - t0)); sys.exit()
if not rows:  # stopped before its first load step ended: the error's first words
    err = next((l for l in open(d + ".log") if "fabric: error:" in l), "fabric: error: -").split("error:")[1]
    print("%d %.1f STOPPED %s" % (s["te_steps"], t1 - t0, err.split(":")[0].strip())); sys.exit()
last = rows[-1]
res = ("drape %.2f %%" % s["drape_coefficient_pct"] if "drape_coefficient_pct" in s
       else "travel %s mm, force %s N" % (last.get("travel_mm", "-"), last["force_N"]) if "travel_mm" in last
       else "force %s N" % last["force_N"])
print("%d %.1f %s %s" % (s["te_steps"], t1 - t0, "yes" if s["converged"] else "NO", res))
PY
}

# row NAME OPTIONS...: run into n w c r; a run that left no results (not a stop the solver reports) ends the script
row() {
  local out
  out="$(run "$@")" # (not a process substitution: the shell waits for it, and Ctrl-C reaches it)
  read -r n w c r <<<"$out"
  [[ $c != failed ]] || { echo "bench_relax.sh: run $1 left no results: $(fabric_error "$work/$1.log" 3)" >&2; exit 1; }
}

if [[ " $tables " == *" 1 "* ]]; then
  echo "Table 1: square net 101 x 101, one load step of 0.5 N, -balance_tol 1e-6 (np $np)"
  printf '%-22s %10s %8s %9s  %s\n' relaxation te_steps wall_s balanced result
  net=(-scene inputs/square_net.yaml -gauge_mm 41.6666667 -width_mm 41.6666667 -load_steps 1 -max_inner_steps 400000)
  for d in 0.02 0.03 0.05 0.1 0.2; do
    row "net_d$d" "${net[@]}" -integrator damped -damping_ratio "$d"
    printf '%-22s %10s %8s %9s  %s\n' "damped $d" "$n" "$w" "$c" "$r"
  done
  row net_fire "${net[@]}"
  printf '%-22s %10s %8s %9s  %s\n' "fire (default)" "$n" "$w" "$c" "$r"
fi

if [[ " $tables " == *" 2 "* ]]; then
  echo "Table 2: shipped scenes, FIRE (as shipped) against the damped scheme with the scenes' former keys (np $np)"
  echo "curve: the largest difference of FIRE's force (the square net's: travel, its force is the load) from the"
  echo "damped run's, in % of the damped value, over the load steps from 5 mm of travel on (pushing) or with a"
  echo "force above 1 % of the largest (the others)"
  printf '%-12s %-44s %10s %8s %9s  %s\n' scene relaxation te_steps wall_s balanced result
  # scene|former damped options
  for row in "strip_warp|-damping_ratio 1" "square_net|-damping_ratio 1" "bias|-damping_ratio 0.05" \
             "drape|-damping_ratio 0.003 -te_safety 0.75 -te_strain_window 0.03 -balance_tol 1e-3" "pushing|-damping_ratio 1"; do
    sc="${row%%|*}"; old="${row#*|}"
    # shellcheck disable=SC2086
    row "${sc}_damped" -scene "inputs/$sc.yaml" -integrator damped $old
    printf '%-12s %-44s %10s %8s %9s  %s\n' "$sc" "damped $old" "$n" "$w" "$c" "$r"
    row "${sc}_fire" -scene "inputs/$sc.yaml"
    printf '%-12s %-44s %10s %8s %9s  %s\n' "$sc" "fire (as shipped)" "$n" "$w" "$c" "$r"
    [[ $sc == drape ]] || /usr/bin/python3 - "$work/${sc}_damped/curve.csv" "$work/${sc}_fire/curve.csv" <<'PY'
import csv, sys
try:
    a, b = (list(csv.DictReader(open(f))) for f in sys.argv[1:3])
except Exception:
    sys.exit()
top = max(abs(float(r["force_N"])) for r in a)
keep = [(x, y) for x, y in zip(a, b)
        if (float(x["travel_mm"]) >= 5 - 1e-9 if "travel_mm" in x and "pushing" in sys.argv[1] else abs(float(x["force_N"])) > 0.01 * top)]
col = "travel_mm" if "square_net" in sys.argv[1] else "force_N"  # the square net's force is the load it is given
d = max((abs(float(y[col]) - float(x[col])) / abs(float(x[col])) for x, y in keep), default=0)
print("%-12s %-44s curve: %.3f %% over %d load steps" % ("", "", 100 * d, len(keep)))
PY
  done
fi
