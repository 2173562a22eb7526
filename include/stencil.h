/* stencil.h - a symmetric block operator on the grid's layout stored by stencil (stencil.c): per
 * crossing, its centre 3x3 block and one for each neighbour of the forward half of a fixed
 * stencil (the backward ones are their neighbours' transposes), no column indices. The
 * quasi-static path's tangent and its multigrid levels' Galerkin operators, as a MATSHELL whose
 * product reads each block once (docs/static.md). */
#ifndef FABRIC_STENCIL_H
#define FABRIC_STENCIL_H

#include <petscdmda.h>
#include <petscmat.h>

#define STENCIL_MAX_SLOTS 21

/* the coarse point(s) c over fine point i of a side of M points, and their weights (linear): the
   coarse point I lies on the fine point min(2I, M - 1) (the multigrid levels of src/static.c) */
static inline int StencilUnder(PetscInt i, PetscInt M, PetscInt c[2], PetscReal w[2])
{
  if (i % 2 == 0 || i == M - 1) {
    c[0] = (i + 1) / 2, w[0] = 1;
    return 1;
  }
  c[0] = (i - 1) / 2, c[1] = (i + 1) / 2, w[0] = w[1] = 0.5;
  return 2;
}

/* The multigrid levels' coarsening rule (src/static.c): an M x N grid on m x n ranks is coarsened to
   (M/2 + 1) x (N/2 + 1) while both sides keep at least 4 coarse points a rank and 3 points in all. A
   grid whose side has an odd number of spacings is coarsened only while it has more than
   MG_COARSEST points: such coarse spaces are poorer, and on the 201 x 201 net two more of them below
   26 x 26 took 496 Krylov iterations against 321 (docs/static.md). */
#define MG_COARSEST   1024
#define MG_MAX_LEVELS 12 /* the finest grid's included */
static inline int MultigridCoarsens(PetscInt M, PetscInt N, PetscInt m, PetscInt n)
{
  return !((((M - 1) % 2 || (N - 1) % 2) && M * N <= MG_COARSEST) || M / 2 + 1 < 4 * m || N / 2 + 1 < 4 * n ||
           M < 3 || N < 3);
}

/* a neighbour (di, dj) whose block is stored (a forward one: the row's own is the transpose of its
   neighbour's) */
static inline int StencilForward(int di, int dj) { return dj > 0 || (dj == 0 && di > 0); }

typedef struct {
  DM         dm;                        /* the layout (dof 3; its ghost width covers the stencil) */
  PetscInt   ns;                        /* stored slots: 0 the centre, then the forward neighbours */
  int        di[STENCIL_MAX_SLOTS], dj[STENCIL_MAX_SLOTS];
  int        slot[5][5];                /* stored slot of the neighbour (di, dj): slot[dj + 2][di + 2];
                                           -1 for a backward one or none */
  PetscBool  in[5][5];                  /* (di, dj) is in the stencil (either half) */
  PetscInt   M, N, xs, ys, xm, ym;      /* the grid, the owned patch */
  PetscInt   gxs, gys, gxm, gym;        /* the ghosted patch: blk's layout */
  PetscReal *blk;                       /* per ghosted point, ns 3x3 blocks (row-major): row i couples
                                           (i + di, j + dj); after StencilMatAssemble a ghost point
                                           holds its owner's blocks */
  Vec        xl;                        /* the product's ghosted input */
  PetscSF    ghosts;                    /* ghost points' blocks (leaves) and their owners' (roots) */
  MPI_Datatype unit;                    /* a point's ns blocks */
} StencilData;

/* the block of the row of ghosted point g for its neighbour (di, dj) into K (0 if none): stored
   there, or the transpose of the block stored at the neighbour for (-di, -dj); returns whether
   (di, dj) is in the stencil */
static inline PetscBool StencilBlock(const StencilData *d, PetscInt g, int di, int dj, PetscReal K[9])
{
  int s;
  if (di < -2 || di > 2 || dj < -2 || dj > 2 || !d->in[dj + 2][di + 2]) {
    for (int e = 0; e < 9; e++) K[e] = 0;
    return PETSC_FALSE;
  }
  if ((s = d->slot[dj + 2][di + 2]) >= 0)
    for (int e = 0; e < 9; e++) K[e] = d->blk[9 * (d->ns * g + s) + e];
  else {
    const PetscReal *T = d->blk + 9 * (d->ns * (g + dj * d->gxm + di) + d->slot[2 - dj][2 - di]);
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) K[3 * r + c] = T[3 * c + r];
  }
  return PETSC_TRUE;
}

/* a MATSHELL of the layout dm with the symmetric stencil of nfull neighbours (di[s], dj[s])
   (|di|, |dj| <= 2, the centre among them), zero; MatMult, MatMultTranspose (the same:
   symmetric), MatGetDiagonal, MatShift, MatZeroEntries */
PetscErrorCode StencilMatCreate(DM dm, PetscInt nfull, const int di[], const int dj[], Mat *A);
PetscBool      StencilMatIs(Mat A);
PetscErrorCode StencilMatGetData(Mat A, StencilData **d);
/* after the stored blocks are written (owned and ghost points): adds the ghost points' blocks into
   their owners', brings the sums back to the ghost points, and marks the operator changed */
PetscErrorCode StencilMatAssemble(Mat A);
/* the stencil of the Galerkin operator P^T A P of A's (the levels' bilinear P): the 3x3 box, and
   with points two apart the box with the points (+-2, +-1) and (+-1, +-2) (21 neighbours) */
PetscErrorCode StencilCoarseSlots(Mat A, PetscInt *nc, int dic[], int djc[]);
/* coarse = P^T fine P for the levels' bilinear interpolation (StencilUnder), coarse's layout the
   coarsening of fine's (src/static.c: CoarsenLayout) */
PetscErrorCode StencilMatGalerkin(Mat fine, Mat coarse);
/* the same operator into B, an AIJ matrix of A's layout (DMCreateMatrix) */
PetscErrorCode StencilMatToAIJ(Mat A, Mat B);

#endif
