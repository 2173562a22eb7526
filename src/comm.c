/* comm.c - all communication: the halo exchange of ghost crossing points and the
 * reductions (balance test, stable step, front). Max-reductions are exact, so
 * decisions taken on them are the same on any number of ranks (MODEL.md 13).
 */
#include "fabric.h"

/* one halo exchange per te step: refresh the ghost crossing points of Xl from X */
PetscErrorCode HaloExchange(Fabric fab)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(EV_Halo, 0, 0, 0, 0));
  PetscCall(DMGlobalToLocalBegin(fab->da, fab->X, INSERT_VALUES, fab->Xl));
  PetscCall(DMGlobalToLocalEnd(fab->da, fab->X, INSERT_VALUES, fab->Xl));
  PetscCall(PetscLogEventEnd(EV_Halo, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode GlobalMax(MPI_Comm comm, PetscReal *v, PetscInt n)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(EV_Reduce, 0, 0, 0, 0));
  PetscCall(MPIU_Allreduce(MPI_IN_PLACE, v, (PetscMPIInt)n, MPIU_REAL, MPIU_MAX, comm));
  PetscCall(PetscLogEventEnd(EV_Reduce, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode GlobalSum(MPI_Comm comm, PetscReal *v, PetscInt n)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(EV_Reduce, 0, 0, 0, 0));
  PetscCall(MPIU_Allreduce(MPI_IN_PLACE, v, (PetscMPIInt)n, MPIU_REAL, MPIU_SUM, comm));
  PetscCall(PetscLogEventEnd(EV_Reduce, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}
