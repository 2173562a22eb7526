# bench_env.sh: the start of the benchmark scripts, sourced with their arguments: --help prints the
# script's header (its comment lines after the first); strict mode; here (the repository) and fabric
# (FABRIC, else build/fabric, built by scripts/setup.sh when missing); Open MPI allowed to run as
# root and more ranks than cores.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/{/^[^#]/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;; esac
set -eu
here="$(cd "$(dirname "$0")/.." && pwd)"
fabric="${FABRIC:-$here/build/fabric}"
[[ -x "$fabric" ]] || bash "$here/scripts/setup.sh" >/dev/null
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
