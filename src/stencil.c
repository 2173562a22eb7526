/* stencil.c - a symmetric block operator on the grid's layout stored by stencil: per point of the
 * ghosted patch, its centre 3x3 block and one for each forward neighbour of a fixed stencil (the
 * tangent's: the star, the box's corners with shear, the points two apart along a yarn with
 * bending); a row's backward blocks are the transposes of its neighbours' forward ones. No
 * indices: a product reads each stored block once and uses it twice (an AIJ matrix of the same
 * operator streams every block with a column index per value). The Galerkin operator of the
 * multigrid levels' bilinear interpolation is formed point by point from the blocks
 * (StencilMatGalerkin), with no intermediate products; the coarsest level is copied into an AIJ
 * matrix for its direct solve. Blocks written at a ghost point (a term of this rank reaching a
 * neighbour's point) are added into the owner's, and the sums brought back to the ghost points,
 * by StencilMatAssemble.
 */
#include "stencil.h"
#include "comm.h"

#include <petsc/private/petscimpl.h> /* PetscObjectStateIncrease */
#include <petscsf.h>

/* y = A x: per owned point, its centre block, its forward blocks on the neighbours ahead and the
   transposes of the blocks of the neighbours behind (ghost points near the patch's edge) */
static PetscErrorCode StencilMult(Mat A, Vec x, Vec y)
{
  StencilData       *d;
  const PetscScalar *xl;
  PetscScalar       *yy;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &d));
  PetscCall(HaloExchange(d->dm, x, d->xl));
  PetscCall(VecGetArrayRead(d->xl, &xl));
  PetscCall(VecGetArrayWrite(y, &yy));
  for (PetscInt j = d->ys; j < d->ys + d->ym; j++) {
    const PetscBool jin = j >= 2 && j < d->N - 2;
    for (PetscInt i = d->xs; i < d->xs + d->xm; i++) {
      const PetscInt     g  = (j - d->gys) * d->gxm + (i - d->gxs);
      const PetscReal   *B  = d->blk + 9 * d->ns * g;
      const PetscScalar *xp = xl + 3 * g;
      const PetscBool    in = jin && i >= 2 && i < d->M - 2; /* every neighbour inside the grid */
      PetscScalar        y0 = B[0] * xp[0] + B[1] * xp[1] + B[2] * xp[2];
      PetscScalar        y1 = B[3] * xp[0] + B[4] * xp[1] + B[5] * xp[2];
      PetscScalar        y2 = B[6] * xp[0] + B[7] * xp[1] + B[8] * xp[2];
      for (PetscInt s = 1; s < d->ns; s++) {
        const PetscInt off = d->dj[s] * d->gxm + d->di[s];
        if (in || (i + d->di[s] < d->M && j + d->dj[s] < d->N && i + d->di[s] >= 0)) { /* ahead */
          const PetscReal   *F = B + 9 * s;
          const PetscScalar *v = xp + 3 * off;
          y0 += F[0] * v[0] + F[1] * v[1] + F[2] * v[2];
          y1 += F[3] * v[0] + F[4] * v[1] + F[5] * v[2];
          y2 += F[6] * v[0] + F[7] * v[1] + F[8] * v[2];
        }
        if (in || (i - d->di[s] >= 0 && j - d->dj[s] >= 0 && i - d->di[s] < d->M)) { /* behind: transposed */
          const PetscReal   *T = d->blk + 9 * (d->ns * (g - off) + s);
          const PetscScalar *v = xp - 3 * off;
          y0 += T[0] * v[0] + T[3] * v[1] + T[6] * v[2];
          y1 += T[1] * v[0] + T[4] * v[1] + T[7] * v[2];
          y2 += T[2] * v[0] + T[5] * v[1] + T[8] * v[2];
        }
      }
      {
        const PetscInt k = 3 * ((j - d->ys) * d->xm + (i - d->xs));
        yy[k] = y0, yy[k + 1] = y1, yy[k + 2] = y2;
      }
    }
  }
  PetscCall(VecRestoreArrayRead(d->xl, &xl));
  PetscCall(VecRestoreArrayWrite(y, &yy));
  PetscCall(PetscLogFlops(18.0 * (2 * d->ns - 1) * d->xm * d->ym));
  PetscFunctionReturn(0);
}

static PetscErrorCode StencilGetDiagonal(Mat A, Vec diag)
{
  StencilData *d;
  PetscScalar *a;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &d));
  PetscCall(VecGetArrayWrite(diag, &a));
  for (PetscInt j = d->ys; j < d->ys + d->ym; j++)
    for (PetscInt i = d->xs; i < d->xs + d->xm; i++) {
      const PetscInt   g = (j - d->gys) * d->gxm + (i - d->gxs), k = 3 * ((j - d->ys) * d->xm + (i - d->xs));
      const PetscReal *B = d->blk + 9 * d->ns * g; /* the centre */
      a[k] = B[0], a[k + 1] = B[4], a[k + 2] = B[8];
    }
  PetscCall(VecRestoreArrayWrite(diag, &a));
  PetscFunctionReturn(0);
}

/* A + a I (TAO's Newton methods perturb the Hessian so): on the centre blocks' diagonals */
static PetscErrorCode StencilShift(Mat A, PetscScalar a)
{
  StencilData *d;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &d));
  for (PetscInt j = d->ys; j < d->ys + d->ym; j++)
    for (PetscInt i = d->xs; i < d->xs + d->xm; i++) {
      PetscReal *B = d->blk + 9 * d->ns * ((j - d->gys) * d->gxm + (i - d->gxs)); /* the centre */
      B[0] += a, B[4] += a, B[8] += a;
    }
  PetscCall(PetscObjectStateIncrease((PetscObject) A));
  PetscFunctionReturn(0);
}

static PetscErrorCode StencilZeroEntries(Mat A)
{
  StencilData *d;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &d));
  PetscCall(PetscArrayzero(d->blk, 9 * d->ns * d->gxm * d->gym));
  PetscFunctionReturn(0);
}

static PetscErrorCode StencilDestroy(Mat A)
{
  StencilData *d;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &d));
  PetscCall(PetscFree(d->blk));
  PetscCall(VecDestroy(&d->xl));
  PetscCall(PetscSFDestroy(&d->ghosts));
  if (d->unit != MPI_DATATYPE_NULL) PetscCallMPI(MPI_Type_free(&d->unit));
  PetscCall(DMDestroy(&d->dm));
  PetscCall(PetscFree(d));
  PetscFunctionReturn(0);
}

/* the ghost points of the patch (leaves) and where each lies in its owner's ghosted patch (root) */
static PetscErrorCode GhostsCreate(StencilData *d)
{
  PetscInt        m, n, w, nleaves = 0, *ilocal;
  const PetscInt *lx, *ly;
  PetscInt       *x0, *y0, *ox, *oy;
  PetscSFNode    *remote;

  PetscFunctionBeginUser;
  PetscCall(DMDAGetInfo(d->dm, NULL, NULL, NULL, NULL, &m, &n, NULL, NULL, &w, NULL, NULL, NULL, NULL));
  PetscCall(DMDAGetOwnershipRanges(d->dm, &lx, &ly, NULL));
  PetscCall(PetscMalloc4(m + 1, &x0, n + 1, &y0, d->M, &ox, d->N, &oy));
  x0[0] = y0[0] = 0;
  for (PetscInt a = 0; a < m; a++) {
    x0[a + 1] = x0[a] + lx[a];
    for (PetscInt i = x0[a]; i < x0[a + 1]; i++) ox[i] = a;
  }
  for (PetscInt b = 0; b < n; b++) {
    y0[b + 1] = y0[b] + ly[b];
    for (PetscInt j = y0[b]; j < y0[b + 1]; j++) oy[j] = b;
  }
  PetscCall(PetscMalloc2(d->gxm * d->gym, &ilocal, d->gxm * d->gym, &remote));
  for (PetscInt j = d->gys; j < d->gys + d->gym; j++)
    for (PetscInt i = d->gxs; i < d->gxs + d->gxm; i++) {
      const PetscInt a = ox[i], b = oy[j];
      PetscInt       gx0, gy0, gxe;
      if (i >= d->xs && i < d->xs + d->xm && j >= d->ys && j < d->ys + d->ym) continue;
      gx0 = PetscMax(x0[a] - w, 0), gxe = PetscMin(x0[a + 1] + w, d->M), gy0 = PetscMax(y0[b] - w, 0);
      ilocal[nleaves]       = (j - d->gys) * d->gxm + (i - d->gxs);
      remote[nleaves].rank  = b * m + a;
      remote[nleaves].index = (j - gy0) * (gxe - gx0) + (i - gx0);
      nleaves++;
    }
  PetscCall(PetscSFCreate(PetscObjectComm((PetscObject) d->dm), &d->ghosts));
  PetscCall(PetscSFSetGraph(d->ghosts, d->gxm * d->gym, nleaves, ilocal, PETSC_COPY_VALUES, remote, PETSC_COPY_VALUES));
  PetscCall(PetscSFSetUp(d->ghosts));
  PetscCall(PetscFree2(ilocal, remote));
  PetscCall(PetscFree4(x0, y0, ox, oy));
  PetscCallMPI(MPI_Type_contiguous((PetscMPIInt) (9 * d->ns), MPIU_REAL, &d->unit));
  PetscCallMPI(MPI_Type_commit(&d->unit));
  PetscFunctionReturn(0);
}

PetscErrorCode StencilMatCreate(DM dm, PetscInt nfull, const int di[], const int dj[], Mat *A)
{
  StencilData *d;
  PetscInt     zs, zm;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&d));
  d->unit = MPI_DATATYPE_NULL;
  PetscCall(PetscObjectReference((PetscObject) dm));
  d->dm = dm;
  for (int b = 0; b < 5; b++)
    for (int a = 0; a < 5; a++) d->slot[b][a] = -1, d->in[b][a] = PETSC_FALSE;
  for (PetscInt s = 0; s < nfull; s++) {
    PetscCheck(PetscAbsInt(di[s]) <= 2 && PetscAbsInt(dj[s]) <= 2, PETSC_COMM_SELF, PETSC_ERR_PLIB, "stencil reach");
    d->in[dj[s] + 2][di[s] + 2] = PETSC_TRUE;
  }
  d->di[0] = d->dj[0] = 0, d->slot[2][2] = 0, d->ns = 1; /* the centre, then the forward half in order */
  for (int b = -2; b <= 2; b++)
    for (int a = -2; a <= 2; a++) {
      if (!d->in[b + 2][a + 2]) continue;
      PetscCheck(d->in[2 - b][2 - a], PETSC_COMM_SELF, PETSC_ERR_PLIB, "an unsymmetric stencil");
      if (!StencilForward(a, b)) continue;
      d->di[d->ns] = a, d->dj[d->ns] = b, d->slot[b + 2][a + 2] = (int) d->ns++;
    }
  PetscCheck(d->in[2][2], PETSC_COMM_SELF, PETSC_ERR_PLIB, "a stencil without its centre");
  PetscCall(DMDAGetInfo(dm, NULL, &d->M, &d->N, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
  PetscCall(DMDAGetCorners(dm, &d->xs, &d->ys, &zs, &d->xm, &d->ym, &zm));
  PetscCall(DMDAGetGhostCorners(dm, &d->gxs, &d->gys, &zs, &d->gxm, &d->gym, &zm));
  PetscCall(CheckRankEntries(PetscObjectComm((PetscObject) dm), 9.0 * (double) d->ns * (double) d->gxm * (double) d->gym,
                             9 * d->ns, "its stiffness blocks, with its ghosts"));
  PetscCall(PetscCalloc1(9 * d->ns * d->gxm * d->gym, &d->blk));
  PetscCall(DMCreateLocalVector(dm, &d->xl));
  PetscCall(GhostsCreate(d));
  PetscCall(MatCreateShell(PetscObjectComm((PetscObject) dm), 3 * d->xm * d->ym, 3 * d->xm * d->ym, PETSC_DETERMINE,
                           PETSC_DETERMINE, d, A));
  {
    PetscInt w;
    PetscCall(DMDAGetInfo(dm, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, &w, NULL, NULL, NULL, NULL));
    for (PetscInt s = 0; s < d->ns; s++)
      PetscCheck(PetscAbsInt(d->di[s]) <= w && d->dj[s] <= w, PETSC_COMM_SELF, PETSC_ERR_PLIB,
                 "a stencil wider than the layout's ghosts");
  }
  PetscCall(MatSetBlockSize(*A, 3));
  PetscCall(MatShellSetOperation(*A, MATOP_MULT, (void (*)(void)) StencilMult));
  PetscCall(MatShellSetOperation(*A, MATOP_MULT_TRANSPOSE, (void (*)(void)) StencilMult)); /* symmetric */
  PetscCall(MatShellSetOperation(*A, MATOP_GET_DIAGONAL, (void (*)(void)) StencilGetDiagonal));
  PetscCall(MatShellSetManageScalingShifts(*A)); /* its own shift, on the blocks the preconditioner reads */
  PetscCall(MatShellSetOperation(*A, MATOP_SHIFT, (void (*)(void)) StencilShift));
  PetscCall(MatShellSetOperation(*A, MATOP_ZERO_ENTRIES, (void (*)(void)) StencilZeroEntries));
  PetscCall(MatShellSetOperation(*A, MATOP_DESTROY, (void (*)(void)) StencilDestroy));
  PetscCall(MatSetOption(*A, MAT_SYMMETRIC, PETSC_TRUE));
  PetscCall(MatSetDM(*A, dm));
  PetscFunctionReturn(0);
}

PetscBool StencilMatIs(Mat A)
{
  PetscBool shell = PETSC_FALSE;
  void (*op)(void) = NULL;

  if (!A || PetscObjectTypeCompare((PetscObject) A, MATSHELL, &shell) || !shell) return PETSC_FALSE;
  if (MatShellGetOperation(A, MATOP_MULT, &op)) return PETSC_FALSE;
  return op == (void (*)(void)) StencilMult ? PETSC_TRUE : PETSC_FALSE;
}

PetscErrorCode StencilMatGetData(Mat A, StencilData **d)
{
  PetscFunctionBeginUser;
  PetscCheck(StencilMatIs(A), PetscObjectComm((PetscObject) A), PETSC_ERR_ARG_WRONG, "not a stencil operator");
  PetscCall(MatShellGetContext(A, d));
  PetscFunctionReturn(0);
}

PetscErrorCode StencilMatAssemble(Mat A)
{
  StencilData *d;

  PetscFunctionBeginUser;
  PetscCall(StencilMatGetData(A, &d));
  PetscCall(PetscSFReduceBegin(d->ghosts, d->unit, d->blk, d->blk, MPI_SUM));
  PetscCall(PetscSFReduceEnd(d->ghosts, d->unit, d->blk, d->blk, MPI_SUM));
  PetscCall(PetscSFBcastBegin(d->ghosts, d->unit, d->blk, d->blk, MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(d->ghosts, d->unit, d->blk, d->blk, MPI_REPLACE));
  PetscCall(PetscObjectStateIncrease((PetscObject) A));
  PetscFunctionReturn(0);
}

PetscErrorCode StencilCoarseSlots(Mat A, PetscInt *nsc, int dic[], int djc[])
{
  StencilData *d;
  PetscBool    two = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(StencilMatGetData(A, &d));
  for (PetscInt s = 0; s < d->ns; s++)
    if (PetscAbsInt(d->di[s]) == 2 || PetscAbsInt(d->dj[s]) == 2) two = PETSC_TRUE;
  *nsc = 0;
  for (int b = -2; b <= 2; b++)
    for (int a = -2; a <= 2; a++) {
      const int aa = PetscAbsInt(a), bb = PetscAbsInt(b);
      if (aa + bb == 4 || (!two && (aa == 2 || bb == 2))) continue;
      dic[*nsc] = a, djc[*nsc] = b, (*nsc)++;
    }
  PetscFunctionReturn(0);
}

/* Every fine pair (p, q) of A, p owned, q in p's row (the whole stencil: the backward blocks are
   the neighbours' transposes), goes to the coarse pairs (I, J) over them with the product of
   their weights; a coarse pair is stored at I if J is I or ahead of I: the others are the
   transposes of those, by symmetry. Coarse points of other ranks' patches go to them. */
PetscErrorCode StencilMatGalerkin(Mat fine, Mat coarse)
{
  StencilData *f, *c;

  PetscFunctionBeginUser;
  PetscCall(StencilMatGetData(fine, &f));
  PetscCall(StencilMatGetData(coarse, &c));
  PetscCall(PetscArrayzero(c->blk, 9 * c->ns * c->gxm * c->gym));
  for (PetscInt j = f->ys; j < f->ys + f->ym; j++)
    for (PetscInt i = f->xs; i < f->xs + f->xm; i++) {
      const PetscInt g = (j - f->gys) * f->gxm + (i - f->gxs);
      PetscInt       ci[2], cj[2];
      PetscReal      wi[2], wj[2];
      const int      ni = StencilUnder(i, f->M, ci, wi), nj = StencilUnder(j, f->N, cj, wj);
      for (int dj = -2; dj <= 2; dj++)
        for (int di = -2; di <= 2; di++) {
          const PetscInt ic = i + di, jc = j + dj;
          PetscReal      B[9];
          PetscInt       qi[2], qj[2];
          PetscReal      vi[2], vj[2];
          int            mi, mj, nz = 0;
          if (ic < 0 || ic >= f->M || jc < 0 || jc >= f->N || !StencilBlock(f, g, di, dj, B)) continue;
          for (int e = 0; e < 9; e++) nz |= B[e] != 0;
          if (!nz) continue;
          mi = StencilUnder(ic, f->M, qi, vi), mj = StencilUnder(jc, f->N, qj, vj);
          for (int b = 0; b < nj; b++)
            for (int a = 0; a < ni; a++) {
              const PetscInt ic0 = ci[a], jc0 = cj[b];
              PetscReal     *row;
              PetscCheck(ic0 >= c->gxs && ic0 < c->gxs + c->gxm && jc0 >= c->gys && jc0 < c->gys + c->gym,
                         PETSC_COMM_SELF, PETSC_ERR_PLIB, "a Galerkin row outside the coarse ghosted patch");
              row = c->blk + 9 * c->ns * ((jc0 - c->gys) * c->gxm + (ic0 - c->gxs));
              for (int q = 0; q < mj; q++)
                for (int p = 0; p < mi; p++) {
                  const PetscInt  ddi = qi[p] - ic0, ddj = qj[q] - jc0;
                  const PetscReal w   = wi[a] * wj[b] * vi[p] * vj[q];
                  int             t;
                  PetscCheck(ddi >= -2 && ddi <= 2 && ddj >= -2 && ddj <= 2 && c->in[ddj + 2][ddi + 2], PETSC_COMM_SELF,
                             PETSC_ERR_PLIB, "a Galerkin block outside the coarse stencil");
                  if ((t = c->slot[ddj + 2][ddi + 2]) < 0) continue; /* behind: its transpose is stored at J */
                  for (int e = 0; e < 9; e++) row[9 * t + e] += w * B[e];
                }
            }
        }
    }
  PetscCall(StencilMatAssemble(coarse));
  PetscFunctionReturn(0);
}

PetscErrorCode StencilMatToAIJ(Mat A, Mat B)
{
  StencilData *d;

  PetscFunctionBeginUser;
  PetscCall(StencilMatGetData(A, &d));
  PetscCall(MatZeroEntries(B));
  for (PetscInt j = d->ys; j < d->ys + d->ym; j++)
    for (PetscInt i = d->xs; i < d->xs + d->xm; i++) {
      const PetscInt g  = (j - d->gys) * d->gxm + (i - d->gxs);
      PetscInt       nc = 0, cols[25];
      PetscScalar    vals[9 * 25];
      for (int dj = -2; dj <= 2; dj++)
        for (int di = -2; di <= 2; di++) {
          PetscReal K[9];
          if (i + di < 0 || i + di >= d->M || j + dj < 0 || j + dj >= d->N || !StencilBlock(d, g, di, dj, K)) continue;
          for (int r = 0; r < 3; r++)
            for (int q = 0; q < 3; q++) vals[r * 3 * 25 + 3 * nc + q] = K[3 * r + q];
          cols[nc++] = g + dj * d->gxm + di;
        }
      for (int r = 1; r < 3; r++) /* pack the 3 rows of 3 nc values */
        for (PetscInt q = 0; q < 3 * nc; q++) vals[r * 3 * nc + q] = vals[r * 3 * 25 + q];
      PetscCall(MatSetValuesBlockedLocal(B, 1, &g, nc, cols, vals, INSERT_VALUES));
    }
  PetscCall(MatAssemblyBegin(B, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(B, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}
