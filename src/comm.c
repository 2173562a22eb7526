/* comm.c - all communication: the halo exchange of ghost crossing points and the
 * reductions (balance test, stable step, front). Max-reductions are exact, so
 * decisions taken on them are the same on any number of ranks (MODEL.md 13).
 */
#include "comm.h"
#include "events.h"

#include <math.h>

/* one halo exchange per te step: refresh the ghost crossing points of Xl from X */
PetscErrorCode HaloExchange(DM da, Vec X, Vec Xl)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(EV_Halo, 0, 0, 0, 0));
  PetscCall(DMGlobalToLocalBegin(da, X, INSERT_VALUES, Xl));
  PetscCall(DMGlobalToLocalEnd(da, X, INSERT_VALUES, Xl));
  PetscCall(PetscLogEventEnd(EV_Halo, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode GlobalMax(MPI_Comm comm, PetscReal *v, PetscInt n)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(EV_Reduce, 0, 0, 0, 0));
  PetscCall(MPIU_Allreduce(MPI_IN_PLACE, v, (PetscMPIInt) n, MPIU_REAL, MPIU_MAX, comm));
  PetscCall(PetscLogEventEnd(EV_Reduce, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode GlobalSum(MPI_Comm comm, PetscReal *v, PetscInt n)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(EV_Reduce, 0, 0, 0, 0));
  PetscCall(MPIU_Allreduce(MPI_IN_PLACE, v, (PetscMPIInt) n, MPIU_REAL, MPIU_SUM, comm));
  PetscCall(PetscLogEventEnd(EV_Reduce, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* Exact, rank-independent sum of n local terms (any sign) over all ranks: each term is
   quantised on a fixed-point grid q = max |term| / 2^40 (global max: exact), the integers
   are summed in int64 (exact and associative: the same on any number of ranks and any
   split), and the result is sum * q. A sum that feeds back into the dynamics (kinetic
   damping) must be taken this way: a floating-point sum depends on the order of the terms.
   The quantisation error is at most n q / 2 = n max|term| 2^-41; the integer sum cannot
   overflow below 2^22 terms per unit of max |term| (8 M points at the max each). */
#define EXACT_SUM_BITS 40
PetscErrorCode GlobalSumExact(MPI_Comm comm, const PetscReal *terms, PetscInt n, PetscReal *sum)
{
  PetscReal scale = 0;
  long long isum = 0, total = 0;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < n; k++) scale = PetscMax(scale, PetscAbsReal(terms[k]));
  PetscCall(GlobalMax(comm, &scale, 1));
  if (!(scale > 0) || !isfinite(scale)) { /* all zero (or a NaN the caller's watch reports) */
    *sum = scale > 0 ? scale : 0.0;
    PetscFunctionReturn(0);
  }
  {
    const PetscReal inv_q = ldexp(1.0, EXACT_SUM_BITS) / scale;
    for (PetscInt k = 0; k < n; k++) isum += llround(terms[k] * inv_q);
  }
  PetscCall(PetscLogEventBegin(EV_Reduce, 0, 0, 0, 0));
  PetscCallMPI(MPI_Allreduce(&isum, &total, 1, MPI_LONG_LONG, MPI_SUM, comm));
  PetscCall(PetscLogEventEnd(EV_Reduce, 0, 0, 0, 0));
  *sum = (PetscReal) total * (scale / ldexp(1.0, EXACT_SUM_BITS));
  PetscFunctionReturn(0);
}
