/* comm.h - halo exchange and reductions: the only place that communicates (comm.c). */
#ifndef FABRIC_COMM_H
#define FABRIC_COMM_H

#include <petscdm.h>

/* refresh the ghost crossing points of Xl from X (a vector of the DMDA da) */
PetscErrorCode HaloExchange(DM da, Vec X, Vec Xl);
PetscErrorCode GlobalMax(MPI_Comm comm, PetscReal *v, PetscInt n);
PetscErrorCode GlobalSum(MPI_Comm comm, PetscReal *v, PetscInt n);
/* exact, rank-independent sum of n local terms over all ranks (fixed point) */
PetscErrorCode GlobalSumExact(MPI_Comm comm, const PetscReal *terms, PetscInt n, PetscReal *sum);

#endif
