/* comm.c - all communication: the halo exchange of ghost crossing points (and its reverse, and
 * the scatter of a grid vector into natural order), the reductions
 * (balance test, stable step, front, counts, checkpoint checksums) and the broadcasts of what
 * rank 0 found alone (files, directories, the clock). Max-reductions and integer sums are
 * exact, so decisions taken on them are the same on any number of ranks (MODEL.md 13).
 */
#include "comm.h"
#include "events.h"

#include <math.h>
#include <petscdmda.h>
#include <string.h>

#define HALO_HOME "fabric_halo_home"

/* What HaloHome gives X and its read-only ghosted Xl, composed on Xl:
   - home: a local vector of the DMDA whose owned rows are X's array (X's own array is set aside);
   - ghosts: X's ghost points into home's ghost rows (NULL on one rank: there are none);
   - owner: X (not referenced: X and Xl live and die together);
   - placed: the array placed in Xl: none, home's, or on one rank that of the other vector
     exchanged last. */
typedef enum { PLACED_NONE, PLACED_HOME, PLACED_OTHER } HaloPlaced;
typedef struct {
  Vec        home, owner;
  VecScatter ghosts;
  HaloPlaced placed;
} HaloHomeCtx;

static PetscErrorCode HaloHomeDestroy(void *ptr)
{
  HaloHomeCtx *h = (HaloHomeCtx *) ptr;

  PetscFunctionBeginUser;
  PetscCall(VecScatterDestroy(&h->ghosts));
  PetscCall(VecDestroy(&h->home));
  PetscCall(PetscFree(h));
  PetscFunctionReturn(0);
}

/* The ghost points of this rank's patch: their block indices in a local vector (to) and in the
   DMDA's global numbering (from) */
static PetscErrorCode GhostScatter(DM da, Vec X, Vec home, VecScatter *ghosts)
{
  DMDALocalInfo          info;
  ISLocalToGlobalMapping ltog;
  PetscInt               n = 0, k = 0, *loc, *glob;
  IS                     from, to;

  PetscFunctionBeginUser;
  PetscCall(DMDAGetLocalInfo(da, &info));
  n = info.gxm * info.gym - info.xm * info.ym;
  PetscCall(PetscMalloc2(n, &loc, n, &glob));
  for (PetscInt j = info.gys; j < info.gys + info.gym; j++)
    for (PetscInt i = info.gxs; i < info.gxs + info.gxm; i++) {
      if (i >= info.xs && i < info.xs + info.xm && j >= info.ys && j < info.ys + info.ym) continue;
      loc[k++] = (j - info.gys) * info.gxm + (i - info.gxs);
    }
  PetscCall(DMGetLocalToGlobalMapping(da, &ltog));
  PetscCall(ISLocalToGlobalMappingApplyBlock(ltog, n, loc, glob));
  PetscCall(ISCreateBlock(PETSC_COMM_SELF, info.dof, n, glob, PETSC_COPY_VALUES, &from));
  PetscCall(ISCreateBlock(PETSC_COMM_SELF, info.dof, n, loc, PETSC_COPY_VALUES, &to));
  PetscCall(VecScatterCreate(X, from, home, to, ghosts));
  PetscCall(ISDestroy(&from));
  PetscCall(ISDestroy(&to));
  PetscCall(PetscFree2(loc, glob));
  PetscFunctionReturn(0);
}

/* Where this rank's patch spans its rows (no ghost columns: one rank, or the grid split in rows
   alone), the owned points of a ghosted array are one contiguous block: X's array is placed there,
   in a local vector of its own (its home), so that an exchange of X moves the ghost points alone and
   Xl reads the home. Call it before X holds anything. Elsewhere nothing changes: an exchange copies
   every point. */
PetscErrorCode HaloHome(DM da, Vec X, Vec Xl)
{
  DMDALocalInfo  info;
  PetscContainer mark;
  HaloHomeCtx   *h;
  PetscScalar   *a;
  PetscMPIInt    size;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectQuery((PetscObject) Xl, HALO_HOME, (PetscObject *) &mark));
  PetscCheck(!mark, PetscObjectComm((PetscObject) Xl), PETSC_ERR_ARG_WRONGSTATE, "HaloHome: this local vector has a home already");
  PetscCall(DMDAGetLocalInfo(da, &info));
  if (info.gxs != info.xs || info.gxm != info.xm) PetscFunctionReturn(0);
  PetscCall(PetscNew(&h));
  h->owner = X;
  PetscCall(DMCreateLocalVector(da, &h->home));
  PetscCall(VecGetArray(h->home, &a));
  PetscCall(VecPlaceArray(X, a + (size_t) info.dof * (info.ys - info.gys) * info.gxm));
  PetscCall(VecRestoreArray(h->home, &a));
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject) da), &size));
  if (size > 1) PetscCall(GhostScatter(da, X, h->home, &h->ghosts));
  PetscCall(PetscContainerCreate(PetscObjectComm((PetscObject) Xl), &mark));
  PetscCall(PetscContainerSetPointer(mark, h));
  PetscCall(PetscContainerSetUserDestroy(mark, HaloHomeDestroy));
  PetscCall(PetscObjectCompose((PetscObject) Xl, HALO_HOME, (PetscObject) mark));
  PetscCall(PetscContainerDestroy(&mark));
  PetscFunctionReturn(0);
}

/* refresh the ghost crossing points of Xl from X (one per te step on the hot path) */
PetscErrorCode HaloExchange(DM da, Vec X, Vec Xl)
{
  PetscObject  mark;
  HaloHomeCtx *h = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(EV_Halo, 0, 0, 0, 0));
  PetscCall(PetscObjectQuery((PetscObject) Xl, HALO_HOME, &mark));
  if (mark) PetscCall(PetscContainerGetPointer((PetscContainer) mark, (void **) &h));
  if (h && h->owner == X) { /* X's ghosts into its home, and Xl reads the home */
    if (h->ghosts) {
      PetscCall(VecScatterBegin(h->ghosts, X, h->home, INSERT_VALUES, SCATTER_FORWARD));
      PetscCall(VecScatterEnd(h->ghosts, X, h->home, INSERT_VALUES, SCATTER_FORWARD));
    }
    if (h->placed != PLACED_HOME) {
      const PetscScalar *a;
      if (h->placed == PLACED_OTHER) PetscCall(VecResetArray(Xl));
      PetscCall(VecGetArrayRead(h->home, &a));
      PetscCall(VecPlaceArray(Xl, a));
      PetscCall(VecRestoreArrayRead(h->home, &a));
      h->placed = PLACED_HOME;
    } else { /* its values changed under it: its state moves on, as after any exchange */
      PetscScalar *a;
      PetscCall(VecGetArray(Xl, &a));
      PetscCall(VecRestoreArray(Xl, &a));
    }
  } else {
    PetscInt nl = 0, ng = -1;
    if (h && h->placed != PLACED_NONE) {
      PetscCall(VecResetArray(Xl));
      h->placed = PLACED_NONE;
    }
    if (h && !h->ghosts) { /* one rank: the local vector is the global one if the sizes agree */
      PetscCall(VecGetLocalSize(Xl, &nl));
      PetscCall(VecGetLocalSize(X, &ng));
    }
    if (nl == ng) { /* no ghosts: Xl reads X's own array */
      const PetscScalar *a;
      PetscCall(VecGetArrayRead(X, &a));
      PetscCall(VecPlaceArray(Xl, a));
      PetscCall(VecRestoreArrayRead(X, &a));
      h->placed = PLACED_OTHER;
    } else {
      PetscCall(DMGlobalToLocalBegin(da, X, INSERT_VALUES, Xl));
      PetscCall(DMGlobalToLocalEnd(da, X, INSERT_VALUES, Xl));
    }
  }
  PetscCall(PetscLogEventEnd(EV_Halo, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode OwnedFromLocal(DM da, Vec Xl, Vec X)
{
  PetscFunctionBeginUser;
  PetscCall(DMLocalToGlobalBegin(da, Xl, INSERT_VALUES, X));
  PetscCall(DMLocalToGlobalEnd(da, Xl, INSERT_VALUES, X));
  PetscFunctionReturn(0);
}

PetscErrorCode NaturalOrder(DM da, Vec X, Vec N)
{
  PetscFunctionBeginUser;
  PetscCall(DMDAGlobalToNaturalBegin(da, X, INSERT_VALUES, N));
  PetscCall(DMDAGlobalToNaturalEnd(da, X, INSERT_VALUES, N));
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

PetscErrorCode GlobalArgMax(MPI_Comm comm, PetscReal *value, PetscInt *index)
{
  const PetscReal mine = *value;
  PetscReal       key;

  PetscFunctionBeginUser;
  PetscCall(GlobalMax(comm, value, 1));
  /* minus the index, from the ranks that hold the largest value: its max is the lowest index */
  key = *index >= 0 && mine == *value ? -(PetscReal) *index : -PETSC_MAX_REAL;
  PetscCall(GlobalMax(comm, &key, 1));
  *index = key > -PETSC_MAX_REAL ? (PetscInt) (-key) : -1;
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

/* Exact, rank-independent sums of m quantities, each of n local terms (any sign) over all ranks:
   quantity c's terms terms[c*n .. c*n+n) are quantised on a fixed-point grid q = max |term| / 2^40
   (global max: exact), the integers are summed exactly (integer addition is associative: the same on
   any number of ranks and any split), and the result is sum * q. A sum that feeds back into the
   dynamics (kinetic damping, FIRE) must be taken this way: a floating-point sum depends on the
   order of the terms. The quantisation error is at most n q / 2 = n max|term| 2^-41. The integers
   are summed in blocks of EXACT_SUM_BLOCK terms in 64 bits and the blocks in 128 bits (ExactPart's
   sums, GlobalExactParts): no overflow below 2^87 terms. (In 64 bits throughout the total wrapped
   past 2^23 terms at the max each: 8.4 M crossings, below the grid limit.) Two reductions for all m
   quantities: the max (GlobalMax, which a caller may share with its own maxima, then
   GlobalSumsExactScaled) and the integer sum. */
#define EXACT_SUM_BITS 40

/* x rounded to the nearest integer, halves away from zero: llround's result for |x| < 2^62
   (NaN: LLONG_MIN, as llround on x86-64), without a library call. k truncates x; x - k is exact. */
static inline long long RoundHalfAway(double x)
{
  const long long k = (long long) x;
  const double    d = x - (double) k;
  return k + (d >= 0.5) - (d <= -0.5);
}

void ExactSumScales(PetscInt m, const PetscReal *terms, PetscInt n, PetscReal *scale)
{
  for (PetscInt c = 0; c < m; c++) {
    const PetscReal *t = terms + (size_t) c * n;
    PetscReal        s[4] = {0, 0, 0, 0}; /* max is exact in any order (a NaN term is skipped, as PetscMax does) */
    PetscInt         k    = 0;
    for (; k + 4 <= n; k += 4)
      for (int l = 0; l < 4; l++) s[l] = PetscMax(s[l], PetscAbsReal(t[k + l]));
    for (; k < n; k++) s[0] = PetscMax(s[0], PetscAbsReal(t[k]));
    scale[c] = PetscMax(PetscMax(s[0], s[1]), PetscMax(s[2], s[3]));
  }
}

/* sum of RoundHalfAway(t[k] inv_q), k < n, for finite inv_q (|t[k] inv_q| <= 2^40 as |t[k]| <= the scale: a block's
   sum within 2^48, exact in 64 bits; the blocks' in 128). In blocks, in integer and bit operations only, so that
   the loop vectorises: adding 1.5 2^52 to y = t inv_q rounds it to the integer the sum's bits hold (halves to even,
   |y| < 2^51); d = y - that integer is exact, |d| <= 1/2, and a block where some |d| = 1/2 (a half: half-even and
   half-away may differ) or y is NaN is summed again with RoundHalfAway. As |d| <= 1/2, bits(|d|) + 2^62 - bits(1/2)
   reaches bit 62 or 63 only at a half or a NaN. */
#define EXACT_SUM_BLOCK 256
static __int128 QuantisedSum(const PetscReal *t, PetscInt n, PetscReal inv_q)
{
  const double       shift = 6755399441055744.0, half = 0.5; /* 1.5 2^52 */
  unsigned long long bhalf, flag;
  __int128           total = 0;

  memcpy(&bhalf, &half, sizeof bhalf);
  flag = (1ULL << 62) - bhalf;
  for (PetscInt k0 = 0; k0 < n; k0 += EXACT_SUM_BLOCK) {
    const PetscInt     nb = PetscMin(EXACT_SUM_BLOCK, n - k0);
    const PetscReal   *tb = t + k0;
    unsigned long long s = 0, odd = 0;
    for (PetscInt k = 0; k < nb; k++) {
      const double       y = tb[k] * inv_q, ad = fabs(y - ((y + shift) - shift));
      unsigned long long c;
      memcpy(&c, &ad, sizeof c);
      s += ExactLagTerm(y); /* comm.h: the integer y + 1.5 2^52 holds in its low bits */
      odd |= c + flag;
    }
    if (odd >> 62) {
      s = 0;
      for (PetscInt k = 0; k < nb; k++) s += (unsigned long long) RoundHalfAway(tb[k] * inv_q);
    }
    total += (long long) s; /* the block's sum, within 2^48 (mod 2^64 as unsigned): exact as signed */
  }
  return total;
}

PetscErrorCode GlobalSumsExactScaled(MPI_Comm comm, PetscInt m, const PetscReal *terms, PetscInt n,
                                     const PetscReal *scale, PetscReal *sums)
{
  ExactPart local, global;

  PetscFunctionBeginUser;
  PetscCheck(m >= 1 && m <= EXACT_SUMS_MAX, comm, PETSC_ERR_ARG_OUTOFRANGE, "%" PetscInt_FMT " exact sums at once, at most %d",
             m, EXACT_SUMS_MAX);
  memset(&local, 0, sizeof local); /* top[] unused */
  for (PetscInt c = 0; c < m; c++) {
    if (!(scale[c] > 0) || !isfinite(scale[c])) continue; /* all zero (or a NaN the caller's watch reports) */
    const PetscReal inv_q = ldexp(1.0, EXACT_SUM_BITS) / scale[c], *t = terms + (size_t) c * n;
    if (isfinite(inv_q)) local.sum[c] = QuantisedSum(t, n, inv_q);
    else { /* a scale below 2^40 / DBL_MAX (about 6e-297): 1/q overflows, so each term is scaled by a power of two,
              exactly, onto the grid q = 2^(e - 40), |t| < 2^e (it gave LLONG_MIN for every term: wrong sums, and an
              overflow in RoundHalfAway) */
      const int e = ilogb(scale[c]) + 1;
      for (PetscInt k = 0; k < n; k++) local.sum[c] += RoundHalfAway(ldexp(t[k], EXACT_SUM_BITS - e));
    }
  }
  PetscCall(GlobalExactParts(comm, m, &local, &global));
  for (PetscInt c = 0; c < m; c++) {
    if (!(scale[c] > 0 && isfinite(scale[c]))) sums[c] = scale[c] > 0 ? scale[c] : 0.0;
    else if (isfinite(ldexp(1.0, EXACT_SUM_BITS) / scale[c])) sums[c] = (PetscReal) global.sum[c] * (scale[c] / ldexp(1.0, EXACT_SUM_BITS));
    else sums[c] = ldexp((PetscReal) global.sum[c], ilogb(scale[c]) + 1 - EXACT_SUM_BITS); /* the grid of the tiny scale */
  }
  PetscFunctionReturn(0);
}

PetscErrorCode GlobalSumsExact(MPI_Comm comm, PetscInt m, const PetscReal *terms, PetscInt n, PetscReal *sums)
{
  PetscReal scale[EXACT_SUMS_MAX] = {0};

  PetscFunctionBeginUser;
  PetscCheck(m >= 1 && m <= EXACT_SUMS_MAX, comm, PETSC_ERR_ARG_OUTOFRANGE, "%" PetscInt_FMT " exact sums at once, at most %d",
             m, EXACT_SUMS_MAX);
  ExactSumScales(m, terms, n, scale);
  PetscCall(GlobalMax(comm, scale, m));
  PetscCall(GlobalSumsExactScaled(comm, m, terms, n, scale, sums));
  PetscFunctionReturn(0);
}

/* Sums over every rank's points of m quantities, quantity c's n local terms at t[c n ...]: exact and
   rank-independent (GlobalSumsExact); if one is not finite, the plain sums, Inf or NaN as they are
   (the exact sums quantise the terms on the largest) */
PetscErrorCode GlobalPointSums(MPI_Comm comm, PetscInt m, const PetscReal *t, PetscInt n, PetscReal *sums)
{
  PetscReal plain[EXACT_SUMS_MAX] = {0};
  PetscBool finite = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscCheck(m >= 1 && m <= EXACT_SUMS_MAX, comm, PETSC_ERR_ARG_OUTOFRANGE, "%" PetscInt_FMT " exact sums at once, at most %d",
             m, EXACT_SUMS_MAX);
  for (PetscInt c = 0; c < m; c++)
    for (PetscInt k = 0; k < n; k++) plain[c] += t[(size_t) c * n + k];
  PetscCall(GlobalSum(comm, plain, m)); /* the same on every rank: all take the same branch */
  for (PetscInt c = 0; c < m; c++) finite = finite && isfinite(plain[c]);
  if (finite) PetscCall(GlobalSumsExact(comm, m, t, n, sums));
  else
    for (PetscInt c = 0; c < m; c++) sums[c] = plain[c];
  PetscFunctionReturn(0);
}

/* The reduction of ExactParts: sums added, maxima taken, all EXACT_SUMS_MAX slots (unused ones are
   0 on every rank). Integer operations: exact, in any order and any grouping. */
static void ExactPartsCombine(void *in, void *inout, int *len, MPI_Datatype *type)
{
  (void) type;
  for (int k = 0; k < *len; k++) { /* copied in and out: MPI's buffers need not be aligned for __int128 */
    ExactPart a, b;
    memcpy(&a, (const char *) in + k * sizeof a, sizeof a);
    memcpy(&b, (char *) inout + k * sizeof b, sizeof b);
    for (int c = 0; c < EXACT_SUMS_MAX; c++) {
      b.sum[c] += a.sum[c];
      b.top[c] = PetscMax(b.top[c], a.top[c]);
    }
    memcpy((char *) inout + k * sizeof b, &b, sizeof b);
  }
}

static MPI_Datatype exact_part_type = MPI_DATATYPE_NULL;
static MPI_Op       exact_part_op   = MPI_OP_NULL;

static PetscErrorCode ExactPartsFinalize(void)
{
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Op_free(&exact_part_op));
  PetscCallMPI(MPI_Type_free(&exact_part_type));
  PetscFunctionReturn(0);
}

PetscErrorCode GlobalExactParts(MPI_Comm comm, PetscInt m, const ExactPart *local, ExactPart *global)
{
  ExactPart mine = *local;

  PetscFunctionBeginUser;
  PetscCheck(m >= 1 && m <= EXACT_SUMS_MAX, comm, PETSC_ERR_ARG_OUTOFRANGE, "%" PetscInt_FMT " exact sums at once, at most %d",
             m, EXACT_SUMS_MAX);
  if (exact_part_op == MPI_OP_NULL) { /* made once, freed when PETSc finalizes */
    PetscCallMPI(MPI_Type_contiguous((int) sizeof(ExactPart), MPI_BYTE, &exact_part_type));
    PetscCallMPI(MPI_Type_commit(&exact_part_type));
    PetscCallMPI(MPI_Op_create(ExactPartsCombine, 1, &exact_part_op));
    PetscCall(PetscRegisterFinalize(ExactPartsFinalize));
  }
  for (PetscInt c = m; c < EXACT_SUMS_MAX; c++) mine.sum[c] = 0, mine.top[c] = 0;
  PetscCall(PetscLogEventBegin(EV_Reduce, 0, 0, 0, 0));
  PetscCallMPI(MPI_Allreduce(&mine, global, 1, exact_part_type, exact_part_op, comm));
  PetscCall(PetscLogEventEnd(EV_Reduce, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckRankEntries(MPI_Comm comm, double entries, PetscInt per_point, const char *what)
{
  PetscReal most = (PetscReal) entries;

  PetscFunctionBeginUser;
  PetscCall(GlobalMax(comm, &most, 1));
  PetscCheck(most <= (PetscReal) PETSC_MAX_INT, comm, PETSC_ERR_USER_INPUT,
             "-solver static: a rank's patch needs %.4g entries in %s (%" PetscInt_FMT " a crossing), more than PETSc's "
             "32-bit indices reach (%" PetscInt_FMT "): a rank can hold at most %.4g crossings; run on more ranks",
             (double) most, what, per_point, (PetscInt) PETSC_MAX_INT, (double) PETSC_MAX_INT / (double) per_point);
  PetscFunctionReturn(0);
}

/* Integer sums and the broadcasts below belong to set-up and output (counts, checksums, a status
   rank 0 found): not timed as FabricReduce, which is the te steps' communication. */
PetscErrorCode GlobalSumInt(MPI_Comm comm, PetscInt *v, PetscInt n)
{
  PetscFunctionBeginUser;
  PetscCall(MPIU_Allreduce(MPI_IN_PLACE, v, (PetscMPIInt) n, MPIU_INT, MPI_SUM, comm));
  PetscFunctionReturn(0);
}

/* unsigned sums wrap mod 2^64: exact in any order, so the same on any number of ranks */
PetscErrorCode GlobalSumUInt64(MPI_Comm comm, uint64_t *v, PetscInt n)
{
  PetscMPIInt count;

  PetscFunctionBeginUser;
  PetscCall(PetscMPIIntCast(n, &count));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, v, count, MPI_UINT64_T, MPI_SUM, comm));
  PetscFunctionReturn(0);
}

PetscErrorCode CommRank(MPI_Comm comm, PetscMPIInt *rank)
{
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, rank));
  PetscFunctionReturn(0);
}

PetscErrorCode CommSize(MPI_Comm comm, PetscMPIInt *size)
{
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, size));
  PetscFunctionReturn(0);
}

PetscErrorCode BroadcastFromRoot(MPI_Comm comm, void *buf, PetscInt count, MPI_Datatype type)
{
  PetscMPIInt n;

  PetscFunctionBeginUser;
  PetscCall(PetscMPIIntCast(count, &n));
  PetscCallMPI(MPI_Bcast(buf, n, type, 0, comm));
  PetscFunctionReturn(0);
}

PetscErrorCode Barrier(MPI_Comm comm)
{
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Barrier(comm));
  PetscFunctionReturn(0);
}
