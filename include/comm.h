/* comm.h - halo exchange, reductions and broadcasts: the only place that communicates (comm.c). */
#ifndef FABRIC_COMM_H
#define FABRIC_COMM_H

#include <petscdm.h>
#include <stdint.h>
#include <string.h>

/* refresh the ghost crossing points of Xl from X (a vector of the DMDA da). With X and Xl paired
   by HaloHome, where the patch spans its rows, Xl then reads X's ghosted home (only the ghost
   points move) until an exchange of another vector: only for a local vector that is read, never
   written, and read only after an exchange */
PetscErrorCode HaloExchange(DM da, Vec X, Vec Xl);
PetscErrorCode HaloHome(DM da, Vec X, Vec Xl);
/* the owned points of the ghosted Xl back into X (the reverse of HaloExchange, ghosts dropped) */
PetscErrorCode OwnedFromLocal(DM da, Vec Xl, Vec X);
/* X (a vector of the DMDA da) in the natural order of the grid, i fastest, into N (DMDACreateNaturalVector) */
PetscErrorCode NaturalOrder(DM da, Vec X, Vec N);
PetscErrorCode GlobalMax(MPI_Comm comm, PetscReal *v, PetscInt n);
PetscErrorCode GlobalSum(MPI_Comm comm, PetscReal *v, PetscInt n);
/* the largest *value over all ranks and, among the ranks that hold it, the lowest index: each rank
   gives its own value and index (index < 0: none), and gets both back; rank-independent */
PetscErrorCode GlobalArgMax(MPI_Comm comm, PetscReal *value, PetscInt *index);
#define EXACT_SUMS_MAX 4
/* exact, rank-independent sums of m <= 4 quantities over all ranks (fixed point): quantity c's n local
   terms at terms[c n ...], its sum into sums[c] */
PetscErrorCode GlobalSumsExact(MPI_Comm comm, PetscInt m, const PetscReal *terms, PetscInt n, PetscReal *sums);
/* the same, or the plain sums (Inf or NaN as they are) where one is not finite */
PetscErrorCode GlobalPointSums(MPI_Comm comm, PetscInt m, const PetscReal *terms, PetscInt n, PetscReal *sums);
/* the same in two parts, so that a caller's own maxima share the first reduction: the local
   max |term| of each quantity into scale[c] (no communication); then, with scale[] the global
   maxima (GlobalMax of the local ones), the sums (one reduction) */
void           ExactSumScales(PetscInt m, const PetscReal *terms, PetscInt n, PetscReal *scale);
PetscErrorCode GlobalSumsExactScaled(MPI_Comm comm, PetscInt m, const PetscReal *terms, PetscInt n,
                                     const PetscReal *scale, PetscReal *sums);
/* Exact, rank-independent sums in one pass over the terms, on scales known before it (a caller's
   scales from its last pass): each term t of quantity c, |t| <= scale[c] (a power of 2), becomes the
   integer nearest t 2^EXACT_LAG_BITS / scale[c] (ExactLagTerm), summed in 64-bit blocks of at most
   EXACT_LAG_BLOCK terms (unsigned: a term past its scale, which makes the caller sum again, wraps
   instead of overflowing) and the blocks in 128 bits; the bits of the largest |t| come along, so that
   the caller can tell whether the scale held (GlobalExactParts: one collective for the sums and the
   maxima). Exact integers: the same on any number of ranks and any split. */
#define EXACT_LAG_BITS  50
#define EXACT_LAG_BLOCK 256
typedef struct {
  __int128 sum[EXACT_SUMS_MAX]; /* the quantised terms */
  int64_t  top[EXACT_SUMS_MAX]; /* the bits of the largest |term| (kernels.h AbsBits: they order as |term|) */
} ExactPart;
/* the integer nearest y (halves to even) for |y| < 2^51, mod 2^64, in floating-point adds and bit
   operations (so that a loop of them vectorises): y + 1.5 2^52 holds it in its low bits (a y past
   2^51, which makes the caller sum again, gives some other value, without overflow) */
static inline uint64_t ExactLagTerm(double y)
{
  const double z = y + 6755399441055744.0, shift = 6755399441055744.0;
  uint64_t     bz, bs;
  memcpy(&bz, &z, sizeof bz);
  memcpy(&bs, &shift, sizeof bs);
  return bz - bs;
}
/* the parts of all ranks combined: sums added, maxima taken (one reduction, a user-defined MPI
   operation on the exact integers) */
PetscErrorCode GlobalExactParts(MPI_Comm comm, PetscInt m, const ExactPart *local, ExactPart *global);
/* refuses, on every rank alike, a run where some rank would hold more than PETSc's 32-bit indices reach
   (2^31 - 1) in one array: entries, this rank's count; per_point, the entries a crossing takes; what, the array
   (for the message) */
PetscErrorCode CheckRankEntries(MPI_Comm comm, double entries, PetscInt per_point, const char *what);
/* integer sums over all ranks, in place: exact; the uint64 one mod 2^64 (checkpoint checksums) */
PetscErrorCode GlobalSumInt(MPI_Comm comm, PetscInt *v, PetscInt n);
PetscErrorCode GlobalSumUInt64(MPI_Comm comm, uint64_t *v, PetscInt n);

/* this process's rank in comm and the number of ranks */
PetscErrorCode CommRank(MPI_Comm comm, PetscMPIInt *rank);
PetscErrorCode CommSize(MPI_Comm comm, PetscMPIInt *size);
/* the rank-0-then-broadcast pattern: rank 0 has looked at something alone (a file, a directory,
   the clock), every rank gets what it found, so that all ranks take the same decision */
PetscErrorCode BroadcastFromRoot(MPI_Comm comm, void *buf, PetscInt count, MPI_Datatype type);
/* every rank has got here (a file every rank has closed may be touched by rank 0) */
PetscErrorCode Barrier(MPI_Comm comm);

#endif
