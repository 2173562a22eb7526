#!/usr/bin/env bash
# break_locate.sh FABRIC INPUTS: a located break (-break_locate_pct, docs/rupture.md#a-located-break).
#  1. the ball burst at 6 threads/cm (burst.yaml, -ends_per_cm 6 -picks_per_cm 6), whose first tear leaves the
#     fabric whole: the bursting force in 15 load steps and in 60 agrees within 1e-3 relative, by the explicit path
#     and by the static one (each locates at least one break); without the location the two differ (printed);
#  2. the same in 30 load steps on 1, 2 and 3 ranks: positions bit-identical;
#  3. identical yarns (-warp_break_cv_pct 0, the 5 mm strip of rupture.sh case 1): one break located, every segment
#     breaks in its tear, and the maximum force is 12 x (Ec c + EA eb) = 43.056 N at 15.02 % (both within 1e-5);
#  4. checkpoints: the run of case 2 on 2 ranks with -rupture_drop_pct 0 -checkpoint_every 1, killed once a
#     checkpoint holds a located break, restarted on 3 ranks, ends bit-identical to the uninterrupted run;
#  5. the same run with -checkpoint_every_te 50, killed at a checkpoint within a round after which its load step
#     locates a break (the load step:round pairs from the uninterrupted run's -info, e.g. load step 12 before its first
#     location), restarted on 3 ranks: ends bit-identical (the trials and the tear after a restart within the load step);
#  6. frames: a 30 x 20 mm strip (CV 25 %) with frames every 200 te steps and every 200 te steps of a tear: times
#     strictly increasing (a load step that locates a break drops its te-step frames of the load it came before);
#     with tear frames alone (every 50 te steps), the frame at rest and floor(n / 50) of each tear of n te steps
#     (-info): a second break located in a load step keeps the frames of the first one's tear.
set -u
fabric="$1"; inputs="$2"
. "$(dirname "$0")/runs.sh" # $py, $work, $fail, run NP ARGS...
. "$(dirname "$0")/kill_run.sh" # wait_for, kill_run, attr
burst=(-scene "$inputs/burst.yaml" -ends_per_cm 6 -picks_per_cm 6 -output_every 0)

for k in 15 60; do
  run 1 "${burst[@]}" -load_steps $k -output_dir "$work/off$k" -break_locate_pct 0
  run 1 "${burst[@]}" -load_steps $k -output_dir "$work/on$k" -break_locate_pct 0.05
  run 1 "${burst[@]}" -load_steps $k -output_dir "$work/static$k" -break_locate_pct 0.05 -solver static
done
"$py" - "$work" <<'PY' || fail=1
import json, sys
d = sys.argv[1]
s = {n: json.load(open(f"{d}/{n}/summary.json")) for n in ("off15", "off60", "on15", "on60", "static15", "static60")}
bad = 0
for path in ("on", "static"):
    a, b = s[f"{path}15"], s[f"{path}60"]
    ok = abs(a["max_force_N"] / b["max_force_N"] - 1) <= 1e-3 and a["breaks_located"] >= 1 and b["breaks_located"] >= 1
    bad |= not ok
    print(("PASS" if ok else "FAIL") + f" {path}: bursting force in 15 load steps {a['max_force_N']:.6f} N, in 60 {b['max_force_N']:.6f} N "
          f"(tol 1e-3 relative), breaks located {a['breaks_located']}, {b['breaks_located']}")
print(f"     without the location: {s['off15']['max_force_N']:.6f} N and {s['off60']['max_force_N']:.6f} N")
sys.exit(bad)
PY

for np in 1 2 3; do
  run $np "${burst[@]}" -load_steps 30 -break_locate_pct 0.05 -output_dir "$work/r$np" -positions_out "$work/r$np.bin"
done
cmp -s "$work/r1.bin" "$work/r2.bin" && cmp -s "$work/r1.bin" "$work/r3.bin" \
  && echo "PASS located breaks: positions bit-identical on 1, 2 and 3 ranks" \
  || { echo "FAIL located breaks: positions differ on 1, 2 and 3 ranks"; fail=1; }

run 1 -scene "$inputs/strip_warp_rupture.yaml" -gauge_mm 20 -width_mm 5 -warp_break_cv_pct 0 -weft_break_cv_pct 0 \
  -output_every 0 -break_locate_pct 0.05 -output_dir "$work/cv0"
"$py" - "$work/cv0/summary.json" <<'PY' || fail=1
import json, sys
s = json.load(open(sys.argv[1]))
Ec, c, EA, eb = 0.05 * 52, 0.08, 52.0, 0.065
exact, at = 12 * (Ec * c + EA * eb), 100 * (c + eb * (1 + c))
ok = abs(s["max_force_N"] / exact - 1) <= 1e-5 and abs(s["elongation_at_max_force_pct"] / at - 1) <= 1e-5 \
    and s["breaks_located"] == 1 and s["segments_broken"] == 12 * 48 and s["rupture"] is not None
print(("PASS" if ok else "FAIL") + f" identical yarns, located: maximum {s['max_force_N']:.7f} N ({exact:.7f}) at "
      f"{s['elongation_at_max_force_pct']:.7f} % ({at:.4f}), tol 1e-5; {s['breaks_located']} located, "
      f"{s['segments_broken']} of 576 segments broken, rupture {s['rupture']}")
sys.exit(0 if ok else 1)
PY

opts=("${burst[@]}" -quiet -load_steps 30 -break_locate_pct 0.05 -rupture_drop_pct 0 -checkpoint_every 1)
a="$work/whole" b="$work/killed"
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$a" -positions_out "$a/positions.bin" >/dev/null 2>&1 \
  || { echo "FAIL the uninterrupted run failed"; exit 1; }
located() { attr "$1" /breaks_located; }
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$b" -positions_out "$b/positions.bin" >/dev/null 2>&1 &
pid=$!
wait_for "$pid" '[[ -e "$b/checkpoint.h5" && "$(located "$b/checkpoint.h5")" =~ ^[1-9] ]]'
kill_run "$pid"
ck="$b/checkpoint.h5"
step=$(attr "$ck" /load_step)
# restarted A B WHAT: the killed run B restarted on 3 ranks from its checkpoint ends as the uninterrupted run A, bit for bit
restarted() {
  mpiexec -n 3 "$fabric" "${opts[@]}" -output_dir "$2" -positions_out "$2/positions.bin" -restart "$2/checkpoint.h5" >/dev/null 2>&1
  local rc=$?
  cmp -s "$1/positions.bin" "$2/positions.bin" && cmp -s "$1/curve.csv" "$2/curve.csv" \
    && echo "PASS restarted on 3 ranks $3 == uninterrupted, bit for bit" \
    || { echo "FAIL restarted $3 (exit $rc): positions or curve.csv differ"; fail=1; }
}
if [[ -e "$b/summary.json" || ! "$(located "$ck")" =~ ^[1-9] ]]; then
  echo "FAIL the run to be killed ended, or was stopped, before a checkpoint held a located break"; fail=1
else
  restarted "$a" "$b" "after load step $step (a located break in its checkpoint)"
fi
# 5. a checkpoint within a load step that locates a break after it (-checkpoint_every_te), restarted on 3 ranks
a="$work/te_whole" b="$work/te_killed"
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$a" -positions_out "$a/positions.bin" -info :sys >"$work/te_info" 2>&1 \
  || { echo "FAIL the uninterrupted run (-info) failed"; exit 1; }
# the rounds (load step:round) after which a break is located in the same load step, from rank 0's -info
pairs=$("$py" - "$work/te_info" <<'PY'
import re, sys
lines = [l for l in open(sys.argv[1]) if l.startswith("[0] <sys> ")]
pairs = set()
for k, l in enumerate(lines):
    m = re.search(r"RelaxRound\(\): load step (\d+), round (\d+) ", l)
    if m and any(f"LocateBreak(): load step {m.group(1)}: locating a break" in x for x in lines[k:]):
        pairs.add(f"{m.group(1)}:{m.group(2)}")
print(" ".join(sorted(pairs)))
PY
)
# a checkpoint within a load step: "S:R" (its load step and round); else "-"
within() {
  local a; a=($(attr "$1" /within_load_step /load_step /relax_round))
  [[ ${#a[@]} == 3 && ${a[0]} == 1 ]] && echo "$((a[1] + 1)):${a[2]}" || echo -
}
for try in 1 2 3; do # a poll that misses every qualifying checkpoint (a busy machine) tries again
  rm -rf "$b"
  mpiexec -n 2 "$fabric" "${opts[@]}" -checkpoint_every_te 50 -output_dir "$b" -positions_out "$b/positions.bin" >/dev/null 2>&1 &
  pid=$!
  wait_for "$pid" '[[ -e "$b/checkpoint.h5" && " $pairs " == *" $(within "$b/checkpoint.h5") "* ]]'
  kill_run "$pid"
  [[ ! -e "$b/summary.json" && " $pairs " == *" $(within "$b/checkpoint.h5") "* ]] && break
done
at=$(within "$b/checkpoint.h5")
if [[ -e "$b/summary.json" || " $pairs " != *" $at "* ]]; then
  echo "FAIL the run to be killed ended, or its checkpoint (load step:round $at) is not one with a break located after it in its load step ($pairs)"; fail=1
else
  restarted "$a" "$b" "from within load step:round $at (a break located later in that load step)"
fi
run 1 -scene "$inputs/strip_warp_rupture.yaml" -gauge_mm 30 -width_mm 20 -load_steps 30 -warp_break_cv_pct 25 \
  -output_dir "$work/frames" -output_te_every 200 -output_tear_every 200
"$py" - "$work/frames" <<'PY' || fail=1
import h5py, json, sys
d = sys.argv[1]
with h5py.File(f"{d}/fabric.h5", "r") as f:
    t = [tuple(f["frames"][k].attrs[a].item() for a in ("time_s", "load_step", "te_step")) for k in sorted(f["frames"])]
    n = f.attrs["frames"].item()
xmf = open(f"{d}/fabric.xmf").read().count("<Time ")
back = [(a, b) for a, b in zip(t, t[1:]) if b[0] <= a[0]]
located = json.load(open(f"{d}/summary.json"))["breaks_located"]
ok = not back and len(t) == n == xmf and located >= 1
print(("PASS" if ok else "FAIL") + f" frames with {located} located breaks: {len(t)} in fabric.h5 ({n} counted, {xmf} in fabric.xmf), "
      "times strictly increasing" + ("" if not back else f": not after {back[:3]}"))
sys.exit(0 if ok else 1)
PY
mpiexec -n 2 "$fabric" -quiet -scene "$inputs/strip_warp_rupture.yaml" -gauge_mm 30 -width_mm 20 -load_steps 30 \
  -warp_break_cv_pct 25 -output_dir "$work/tearframes" -output_every 0 -output_tear_every 50 -info :sys >"$work/info" 2>&1 \
  || { cat "$work/info"; echo "FAIL the tear-frames run failed"; fail=1; }
"$py" - "$work/tearframes/fabric.h5" "$work/info" <<'PY' || fail=1
import h5py, re, sys
log = open(sys.argv[2]).read()  # -info: every rank's lines, rank 0's counted
tears = [int(n) for n in re.findall(r"\[0\] <sys> FollowTear\(\): load step \d+: a tear of (\d+) te steps", log)]
steps = re.findall(r"\[0\] <sys> LocateBreak\(\): load step (\d+): locating a break", log)
with h5py.File(sys.argv[1], "r") as f:
    n = len(f["frames"])
want = 1 + sum(t // 50 for t in tears)
twice = len(steps) > len(set(steps))
ok = n == want and twice
print(("PASS" if ok else "FAIL") + f" tear frames: {n} in fabric.h5, the frame at rest and floor(n / 50) of each tear "
      f"({tears}): {want}; a load step with two located breaks: {twice}")
sys.exit(0 if ok else 1)
PY
exit $fail
