# runs.sh - sourced by the scene test scripts (static.sh, rupture.sh) after they set $fabric:
# the interpreter with numpy/h5py ($py), a work directory removed at exit ($work), the failure flag
# ($fail) and run NP ARGS..., one quiet fabric run on NP ranks whose failure is shown and counted.
py=/usr/bin/python3
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fail=0
run() { local np="$1"; shift; mpiexec -n "$np" "$fabric" -quiet "$@" >"$work/log" 2>&1 || { cat "$work/log"; echo "FAIL: run on $np ranks failed: $*"; fail=1; }; }
