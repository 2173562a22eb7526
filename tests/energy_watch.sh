#!/usr/bin/env bash
# energy_watch.sh FABRIC: the energy watch (balance.c, docs/stability.md) stops a damped run that
# pumps energy at the yarn law's kink, with one clear message naming the cause and the crossing,
# the same on 1 and 2 ranks, and it does not stop a run that does not pump.
# The case: inputs/square_net.yaml scaled to 51 x 51 crossings, its 0.5 N in one load step,
# -integrator damped -damping_ratio 0.01 (below the net's best ratio: the ring at the kink at zero
# strain gains energy; measured: H rises from -3.408e-4 J, stopped at te step 8961).
# The level ring: the same net at 101 x 101 crossings with -damping_ratio 0.01 -te_safety 0.5, whose
# H reaches its lowest (-5.8578e-4 J) by te step 24 577 and then rises far below the first test's
# bound (measured: 3.3e-6 J by te step 59 905, against 0.5 x 7.9e-4 J; without the second test it
# ran its 200 000 te steps, flagged); stopped at te step 33 025 by the second test (H above its
# lowest at 32 watched te steps in a row).
set -u
fabric="$1"
here="$(cd "$(dirname "$0")/.." && pwd)"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
net=(-scene "$here/inputs/square_net.yaml" -gauge_mm 20.8333333 -width_mm 20.8333333 -load_steps 1
     -max_inner_steps 100000 -integrator damped -output_every 0 -quiet)
fail=0
for np in 1 2; do
  mpiexec -n $np "$fabric" "${net[@]}" -damping_ratio 0.01 -output_dir "$work/np$np" >"$work/log$np" 2>&1; rc=$?
  msg="$(grep '^fabric: error:' "$work/log$np")"
  echo "$np rank(s): exit $rc: ${msg:0:160}..."
  if [[ $rc -ne 0 && $(grep -c '^fabric: error:' "$work/log$np") -eq 1 ]] &&
     [[ $msg =~ "energy watch: at load step 1, te step "[0-9]+" of its relaxation, the mechanical energy has grown" ]] &&
     [[ $msg =~ "moves most at crossing ("[0-9]+", "[0-9]+")" && $msg == *"yarn law's kink"* && $msg == *"-integrator fire"* ]]; then
    echo "PASS $np rank(s): stopped by the energy watch, one message naming the crossing and the kink"
  else echo "FAIL $np rank(s): expected a non-zero exit and one 'fabric: error: energy watch: ...' line"; fail=1; fi
  if /usr/bin/python3 -c "import json,sys; s=json.load(open('$work/np$np/summary.json')); sys.exit(not (s['converged'] is False and s['error'].startswith('energy watch')))"; then
    echo "PASS $np rank(s): summary.json says not converged and carries the message"
  else echo "FAIL $np rank(s): summary.json does not record the stop"; fail=1; fi
done
if [[ "$(grep '^fabric: error:' "$work/log1")" == "$(grep '^fabric: error:' "$work/log2")" ]]; then
  echo "PASS the same stop on 1 and 2 ranks (te step, energies, crossing, strains)"
else echo "FAIL the stop differs between 1 and 2 ranks"; fail=1; fi
# the watch off: the same run goes past the te step where it stopped
mpiexec -n 1 "$fabric" "${net[@]}" -damping_ratio 0.01 -energy_watch 0 -max_inner_steps 12000 -output_dir "$work/off" >"$work/logoff" 2>&1 \
  && echo "PASS -energy_watch 0: the run goes on to its 12000 te steps (exit 0)" || { echo "FAIL -energy_watch 0 did not finish"; fail=1; }
# no false alarm: a damping that does not pump (0.05) runs on, watched
mpiexec -n 1 "$fabric" "${net[@]}" -damping_ratio 0.05 -max_inner_steps 20000 -output_dir "$work/ok" >"$work/logok" 2>&1 \
  && echo "PASS damping 0.05: watched, not stopped (exit 0)" || { echo "FAIL damping 0.05 stopped: $(grep error "$work/logok")"; fail=1; }
# the level ring: stopped by the held test, within 40 000 te steps
mpiexec -n 1 "$fabric" "${net[@]}" -gauge_mm 41.6666667 -width_mm 41.6666667 -damping_ratio 0.01 -te_safety 0.5 \
  -max_inner_steps 40000 -output_dir "$work/ring" >"$work/logring" 2>&1; rc=$?
msg="$(grep '^fabric: error:' "$work/logring")"
if [[ $rc -ne 0 && $msg =~ "energy watch: at load step 1, te step "[0-9]+" of its relaxation" &&
      $msg == *"has stayed above it for the last 8192 te steps"* && $msg == *"yarn law's kink"* ]]; then
  echo "PASS level ring (101 x 101, damping 0.01, te 0.5): stopped: ${msg:22:100}"
else echo "FAIL level ring: expected the held stop, got exit $rc: ${msg:0:200}"; fail=1; fi
exit $fail
