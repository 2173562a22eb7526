#!/usr/bin/env bash
# scripts_args.sh CASE FABRIC: a script of scripts/ given bad arguments, or whose runs cannot give
# its table, stops with one clear message on stderr and a non-zero exit status (the shell scripts: 2
# for a bad argument, before any run; 1 when the runs cannot give the table), checked exactly: never a Python
# traceback, a silent success, or a table that the runs do not support. The scripts run FABRIC
# (FABRIC=...), from a directory other than the repository's root.
set -u
case_="$1"; export FABRIC="$2"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
fail=0
expect() { # RC MESSAGE COMMAND...: exit status RC, and MESSAGE the whole of stderr
  local want_rc="$1" want="$2" rc; shift 2
  "$@" >"$work/out" 2>"$work/err"; rc=$?
  if [[ $rc -eq $want_rc && "$(cat "$work/err")" == "$want" ]]; then
    echo "PASS ${*#"$root/"}: exit $rc, $want"
  else
    echo "FAIL ${*#"$root/"}: exit $rc (expected $want_rc); stdout:"; cat "$work/out"; echo "stderr:"; cat "$work/err"
    echo "expected stderr: $want"; fail=1
  fi
}
# stopped_whole NAME RANKS MESSAGE COMMAND...: COMMAND (a Python script whose runs have sessions of their own) started in
# a session of its own, SIGINT at its default, and sent SIGINT to its group once RANKS of its ranks run, as a terminal's
# Ctrl-C: exit 130, MESSAGE its whole stderr, and no run of it (mpiexec, ranks) left a second later
stopped_whole() {
  local name="$1" ranks="$2" msg="$3" pid rc t0 left; shift 3
  runs() { pgrep -d, -f -- "-output_dir $work/tmp/"; }
  TMPDIR="$work/tmp" /usr/bin/python3 -c 'import os, signal, sys; signal.signal(2, signal.SIG_DFL); os.setsid(); os.execvp(sys.argv[1], sys.argv[1:])' \
    "$@" >"$work/out" 2>"$work/err" &
  pid=$!
  for _ in $(seq 300); do [[ $(pgrep -c -f -- "^$FABRIC .*-output_dir $work/tmp/") -ge $ranks ]] && break; sleep 0.1; done
  [[ -n "$(runs)" ]] || { echo "FAIL $name's run did not start within 30 s"; fail=1; }
  kill -INT -- "-$pid"; t0=$SECONDS
  wait "$pid"; rc=$?
  if [[ $rc -eq 130 && "$(cat "$work/err")" == "$msg" ]]; then
    echo "PASS $name interrupted: exit 130 in $((SECONDS - t0)) s, $msg"
  else echo "FAIL $name interrupted: exit $rc (expected 130); stderr:"; cat "$work/err"; fail=1; fi
  sleep 1; left="$(runs)"
  if [[ -n $left ]]; then
    echo "FAIL $name interrupted left its run going:"; ps -o pid,ppid,args -p "$left" | cut -c1-120; fail=1
    kill ${left//,/ } 2>/dev/null; sleep 2; left="$(runs)"; [[ -z $left ]] || kill -KILL ${left//,/ } 2>/dev/null
  else echo "PASS $name interrupted: no mpiexec or rank left"; fi
}
small_pushing=(-ends_per_cm 4 -picks_per_cm 4 -load_steps 2 -sphere_travel_mm 3)
case "$case_" in
  tradeoff)
    t="$root/scripts/tradeoff.sh"
    # the table's file forgotten: the first option was taken for it (and its value passed on alone)
    expect 2 "scripts/tradeoff.sh: table.csv '-predict': an option, not a file name (give the table's file first, or \"\" for none)" \
      "$t" pushing -predict linear
    # a table that cannot be written: a traceback once every run had ended
    expect 2 "scripts/tradeoff.sh: usage: scripts/tradeoff.sh pushing|bias|drape [table.csv [options...]] (--help)" "$t"
    expect 0 "" "$t" --help
    grep -q "^The explicit path's speed/accuracy trade" "$work/out" || { echo "FAIL tradeoff.sh --help printed: $(head -1 "$work/out")"; fail=1; }
    expect 2 "scripts/tradeoff.sh: table.csv 'no/t.csv': no directory no" "$t" bias no/t.csv
    expect 2 "scripts/tradeoff.sh: table.csv '$work': a directory" "$t" bias "$work"
    # a pushing test that stops before 5 mm: max() of no row, a traceback after every run
    expect 1 "scripts/tradeoff.sh: the reference run (-solver static -balance_tol 1e-8 ${small_pushing[*]}) reaches no load step at 5 mm of travel or more (the force error is taken from 5 mm on); nothing to measure against" \
      "$t" pushing "" "${small_pushing[@]}"
    # LIMIT_S=0 took off the limit, a word failed every run with timeout's message; RANKS=0 ran on every slot
    expect 2 "scripts/tradeoff.sh: LIMIT_S '0': a run's time limit, a positive number of seconds (or with a unit: 5m)" env LIMIT_S=0 "$t" bias
    expect 2 "scripts/tradeoff.sh: RANKS '0': the number of ranks, a positive integer" env RANKS=0 "$t" bias
    expect 2 "scripts/tradeoff.sh: LIMIT_S '5x': a run's time limit, a positive number of seconds (or with a unit: 5m)" env LIMIT_S=5x "$t" bias
    expect 2 "scripts/tradeoff.sh: FABRIC '$work': not an executable file" env FABRIC="$work" "$t" bias
    # timeout's own forms run (an exponent, a unit): the reference's error, not the limit's
    expect 1 "scripts/tradeoff.sh: the reference run (-solver static -balance_tol 1e-8 -gauge_mm abc) stopped: fabric: error: -gauge_mm abc: not a number; nothing to measure against" \
      env LIMIT_S=1e1m "$t" bias "" -gauge_mm abc
    ;;
  bench_pushing)
    expect 1 "bench_pushing.sh: the reference run reaches no load step at 5 mm of travel or more: no force error from 5 mm on" \
      "$root/scripts/bench_pushing.sh" "${small_pushing[@]}"
    # a run that fails says fabric's message (it said mpiexec's footer: "Process name: ... Exit code: 1")
    expect 1 "bench_pushing.sh: run static_1e-8 failed: fabric: error: -gauge_mm abc: not a number" \
      "$root/scripts/bench_pushing.sh" -gauge_mm abc
    # RANKS=0 ran on every slot; a FABRIC that is no program: every run failed to start, FABRIC unnamed
    expect 2 "bench_pushing.sh: RANKS '0': the number of ranks, a positive integer" env RANKS=0 "$root/scripts/bench_pushing.sh"
    expect 2 "bench_pushing.sh: FABRIC '$work': not an executable file" env FABRIC="$work" "$root/scripts/bench_pushing.sh"
    ;;
  bench_drape_static)
    # a run that fails says fabric's message (not mpiexec's footer), and the row's options
    expect 1 "bench_drape_static.sh: run 1 (-snes_max_it 1000) failed: fabric: error: -gauge_mm abc: not a number" \
      "$root/scripts/bench_drape_static.sh" -gauge_mm abc
    expect 0 "" "$root/scripts/bench_drape_static.sh" --help
    grep -q "^The drape (inputs/drape.yaml, 2 threads/cm" "$work/out" || { echo "FAIL bench_drape_static.sh --help printed: $(head -1 "$work/out")"; fail=1; }
    # the header only, its usage line last (the help of the benchmark scripts printed their own "case" line after it)
    [[ "$(tail -1 "$work/out")" == "usage: scripts/bench_drape_static.sh [extra options for every run, e.g. -contact_stiffness_N_m 200]" ]] ||
      { echo "FAIL bench_drape_static.sh --help ended with: $(tail -1 "$work/out")"; fail=1; }
    ;;
  plot_tradeoff)
    printf 'knob,value,balanced,wall_s,te_steps,force_err_pct\nreference,static 1e-8,true,1.98,-,0.0000\nbase,-,true,0.41,973,0.0001\n' >t.csv
    # an image that cannot be written: matplotlib's traceback
    expect 1 "plot_tradeoff.py: -o no/f.png: No such file or directory" /usr/bin/python3 "$root/scripts/plot_tradeoff.py" t.csv -o no/f.png
    # the formats as this matplotlib lists them (each version has its own: 3.6's are eps ... webp)
    formats=$(/usr/bin/python3 -c 'import matplotlib; matplotlib.use("Agg"); import matplotlib.pyplot as plt; print(", ".join(sorted(plt.figure().canvas.get_supported_filetypes())))')
    expect 1 "plot_tradeoff.py: -o f.xyz: Format 'xyz' is not supported (supported formats: $formats)" \
      /usr/bin/python3 "$root/scripts/plot_tradeoff.py" t.csv -o f.xyz
    expect 0 "" /usr/bin/python3 "$root/scripts/plot_tradeoff.py" t.csv -o "f g.png"
    [[ -s "f g.png" ]] || { echo "FAIL plot_tradeoff.py wrote no f g.png"; fail=1; }
    ;;
  bench_static)
    b="$root/scripts/bench_static.sh"
    # an option without its value: bash's "$2: unbound variable"; a size that is no grid: fabric's
    # message in a log the script removed, and exit 1 without a word
    expect 2 "bench_static.sh: option -static_sequence without its value (options before the sizes are -option value pairs)" "$b" -static_sequence
    expect 2 "bench_static.sh: size 'abc': the crossings along a side, a whole number from 3" "$b" 11 abc
    # a run that fails: it was left without a word as well
    LOAD_STEPS=2 expect 1 "bench_static.sh: the run of 11x11 crossings failed: fabric: error: -pc_type cg with -solver static: not a preconditioner PETSc knows (see -help)" \
      "$b" -pc_type cg 11
    # the same size twice: p = log(t2/t1)/log(1) printed as -inf or nan
    LOAD_STEPS=1 expect 0 "" "$b" 9 9
    [[ "$(awk '$1 == "9x9" {print $(NF - 1), $NF}' "$work/out" | tr '\n' ' ')" == "- - - - " ]] && echo "PASS bench_static.sh 9 9: no ratio, no p" ||
      { echo "FAIL bench_static.sh 9 9 printed:"; cat "$work/out"; fail=1; }
    ;;
  drape_grid)
    d="$root/scripts/drape_grid.sh"
    expect 2 "drape_grid.sh: option -balance_tol without its value (options before the densities are -option value pairs)" "$d" -balance_tol
    expect 2 "drape_grid.sh: density '0': threads/cm, a decimal number above 0 (digits and a point)" "$d" 2 0
    # ranks from the environment: a word went to mpiexec, which printed its usage
    expect 2 "drape_grid.sh: RANKS 'abc': the number of ranks, a positive integer" env RANKS=abc "$d" 2
    expect 1 "drape_grid.sh: the run at 2 threads/cm failed: fabric: error: -gauge_mm abc: not a number" "$d" -gauge_mm abc 2
    # a run cut short: its row, read from its summary.json, says it did not balance
    expect 0 "" "$d" -max_inner_steps 50 2
    grep -Eq '^2 +61x61 +2821 +[0-9.e+-]+ +50 .* false$' "$work/out" || { echo "FAIL drape_grid.sh printed:"; cat "$work/out"; fail=1; }
    ;;
  bench_relax)
    b="$root/scripts/bench_relax.sh"
    # --table 3 printed nothing and exited 0; a flag at the end: bash's "$2: unbound variable"
    expect 2 "bench_relax.sh: --table '3': 1 or 2" "$b" --table 3
    expect 2 "bench_relax.sh: --table without its value (--table 1|2, --np N)" "$b" --np 1 --table
    expect 2 "bench_relax.sh: --np 'x': a positive number of ranks" "$b" --np x
    # a run that leaves no results: a "failed" row and exit 0; KEEP a file: mkdir's own words
    printf '#!/bin/sh\necho "fabric: error: planted" >&2\nexit 1\n' >fake && chmod +x fake
    expect 1 "bench_relax.sh: run net_d0.02 left no results: fabric: error: planted" env FABRIC="$work/fake" "$b" --table 1 --np 1
    echo text >file
    expect 2 "bench_relax.sh: KEEP 'file': cannot make that directory" env KEEP=file "$b" --table 1
    ;;
  stability_sweep)
    # --keep naming a file: a traceback from the first case (FileExistsError)
    echo text >file
    # argparse's usage above the error: its text and wrapping are the Python version's and the terminal's (3.13
    # rewrote how usage is laid out), so the usage is taken from the script's own -h, laid out alike
    usage="$("$root/scripts/stability_sweep.sh" -h | sed -n '1,/^$/p' | sed '$d')"
    expect 2 "$usage
stability_sweep.py: error: argument --keep: $work/file: not a directory" "$root/scripts/stability_sweep.sh" -fast --keep file --fabric "$FABRIC"
    ;;
  scene_times)
    # a scene file of one's own named like a shipped one: the shipped one was timed (its directory dropped)
    mkdir own && cp "$root/inputs/bias.yaml" own/
    expect 2 "scene_times.sh: scene 'own/bias.yaml@1': only the scenes of inputs/ (strip_warp, strip_warp.yaml or inputs/strip_warp.yaml)" \
      "$root/scripts/scene_times.sh" strip_warp own/bias.yaml@1
    expect 2 "scene_times.sh: unknown option '-x' (--static, first, is the only one; --help)" "$root/scripts/scene_times.sh" -x
    # --static: the quasi-static row after the explicit one, both at the 25 x 25 net's deflection
    # under 0.5 N, 0.564165069 mm (docs/static.md), to the 5 digits printed
    expect 0 "" "$root/scripts/scene_times.sh" --static square_net@1
    rows="$(awk '$1 == "square_net" {print $2, $9, $10, $11, ($2 == "static" && $7 > 0 ? "newton" : "-")}' "$work/out")"
    want="$(printf 'explicit yes 0.56417 mm -\nstatic yes 0.56417 mm newton')"
    [[ $rows == "$want" ]] && echo "PASS scene_times.sh --static: $(tr '\n' ';' <<<"$rows")" ||
      { echo "FAIL scene_times.sh --static printed:"; cat "$work/out"; fail=1; }
    ;;
  te_table)
    # inputs/NAME.yaml from a directory other than the root: refused as not a scene of inputs/
    expect 2 "te_table.sh: scene 'inputs/nothere.yaml': no inputs/nothere.yaml" "$root/scripts/te_table.sh" inputs/nothere.yaml
    mkdir own && cp "$root/inputs/bias.yaml" own/
    expect 2 "te_table.sh: scene 'own/bias.yaml': only the scenes of inputs/ (bias, bias.yaml or inputs/bias.yaml)" \
      "$root/scripts/te_table.sh" own/bias.yaml
    # NP=0 ran and labelled the table "0 ranks"; a word stopped every row with mpiexec's separator line
    expect 2 "te_table.sh: NP '0': the number of ranks, a positive integer" env NP=0 "$root/scripts/te_table.sh" bias
    # a FABRIC that is no program: a "(stopped)" row per scene, each with mpiexec's "failed to start"
    expect 2 "te_table.sh: FABRIC '$work': not an executable file" env FABRIC="$work" "$root/scripts/te_table.sh" bias
    ;;
  interrupt)
    # Ctrl-C (SIGINT to the script's process group, as a terminal sends it) stops the script at once, with its
    # runs: te_table.sh went on to the next scene after a "(stopped)" row, tradeoff.sh (its runs under timeout,
    # in a group of their own) ran every row; exit 130, "interrupted", no process of it left, no table file
    for s in "te_table.sh strip_warp square_net" "tradeoff.sh bias $work/t.csv" "bench_pushing.sh" "bench_relax.sh --table 1 --np 1"; do
      read -ra cmd <<<"$s"
      /usr/bin/python3 -c 'import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL); os.setsid(); os.execvp(sys.argv[1], sys.argv[1:])' \
        "$root/scripts/${cmd[0]}" "${cmd[@]:1}" >"$work/out" 2>"$work/err" &
      pid=$!
      sleep 2.5; kill -INT -- -"$pid"; wait "$pid"; rc=$?
      # its ranks stop at their next step (a SIGTERM from mpiexec): within 5 s (zombies are dead, not yet reaped by init)
      for _ in 1 2 3 4 5 6 7 8 9 10; do left="$(ps -o stat= -s "$pid" | grep -vc '^Z')"; ((left == 0)) && break; sleep 0.5; done
      if [[ $rc == 130 && "$(tail -1 "$work/err")" == *"${cmd[0]}: interrupted" && $left == 0 && ! -e $work/t.csv ]] &&
        ! grep -q '(stopped)' "$work/out"; then
        echo "PASS ${cmd[0]} interrupted: exit 130, nothing left"
      else
        echo "FAIL ${cmd[0]} interrupted: exit $rc, $left processes left; stdout:"; cat "$work/out"; echo "stderr:"; cat "$work/err"; fail=1
      fi
      pkill -KILL -s "$pid" 2>/dev/null
    done
    ;;
  plot_curve)
    # -o without an extension: matplotlib wrote curve.png, the script printed "curve"
    mkdir plot && cd plot || exit 1
    printf "load_step,time_s,elongation_pct,force_N,inner_steps,residual,balanced\n1,1,1,1,1,0,1\n" >c.csv
    expect 0 "" /usr/bin/python3 "$root/scripts/plot_curve.py" c.csv -o curve
    if [[ "$(cat "$work/out")" == curve.png && -s curve.png && ! -e curve ]]; then echo "PASS plot_curve.py -o curve printed curve.png, the file it wrote"
    else echo "FAIL plot_curve.py -o curve printed '$(cat "$work/out")', wrote: $(ls)"; fail=1; fi
    # without -o: curve.png beside the curve (the extension added above made it curve.png.png)
    mkdir run && cp c.csv run/curve.csv && rm -f curve.png
    expect 0 "" /usr/bin/python3 "$root/scripts/plot_curve.py" run/curve.csv
    if [[ "$(cat "$work/out")" == "$PWD/run/curve.png" && -s run/curve.png && "$(ls run)" == "$(printf 'curve.csv\ncurve.png')" ]]; then
      echo "PASS plot_curve.py without -o wrote and printed run/curve.png"
    else echo "FAIL plot_curve.py without -o printed '$(cat "$work/out")', wrote: $(ls run)"; fail=1; fi
    # -o DIR: DIR/curve.png (it wrote DIR.png beside it)
    mkdir figs && expect 0 "" /usr/bin/python3 "$root/scripts/plot_curve.py" c.csv -o figs
    [[ "$(cat "$work/out")" == figs/curve.png && -s figs/curve.png && ! -e figs.png ]] && echo "PASS plot_curve.py -o figs wrote figs/curve.png" ||
      { echo "FAIL plot_curve.py -o figs printed '$(cat "$work/out")', wrote: $(ls)"; fail=1; }
    # a fabric curve.csv as --measured: its load_step and time_s were plotted as measured points
    expect 1 "plot_curve.py: --measured run/curve.csv: a fabric curve.csv, not a measured curve (x, force N): give it as a curve, before the options" \
      /usr/bin/python3 "$root/scripts/plot_curve.py" c.csv --measured run/curve.csv
    # the maximum marked when summary.json's is above every row (a located break between two load steps, no
    # rupture: it was marked only with a rupture), and not when it is the curve's own largest force
    printf '{"max_force_N": 1.5, "travel_at_max_force_mm": 0.8, "rupture": null}\n' >run/summary.json
    here="$PWD"; got="$(cd "$root/scripts" && PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 -c "import plot_curve; print(plot_curve.read_maximum('$here/run/curve.csv', [0.0, 1.0]), plot_curve.read_maximum('$here/run/curve.csv', [0.0, 1.5]))")"
    [[ "$got" == "(0.8, 1.5, 'maximum 1.5 N at 0.8 mm') None" ]] && echo "PASS plot_curve.py marks a maximum above the rows: $got" ||
      { echo "FAIL plot_curve.py read_maximum gave: $got"; fail=1; }
    ;;
  slack_census)
    c="$root/scripts/slack_census.py"
    expect 1 "slack_census.py: no.h5: no such file" /usr/bin/python3 "$c" no.h5
    expect 1 "slack_census.py: $work: a directory" /usr/bin/python3 "$c" "$work"
    printf 'x\n' >x.h5
    expect 1 "slack_census.py: x.h5: not an HDF5 file" /usr/bin/python3 "$c" x.h5
    # a grid of 3 rows by 4 columns, spacing 1 along x and 2 along y, with absent (-1), clamped (1), free (0)
    # and grip (2) crossings, stretched by 1.5 along x and 0.5 along y: 6 x segments (strain +0.5) and 5 y
    # segments (-0.5) have a free end and no absent one (counted by hand); frame 1 was cut short
    /usr/bin/python3 - <<'PY' || { echo "FAIL could not write the test's fabric.h5"; fail=1; }
import h5py, numpy as np
kind = np.array([[-1, 1, 0, 2], [0, 0, 0, 1], [1, 0, -1, 0]], dtype=float)
j, i = np.mgrid[0:3, 0:4]
rest = np.stack([i * 1.0, j * 2.0, 0 * i], axis=2)
with h5py.File("grid.h5", "w") as f:
    f["grid/point_kind"], f["grid/rest_positions"] = kind, rest
    f["frames/000000/positions"] = rest * np.array([1.5, 0.5, 1.0])
    f.create_group("frames/000001")
    f.attrs["frames"] = 1
PY
    expect 0 "" /usr/bin/python3 "$c" grid.h5
    want="frame 0: 11 segments with a free end, 5 compressed (e < 0); |e| < 0.0001: 0, |e| < 1e-05: 0, |e| < 1e-06: 0, |e| < 1e-07: 0"
    [[ "$(cat "$work/out")" == "$want" ]] && echo "PASS slack_census.py on the 3 x 4 grid: $want" || { echo "FAIL slack_census.py on the 3 x 4 grid printed: $(cat "$work/out")"; fail=1; }
    expect 1 "slack_census.py: --frame 1: not in grid.h5 (its frames written whole: 0 to 0)" /usr/bin/python3 "$c" grid.h5 --frame 1
    # the square net (25 x 25 crossings, its four edges clamped): 2 x 25 x 24 segments, less the
    # 4 x 24 along the edges, have a free end; at rest (frame 0) every chord strain is exactly 0
    "$FABRIC" -scene "$root/inputs/square_net.yaml" -solver static -load_steps 2 -quiet -output_dir run >run.log 2>&1 ||
      { echo "FAIL the square net's run failed:"; cat run.log; fail=1; }
    expect 1 "slack_census.py: --frame 3: not in run/fabric.h5 (its frames written whole: 0 to 2)" /usr/bin/python3 "$c" run/fabric.h5 --frame 3
    expect 1 "slack_census.py: run/curve.csv: not an HDF5 file" /usr/bin/python3 "$c" run/curve.csv
    head -c 1000 run/fabric.h5 >cut.h5
    expect 1 "slack_census.py: cut.h5: a truncated HDF5 file" /usr/bin/python3 "$c" cut.h5
    # the file a run killed while writing its last frame leaves: the superblock's end of file before that
    # frame's group, which then cannot be opened (a KeyError traceback); the last whole frame is taken
    cp run/fabric.h5 eoa.h5
    /usr/bin/python3 - <<'PY' || { echo "FAIL could not cut eoa.h5"; fail=1; }
import h5py, struct
with h5py.File("eoa.h5", "r") as f:
    addr = h5py.h5o.get_info(f["frames/000002"].id).addr
with open("eoa.h5", "r+b") as fh:
    assert fh.read(9)[8] == 0  # superblock version 0: the end-of-file address at byte 40
    fh.seek(40)
    fh.write(struct.pack("<Q", addr))
PY
    expect 0 "" /usr/bin/python3 "$c" eoa.h5
    grep -q '^frame 1: 1104 segments' "$work/out" && echo "PASS slack_census.py: a frame cut by the end of file passed over" ||
      { echo "FAIL slack_census.py on eoa.h5 printed: $(cat "$work/out")"; fail=1; }
    expect 0 "" /usr/bin/python3 "$c" run/fabric.h5 --frame 0
    want="frame 0: 1104 segments with a free end, 0 compressed (e < 0); |e| < 0.0001: 1104, |e| < 1e-05: 1104, |e| < 1e-06: 1104, |e| < 1e-07: 1104"
    [[ "$(cat "$work/out")" == "$want" ]] && echo "PASS slack_census.py at rest: $want" || { echo "FAIL slack_census.py at rest printed: $(cat "$work/out")"; fail=1; }
    # the net stretched under its load, the last frame by default: every segment taut (the least strain
    # about 2e-5), none compressed
    expect 0 "" /usr/bin/python3 "$c" run/fabric.h5
    grep -Eq '^frame 2: 1104 segments with a free end, 0 compressed \(e < 0\); .*\|e\| < 1e-06: 0, \|e\| < 1e-07: 0$' "$work/out" &&
      echo "PASS slack_census.py: the last frame, taut" || { echo "FAIL slack_census.py loaded printed: $(cat "$work/out")"; fail=1; }
    ;;
  bias_table)
    # a run that stopped on an error after two load steps: its table ended as a whole run's, with exit 0
    mkdir run && printf 'load_step,time_s,travel_mm,force_N,inner_steps,residual,balanced,center_shear_deg\n1,1,1,0.5,10,0,1,2.0\n2,2,2,0.9,12,0,1,4.1\n' >run/curve.csv
    printf '{"gauge_mm": 150, "width_mm": 50, "converged": false, "error": "-te 1 s is above the stable bound"}\n' >run/summary.json
    expect 1 "bias_table.py: run: the run stopped after 2 load steps: -te 1 s is above the stable bound" /usr/bin/python3 "$root/scripts/bias_table.py" run
    [[ $(wc -l <"$work/out") -eq 3 ]] || { echo "FAIL bias_table.py printed $(wc -l <"$work/out") lines, not its head and 2 rows"; fail=1; }
    sed -i 's/, "error": "[^"]*"//; s/false/true/' run/summary.json
    expect 0 "" /usr/bin/python3 "$root/scripts/bias_table.py" run
    [[ $(tail -n 1 "$work/out") == "every load step balanced: yes; D = 100.000 mm" ]] || { echo "FAIL bias_table.py's last line: $(tail -n 1 "$work/out")"; fail=1; }
    # a row cut short (a run stopped while writing it): said, naming the line (it was a TypeError traceback)
    printf '3,3,3,1.2' >>run/curve.csv
    expect 1 "bias_table.py: run/curve.csv: line 4 is not a whole row of numbers (a run stopped while writing it?): 3,3,3,1.2" \
      /usr/bin/python3 "$root/scripts/bias_table.py" run
    # a rupture in load step 3 (its row the tear's, not balanced): it said "every load step balanced: yes" from
    # summary.json's converged (every load step before the rupture) and compared the tear with the formula
    mkdir torn && head -n 3 run/curve.csv >torn/curve.csv && printf '3,3,3,0.4,99,0.5,0,5.0\n' >>torn/curve.csv
    printf '{"gauge_mm": 150, "width_mm": 50, "converged": true, "max_force_N": 0.95, "elongation_at_max_force_pct": 2.9, "rupture": {"load_step": 3, "time_s": 3, "elongation_pct": 3, "force_N": 0.4}}\n' >torn/summary.json
    expect 0 "" /usr/bin/python3 "$root/scripts/bias_table.py" torn
    want="$(printf '%11s %11s %11s %11s %11s %11s' 3.00 3.49 5.00 - 0.4 '99*')
every load step before the rupture balanced: yes; D = 100.000 mm
ruptured in load step 3, at 3 % elongation (its row: the tear's end); maximum force 0.95 N at 2.9 %"
    [[ "$(tail -n 3 "$work/out")" == "$want" ]] && echo "PASS bias_table.py on a rupture: its row marked, no difference" ||
      { echo "FAIL bias_table.py on a rupture printed:"; cat "$work/out"; echo "expected the last lines:"; echo "$want"; fail=1; }
    ;;
  bias_convergence)
    # its arguments are densities: a bad one named as the script's (it went to fabric: "-ends_per_cm abc: not a number")
    expect 2 "bias_convergence.sh: 'abc': not a thread density (a number of threads/cm above 0; --help)" "$root/scripts/bias_convergence.sh" abc
    expect 2 "bias_convergence.sh: '0': not a thread density (a number of threads/cm above 0; --help)" "$root/scripts/bias_convergence.sh" 4 0
    expect 2 "bias_convergence.sh: NP '0': the number of ranks, a positive integer" env NP=0 "$root/scripts/bias_convergence.sh" 4
    expect 0 "" "$root/scripts/bias_convergence.sh" --help
    grep -q "^Grid convergence of the bias extension test" "$work/out" || { echo "FAIL bias_convergence.sh --help printed: $(head -2 "$work/out")"; fail=1; }
    ;;
  setup)
    # it ran the install and the build whatever it was given (--help too)
    expect 2 "setup.sh: usage: scripts/setup.sh (no arguments; --help)" "$root/scripts/setup.sh" --prefix /tmp
    expect 0 "" "$root/scripts/setup.sh" --help
    grep -q "^Install what is missing" "$work/out" || { echo "FAIL setup.sh --help printed: $(head -2 "$work/out")"; fail=1; }
    ;;
  stability_sweep_stop)
    usage="$("$root/scripts/stability_sweep.sh" -h | sed -n '1,/^$/p' | sed '$d')"
    # a directory as --fabric passed an os.access(X_OK) check: every case was then BAD
    expect 2 "$usage
stability_sweep.py: error: argument --fabric: $work: a directory, not an executable" "$root/scripts/stability_sweep.sh" -fast --fabric "$work"
    # Ctrl-C (SIGINT to the terminal's foreground process group) during a 2-rank run: it gave a
    # KeyboardInterrupt traceback and left mpiexec and the ranks running, orphans writing into the
    # removed temporary directory. The run (365 s whole) is interrupted once its ranks have started.
    mkdir tmp
    stopped_whole stability_sweep.sh 2 "stability_sweep: interrupted" "$root/scripts/stability_sweep.sh" --only "energy watch off" --fabric "$FABRIC"
    # (Open MPI keeps its own session directory, ompi.*, in TMPDIR)
    left="$(cd tmp && ls -d stability_sweep.* 2>/dev/null)"
    [[ -z $left ]] && echo "PASS stability_sweep.sh interrupted: its temporary directory removed" ||
      { echo "FAIL stability_sweep.sh interrupted left: $left"; fail=1; }
    ;;
  bench_speedups)
    # in a tree of its own (the script writes ROOT/results/bench): its inputs, and as build/fabric FABRIC
    # with -max_inner_steps 50 added (the last given wins) to every run, or to every run but the reference
    mkdir -p repo/scripts repo/build tmp && cp "$root/scripts/bench_speedups.py" "$root/scripts/runstop.py" repo/scripts/ && ln -s "$root/inputs" repo/inputs
    py="$work/repo/scripts/bench_speedups.py"
    cut() { # all | not_reference
      printf '#!/bin/bash\n' >repo/build/fabric
      [[ $1 == all ]] && printf 'set -- "$@" -max_inner_steps 50\n' >>repo/build/fabric ||
        printf '[[ " $* " == *" -balance_tol 1e-8 "* ]] || set -- "$@" -max_inner_steps 50\n' >>repo/build/fabric
      printf 'exec %q "$@"\n' "$FABRIC" >>repo/build/fabric; chmod +x repo/build/fabric
    }
    no_tmp() { # the temporary outputs removed
      local left; left="$(cd tmp && ls -d bench_speedups_* 2>/dev/null)"
      [[ -z $left ]] && echo "PASS bench_speedups.py $1: nothing left in TMPDIR" || { echo "FAIL bench_speedups.py $1 left: $left"; fail=1; }
    }
    # results/bench a file: a FileExistsError traceback, and the temporary directory (made first) left behind
    mkdir repo/results && : >repo/results/bench
    expect 1 "bench_speedups: $work/repo/results/bench: not a directory (Table 2 writes its PNG there)" env TMPDIR="$work/tmp" /usr/bin/python3 "$py" --quick --tables 2
    no_tmp "with results/bench a file"
    rm repo/results/bench
    # a reference that does not balance: its errors were taken as the truth (it hit the default
    # -max_inner_steps 20000 in load step 1; it now has 400000, and is checked)
    cut all
    expect 1 "bench_speedups: the reference of strip_warp.yaml (-width_mm 2 -predict linear -balance_tol 1e-8 -speed_tol 1e-8 -max_inner_steps 400000) did not balance load steps 1, 2, 3, 4, 5, ... of 50: no reference to measure errors against, no table" \
      env TMPDIR="$work/tmp" /usr/bin/python3 "$py" --quick --tables 2
    # Table 2 says which rows balanced: here none (50 te steps per load step), each flagged false
    cut not_reference
    expect 0 "" env TMPDIR="$work/tmp" /usr/bin/python3 "$py" --quick --tables 2
    if grep -Eq "^balance_tol +te_safety +wall_s +te_steps +max_N' +err_%peak +balanced$" "$work/out" &&
       [[ $(grep -Ec '^ *1e-[234] +0\.[59] .* 50 +[0-9.]+ +false$' "$work/out") -eq 6 && -s repo/results/bench/speedups_trade.png ]]; then
      echo "PASS bench_speedups.py --quick --tables 2: 6 rows, each balanced false"
    else echo "FAIL bench_speedups.py --quick --tables 2 printed:"; cat "$work/out"; fail=1; fi
    no_tmp "--quick --tables 2"
    # Ctrl-C during the reference's run: a KeyboardInterrupt traceback
    stopped_whole bench_speedups.py 1 "bench_speedups: interrupted" /usr/bin/python3 "$py" --quick --tables 2
    no_tmp "interrupted"
    ;;
  plot_tradeoff_input)
    p="$root/scripts/plot_tradeoff.py"
    head='knob,value,balanced,wall_s,te_steps,force_err_pct'
    printf '%s\nreference,static 1e-8,true,1.98,-,0.0000\nbase,-,true,0.41,973,0.0001\nbalance_tol,1e-2,false,0.20,500,0.5\n' "$head" >t.csv
    # -o DIR: it wrote DIR.png beside the directory, without a word; now DIR/tradeoff_TABLE.png
    mkdir figs && expect 0 "" /usr/bin/python3 "$p" t.csv -o figs
    [[ "$(cat "$work/out")" == figs/tradeoff_t.png && -s figs/tradeoff_t.png && ! -e figs.png ]] && echo "PASS plot_tradeoff.py -o figs wrote figs/tradeoff_t.png" ||
      { echo "FAIL plot_tradeoff.py -o figs printed '$(cat "$work/out")', wrote: $(ls)"; fail=1; }
    # -o without an extension: matplotlib wrote noext.png, and nothing said so
    expect 0 "" /usr/bin/python3 "$p" t.csv -o noext
    [[ "$(cat "$work/out")" == noext.png && -s noext.png && ! -e noext ]] && echo "PASS plot_tradeoff.py -o noext printed noext.png, the file it wrote" ||
      { echo "FAIL plot_tradeoff.py -o noext printed '$(cat "$work/out")', wrote: $(ls)"; fail=1; }
    # every row but the reference stopped (tradeoff.sh's '-' in every column after balanced): an empty plot, exit 0
    printf '%s\nreference,static 1e-8,true,1.98,-,0.0000\nbase,-,stopped,-,-,-\nte_safety,0.9,timeout,-,-,-\n' "$head" >stopped.csv
    expect 1 "plot_tradeoff.py: stopped.csv: no row but the reference ran (every one stopped, was refused or ran out of time: wall_s '-'): nothing to plot" \
      /usr/bin/python3 "$p" stopped.csv -o s.png
    # not numbers where the plot needs them, no knob column: ValueError and KeyError tracebacks
    printf '%s\nreference,static 1e-8,true,1.98,-,0.0000\nbase,-,true,abc,973,0.0001\n' "$head" >wall.csv
    expect 1 "plot_tradeoff.py: wall.csv line 3 (knob base): wall_s 'abc': not a number above 0" /usr/bin/python3 "$p" wall.csv -o w.png
    printf '%s\nreference,static 1e-8,true,1.98,-,0.0000\nbase,-,true,0.41,973,-\n' "$head" >dash.csv
    expect 1 "plot_tradeoff.py: dash.csv line 3 (knob base): force_err_pct '-': not a number of 0 or more" /usr/bin/python3 "$p" dash.csv -o d.png
    printf 'value,balanced,wall_s,te_steps,force_err_pct\nstatic 1e-8,true,1.98,-,0.0000\n' >noknob.csv
    expect 1 "plot_tradeoff.py: noknob.csv: no knob column (not a table of scripts/tradeoff.sh)" /usr/bin/python3 "$p" noknob.csv -o k.png
    [[ -z "$(ls s.png w.png d.png k.png 2>/dev/null)" ]] || { echo "FAIL plot_tradeoff.py wrote a figure of a table it refused: $(ls)"; fail=1; }
    ;;
  *) echo "scripts_args.sh: unknown case $case_"; exit 2 ;;
esac
exit $fail
