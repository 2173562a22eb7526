#!/usr/bin/env bash
# output_revision.sh FABRIC SCENE SOURCE_DIR: results say which solver made them. summary.json's
# fabric_revision and fabric.h5's root attribute of that name are the source tree's revision at
# build time, git describe --always --dirty --abbrev=12 ("unknown" outside SRC's own git tree): the same as
# the tree's now, as the README's test command builds before it tests; petsc_version is the
# PETSc of pkg-config, mpi_library the MPI library's name and version (MPI_Get_library_version,
# up to its first comma).
set -u
fabric="$1"; scene="$2"; src="$3"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fail=0
check() { if eval "$1"; then echo "PASS $2"; else echo "FAIL $2"; fail=1; fi; }
mpiexec -n 2 "$fabric" -scene "$scene" -quiet -gauge_mm 20 -width_mm 5 -load_steps 2 -output_dir "$work/out" >/dev/null ||
  { echo "FAIL the run failed"; exit 1; }
key() { /usr/bin/python3 -c "import json, sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$work/out/summary.json" "$1"; }
rev=unknown # outside SRC's own git tree (an export into another repository's folder, say)
if [[ "$(realpath "$(git -C "$src" rev-parse --show-toplevel 2>/dev/null)" 2>/dev/null)" == "$(realpath "$src")" ]]; then
  rev=$(git -C "$src" describe --always --dirty --abbrev=12 2>/dev/null) || rev=unknown
fi
got=$(key fabric_revision)
h5=$(h5dump -a /fabric_revision "$work/out/fabric.h5" 2>/dev/null | sed -n 's/ *(0): "\(.*\)"/\1/p')
check '[[ "$got" == "$rev" ]]' "summary.json fabric_revision '$got' is the tree's '$rev' (rebuild after changing the tree)"
check '[[ "$h5" == "$got" ]]' "fabric.h5's root attribute fabric_revision '$h5' is summary.json's"
petsc=$(pkg-config --modversion PETSc)
check '[[ "$(key petsc_version)" == "$petsc" ]]' "petsc_version '$(key petsc_version)' is pkg-config's PETSc $petsc"
mpi=$(key mpi_library)
check '[[ "$mpi" =~ ^(Open\ MPI\ v|MPICH\ Version:|Intel\(R\)\ MPI).*[0-9] && "$mpi" != *,* ]]' "mpi_library '$mpi': the library's name and version, up to its first comma"
exit $fail
