# bench_env.sh: the start of the benchmark scripts, sourced with their arguments: --help prints the
# script's header (its comment lines after the first); strict mode; here (the repository) and fabric
# (FABRIC, else build/fabric, built by scripts/setup.sh when missing); Open MPI allowed to run as
# root and more ranks than cores; fabric_error LOG [LINES] (fabric's own error line from a run's log, not
# mpiexec's footer after it, else its last LINES lines, 1 by default), summary_key DIR KEY (KEY's value in
# DIR/summary.json: a number, true or false) and positive_ranks NAME VALUE (an environment variable's
# rank count, a positive integer, else a message and exit 2). Ctrl-C (SIGINT to the process group, as a
# terminal sends it, or SIGTERM to the group) stops the script with "interrupted" and exit 130, its runs
# with it (mpiexec is in its group); a signal to the script alone stops it after its current run.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/{/^[^#]/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;; esac
set -eu
here="$(cd "$(dirname "$0")/.." && pwd)"
fabric="${FABRIC:-$here/build/fabric}"
if [[ -n "${FABRIC:-}" ]]; then # the user's binary is used as given: not built
  [[ -f "$FABRIC" && -x "$FABRIC" ]] || { echo "${0##*/}: FABRIC '$FABRIC': not an executable file" >&2; exit 2; }
  fabric="$(cd "$(dirname "$FABRIC")" && pwd)/$(basename "$FABRIC")" # the same file from any directory
elif [[ ! -x "$fabric" ]]; then
  bash "$here/scripts/setup.sh" >/dev/null
fi
trap 'echo "${0##*/}: interrupted" >&2; exit 130' INT TERM
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
fabric_error() { grep -m1 '^fabric: error' "$1" || tail -"${2:-1}" "$1"; }
positive_ranks() { [[ $2 =~ ^[1-9][0-9]*$ ]] || { echo "${0##*/}: $1 '$2': the number of ranks, a positive integer" >&2; exit 2; }; }
summary_key() { sed -n "s/^ *\"$2\": \\([^,]*\\),*$/\\1/p" "$1/summary.json" | head -1; }
