/* stencil.h - a block operator on the grid's layout stored by stencil (stencil.c): per crossing, one
 * 3x3 block for each neighbour of a fixed stencil, no column indices. The quasi-static path's
 * tangent and its multigrid levels' Galerkin operators, as a MATSHELL whose product reads each
 * block once (docs/static.md). */
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

typedef struct {
  DM         dm;                        /* the layout (dof 3; its ghost width covers the stencil) */
  PetscInt   ns;                        /* stencil slots */
  int        di[STENCIL_MAX_SLOTS], dj[STENCIL_MAX_SLOTS];
  int        slot[5][5];                /* slot of the neighbour (di, dj): slot[dj + 2][di + 2], -1 if none */
  PetscInt   M, N, xs, ys, xm, ym;      /* the grid, the owned patch */
  PetscInt   gxs, gys, gxm, gym;        /* the ghosted patch: blk's layout */
  PetscReal *blk;                       /* per ghosted point, ns 3x3 blocks (row-major): row i couples
                                           (i + di, j + dj); a ghost point's blocks go to its owner */
  Vec        xl;                        /* the product's ghosted input */
  PetscSF    ghosts;                    /* ghost points' blocks (leaves) onto their owners' (roots) */
  MPI_Datatype unit;                    /* a point's ns blocks */
} StencilData;

/* a MATSHELL of the layout dm with the ns neighbours (di[s], dj[s]) (|di|, |dj| <= 2), zero;
   MatMult, MatMultTranspose (the same: symmetric), MatGetDiagonal, MatShift, MatZeroEntries */
PetscErrorCode StencilMatCreate(DM dm, PetscInt ns, const int di[], const int dj[], Mat *A);
PetscBool      StencilMatIs(Mat A);
PetscErrorCode StencilMatGetData(Mat A, StencilData **d);
/* after the blocks are written (owned and ghost points): adds the ghost points' blocks into
   their owners' and marks the operator changed */
PetscErrorCode StencilMatAssemble(Mat A);
/* the stencil of the Galerkin operator P^T A P of a stencil (the levels' bilinear P): the 3x3 box,
   and with points two apart the box with the points (+-2, +-1) and (+-1, +-2) (21 slots) */
void StencilCoarseSlots(PetscInt ns, const int di[], const int dj[], PetscInt *nsc, int dic[], int djc[]);
/* coarse = P^T fine P for the levels' bilinear interpolation (StencilUnder), coarse's layout the
   coarsening of fine's (src/static.c: CoarsenLayout) */
PetscErrorCode StencilMatGalerkin(Mat fine, Mat coarse);
/* the same operator into B, an AIJ matrix of A's layout (DMCreateMatrix) */
PetscErrorCode StencilMatToAIJ(Mat A, Mat B);

#endif
