/* static.h - the quasi-static path (MODEL.md 14): each load step's balance as a minimum of the
 * total potential energy, by Newton-Krylov with multigrid (PETSc SNES) (static.c). */
#ifndef FABRIC_STATIC_H
#define FABRIC_STATIC_H

#include "fabric.h"

typedef struct _p_StaticSolver *StaticSolver;

typedef struct {                  /* one load step's solve */
  PetscInt  nonlinear_iterations; /* Newton steps */
  PetscInt  linear_iterations;    /* Krylov iterations over those steps */
  PetscReal residual;             /* the balance test's residual at the end (as the explicit path's) */
  PetscBool balanced;
  char      reason[64]; /* SNES's converged reason of the last attempt */
} StaticResult;

/* the SNES, its matrix (DMCreateMatrix of the grid's DMDA) and the preconditioner's defaults;
   PETSc's options (-snes_*, -ksp_*, -pc_*) override them */
PetscErrorCode StaticCreate(Fabric fab, StaticSolver *ss);
PetscErrorCode StaticDestroy(StaticSolver *ss);
/* -static_sequence: the fabric at half the thread density and its solver (NULL, NULL: none); the
   driver brings it to the load step and solves it (its coarser ones first) before this one's solve,
   which starts from the coarse change interpolated */
void StaticCoarser(StaticSolver ss, Fabric *cfab, StaticSolver *coarse);
typedef struct {         /* a solve under way, after one of its Newton steps */
  PetscInt  attempt_its; /* Newton steps of the current attempt (a failed attempt is retried, stiffer) */
  PetscInt  its, lits;   /* Newton steps and Krylov iterations of the solve so far, every attempt */
  PetscReal next_shift;  /* the shift the next Newton step takes */
  PetscReal rnorm0;      /* the attempt's first residual norm (SNES's divergence test is relative to it) */
} StaticProgress;

typedef struct { /* the driver's look after each Newton step of a solve that goes on (signals, the clock's
                    checkpoints); *stop ends the solve */
  PetscErrorCode (*look)(void *ctx, const StaticProgress *p, PetscBool *stop);
  void *ctx;
} StaticWatch;

/* balance the current load step from the current positions (the prediction is the first guess),
   with the crossings of inv_m = 0 held where they are; watch (or NULL) looks after each Newton step */
PetscErrorCode StaticSolve(StaticSolver ss, const StaticWatch *watch, StaticResult *r);
/* a restart within a solve: the next StaticSolve goes on from the current positions (a checkpoint's
   iterate, its next shift restored), its attempt already `attempt_its` Newton steps in */
void StaticResume(StaticSolver ss, PetscInt attempt_its);

#endif
