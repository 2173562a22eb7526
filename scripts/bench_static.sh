#!/usr/bin/env bash
# Scaling of the quasi-static path (-solver static, docs/static.md): the square net under its
# central 0.5 N load (inputs/square_net.yaml, 24 threads/cm) grown to N x N crossings, on 2 ranks,
# balanced to 1e-8 relative. One table row per grid: wall time, Newton and Krylov iterations,
# peak memory (PETSc's -memory_view: the peak resident memory, summed over the ranks) and the time ratio to the grid before,
# with the exponent p of time ~ crossings^p between the two.
# Options before the sizes go to every run (for example -static_sequence 3: grid sequencing); the
# column coarse_newton counts the Newton steps on its coarser nets.
# usage: scripts/bench_static.sh [-option value ...] [N ...]   (default 101 201 401; add 801 1601 for the full study)
source "$(dirname "$0")/bench_env.sh"
opts=()
while (($#)) && [[ $1 == -* ]]; do
  (($# >= 2)) || { echo "bench_static.sh: option $1 without its value (options before the sizes are -option value pairs)" >&2; exit 2; }
  opts+=("$1" "$2"); shift 2
done
sizes=("$@"); ((${#sizes[@]})) || sizes=(101 201 401)
for n in "${sizes[@]}"; do
  [[ $n =~ ^[0-9]+$ ]] && ((10#$n >= 3)) || { echo "bench_static.sh: size '$n': the crossings along a side, a whole number from 3" >&2; exit 2; }
done
ranks="${RANKS:-2}"; steps="${LOAD_STEPS:-12}"; positive_ranks RANKS "$ranks"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
((${#opts[@]})) && echo "options: ${opts[*]}"
printf '%-11s %9s %8s %8s %13s %8s %10s %8s %6s\n' crossings wall_s newton krylov coarse_newton mem_MiB deflect_mm ratio p
prev_t=""; prev_n=""
for n in "${sizes[@]}"; do
  mm="$(awk -v n="$n" 'BEGIN{printf "%.10g", (n - 1) * 10 / 24}')" # 24 threads/cm: (n-1) spacings
  mpiexec -n "$ranks" "$fabric" -scene "$here/inputs/square_net.yaml" -solver static -gauge_mm "$mm" -width_mm "$mm" \
    -balance_tol 1e-8 -load_steps "$steps" -output_every 0 -quiet -output_dir "$work/n$n" -memory_view ${opts[@]+"${opts[@]}"} >"$work/log$n" 2>&1 ||
    { echo "bench_static.sh: the run of ${n}x${n} crossings failed: $(fabric_error "$work/log$n" 3)" >&2; exit 1; }
  t="$(summary_key "$work/n$n" wall_s)"; nl="$(summary_key "$work/n$n" nonlinear_iterations)"
  li="$(summary_key "$work/n$n" linear_iterations)"; ci="$(summary_key "$work/n$n" coarse_nonlinear_iterations)"
  conv="$(summary_key "$work/n$n" converged)"
  mem="$(awk '/^Maximum \(over computational time\) process memory/ {for (i=1;i<NF;i++) if ($i == "total") v=$(i+1)} END {printf "%.0f", v/1048576}' "$work/log$n")"
  w="$(tail -1 "$work/n$n/curve.csv" | cut -d, -f3)"
  ratio="-"; p="-"
  if [[ -n "$prev_t" && $((10#$n)) != $((10#$prev_n)) ]]; then # (the same size again: no exponent)
    ratio="$(awk -v a="$t" -v b="$prev_t" 'BEGIN{printf "%.2f", a / b}')"
    p="$(awk -v a="$t" -v b="$prev_t" -v n="$n" -v m="$prev_n" 'BEGIN{printf "%.2f", log(a / b) / log((n * n) / (m * m))}')"
  fi
  printf '%-11s %9.2f %8s %8s %13s %8s %10.4f %8s %6s%s\n' "${n}x${n}" "$t" "$nl" "$li" "$ci" "$mem" "$w" "$ratio" "$p" \
    "$([[ $conv == true ]] || echo '  (not every load step balanced)')"
  prev_t="$t"; prev_n="$n"
done
