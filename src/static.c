/* static.c - the quasi-static path (MODEL.md 14): each load step's balanced state as a minimum
 * of the total potential energy Pi, by Newton-Krylov (PETSc SNES) on the grid's DMDA.
 *
 * Unknowns: every crossing's position (a vector of the DMDA, dof 3). A free crossing
 * (inv_m > 0) has the residual R = -F, F = -grad Pi: internal forces, the point load, the
 * bodies' penalty contact and gravity. A clamped, grip or absent crossing has R = k_bc (x - x_bc)
 * and an identity row scaled by k_bc, its couplings left out of the free rows: the tangent
 * stays symmetric, and Newton never moves it.
 * Objective: Pi (SNESSetObjective). The backtracking line search then decreases the energy,
 * which stays convex across the yarn law's kinks, where |F| need not decrease.
 * Tangent: assembled by rows (FormJacobian) into an operator stored by stencil (stencil.h: 3x3
 * blocks, no indices), or with -static_tangent aij into an AIJ matrix preallocated with the
 * blocks the terms fill (CreateTangent): the force terms' blocks (TermTangent), the bodies' penalty Hessians, plus a
 * pretension shift: every existing segment carries an extra geometric stiffness k_s I (a graph
 * Laplacian of the yarns). A flat net without tension has a singular tangent (no out-of-plane
 * stiffness) and compressed yarns an indefinite one; the shift makes both solvable and spreads a
 * load over the whole net in one linear solve. k_s adapts like a Levenberg-Marquardt parameter:
 * divided by 10 after a full Newton step, multiplied by 4 after a step the line search cut below
 * 1/4, by 100 after a failed solve (which is retried from where it stopped), and 0 once below
 * 1e-12 of the yarns' stiffness, so the last steps are plain Newton steps and converge fast.
 * The first load step starts at -snes_shift_start, a later one from 10x where the last ended.
 * First guess: the free crossings extrapolated in the load factor through the last three balanced
 * states (-snes_extrapolate), unless the driver's prediction moved them; without a prediction
 * the crossings inside the ball move out onto its surface (LeaveSphere).
 * Linear solves: CG (on the true residual) preconditioned by geometric multigrid on the DMDA
 * hierarchy (MultigridHierarchy: any grid size; Galerkin coarse operators, by stencil formed here:
 * RefreshLevels), smoothed by
 * alternating block-line relaxation (LineSmoother: a yarn is 1/strain times stiffer along itself
 * than across, which point smoothers cannot smooth; every line solved whole, across ranks too);
 * on a grid too small to coarsen, CG on LU factors (MUMPS; GAMG with the rigid-body modes without it).
 * All are overridden by -snes_*, -ksp_*, -pc_*, -mg_* (the options prefix is none).
 * Convergence: the explicit path's balance test (the largest free force over the larger of the
 * largest yarn tension and the force floor) at -balance_tol.
 */
#include <petsc/private/pcimpl.h> /* pc->setupcalled: a block preconditioner's blocks exist */
#include <petsc/private/snesimpl.h> /* snes->rnorm0: a restart within a solve keeps its divergence test's reference */
#include "static.h"
#include "static_options.h"
#include "bodies.h"
#include "comm.h"
#include "integrate.h"
#include "stencil.h"

#include <petscsf.h>
#include <petscsnes.h>
#include <petsctao.h>

#include <stdlib.h>
#include <string.h>

#define SHIFT_FLOOR  1e-12 /* below this k_s / k_ref the shift is dropped */
#define MAX_ATTEMPTS 8     /* SNES solves per load step, each after a failed one */
#define ENERGY_NOISE 1e-10 /* a predicted change of Pi below this fraction of |Pi| is rounding noise */

typedef struct {   /* three grid rows of block rows, the ghost points either side included */
  PetscReal *buf[3]; /* grid row j in buf[(j - ys + 1) % 3]: per point (xs - 1 ... xs + xm) ROW_SLOTS 3x3 blocks */
  PetscInt   jo;     /* the row whose owners are being visited */
  PetscBool  used[13]; /* the slots of the terms' stencil */
} RowRing;

struct _p_StaticSolver {
  Fabric         fab;
  SNES           snes;
  Tao            tao; /* -static_minimizer tao: TAO's Newton on Pi instead of SNES */
  DM             dm; /* the grid's layout with the tangent's stencil (the SNES's and multigrid's DM) */
  Mat            J;
  Vec            Xbc;    /* positions of the held crossings this load step */
  Vec            Xstart; /* the first guess of this load step (a solve that reached a state not finite restarts there) */
  unsigned char *free_g; /* ghosted: the crossing is free (inv_m > 0) */
  PetscReal      k_ref;  /* N/m: stiffness scale (a yarn segment's), for k_bc and the shift */
  PetscReal      tmax;   /* largest yarn tension of the last evaluation (the balance test's scale) */
  StaticHistory *h;        /* the fabric's: the last balanced states and the shift (checkpointed) */
  StaticOptions  opt;
  RowRing        ring;     /* the tangent's block rows being accumulated (FormJacobian) */
  PetscInt       tangents; /* assembled so far: a level's line smoother factors its operator once for each */
  PetscInt       levels;   /* of the multigrid hierarchy (MultigridHierarchy; 1: none) */
  DM             dms[MG_MAX_LEVELS]; /* the levels' layouts, the coarsest first, dms[levels - 1] = dm */
  Mat            Ps[MG_MAX_LEVELS];  /* Ps[l]: interpolation from level l - 1 to l */
  PetscBool      stencil;  /* J and the coarse operators stored by stencil (stencil.h) */
  int            sslot[13]; /* stencil: the stored slot of J of each ring slot (-1: behind, or not in the stencil) */
  Mat            Ac[MG_MAX_LEVELS]; /* stencil: the levels' Galerkin operators below the finest */
  Mat            Acoarse;  /* stencil: the coarsest level's, assembled for its direct solve */
  PetscInt       levels_at; /* stencil: the tangent number the coarse operators were formed from */
  /* grid sequencing (-static_sequence): the fabric at half the thread density and its solver */
  Fabric         cfab;
  StaticSolver   coarse;
  Vec            cnat, lnat;   /* the coarse fabric's grid and the level below's, in the natural ordering */
  VecScatter     nat;          /* cnat to lnat (the same ordering, the two layouts' shares) */
  Vec            clevel;       /* a vector of the multigrid level below this one (dms[levels - 2]) */
  Vec            fcorr, fwt;   /* the interpolated change, and the interpolated weight of existing coarse points */
  Vec            cmask;        /* coarse fabric: 1 on an existing crossing, 0 on an absent one */
  PetscInt       corrected_at; /* the load step whose coarse solution last corrected the first guess */
  /* as the coarse level of a finer solver: this load step's first guess and how its solve ended */
  Vec            guess;
  PetscBool      guess_rest;   /* the first guess had no balanced state behind it (the rest state) */
  PetscInt       solved_at;    /* the load step last solved, -1: none */
  PetscBool      solved_balanced;
  /* the solve under way (StaticSolve) */
  const StaticWatch *watch;       /* the driver's look after each Newton step (NULL: none) */
  PetscInt           done_its;    /* Newton steps of the solve's earlier attempts */
  PetscInt           done_lits;   /* their Krylov iterations */
  PetscInt           resume;      /* StaticResume: the Newton steps the checkpoint's attempt had taken, 0: none */
  PetscInt           base;        /* the Newton steps of the current attempt before a restart (its first attempt) */
  PetscReal          rnorm0;      /* that attempt's first residual norm, restored (0: none) */
  PetscBool          watch_stop;  /* the look ended the solve */
};

/* gravity on the free owned points and the residual rows of the held ones */
static PetscErrorCode FormFunction(SNES snes, Vec U, Vec R, void *ctx)
{
  StaticSolver       ss  = (StaticSolver) ctx;
  Fabric             fab = ss->fab;
  const PetscReal   *g   = fab->load.gravity_now;
  const PetscScalar *u, *xb;
  PetscScalar       *r;

  PetscFunctionBeginUser;
  (void) snes;
  PetscCall(ComputeForcesAt(fab, U, R, NULL, &ss->tmax));
  PetscCall(VecGetArrayRead(U, &u));
  PetscCall(VecGetArrayRead(ss->Xbc, &xb));
  PetscCall(VecGetArray(R, &r));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) {
    if (fab->grid.inv_m[k] > 0)
      for (int d = 0; d < 3; d++) r[3 * k + d] = -(r[3 * k + d] + fab->grid.mass[k] * g[d]);
    else
      for (int d = 0; d < 3; d++) r[3 * k + d] = ss->k_ref * (u[3 * k + d] - xb[3 * k + d]);
  }
  PetscCall(VecRestoreArray(R, &r));
  PetscCall(VecRestoreArrayRead(ss->Xbc, &xb));
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCall(GlobalMax(fab->comm, &ss->tmax, 1));
  PetscFunctionReturn(0);
}

/* Pi at U (up to a constant: the held crossings do not move) */
static PetscErrorCode FormObjective(SNES snes, Vec U, PetscReal *pi, void *ctx)
{
  StaticSolver       ss     = (StaticSolver) ctx;
  Fabric             fab    = ss->fab;
  const Patch       *p      = &fab->grid.patch;
  const PetscInt     all[4] = {p->xs, p->xs + p->xm, p->ys, p->ys + p->ym};
  const PetscReal   *g      = fab->load.gravity_now;
  const PetscScalar *xl, *u;
  PetscReal          E, c[BODY_KINDS][3];

  PetscFunctionBeginUser;
  (void) snes;
  PetscCall(HaloExchange(fab->grid.da, U, fab->state.Xl));
  PetscCall(VecGetArrayRead(fab->state.Xl, &xl));
  E = InternalEnergy(p, xl, all);
  PetscCall(VecRestoreArrayRead(fab->state.Xl, &xl));
  for (PetscInt q = 0; q < fab->bodies.n; q++) BodyPosition(&fab->bodies.body[q], fab->load.travel_now, c[q]);
  PetscCall(VecGetArrayRead(U, &u));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) {
    if (!(fab->grid.inv_m[k] > 0)) continue;
    for (int d = 0; d < 3; d++) E -= fab->grid.mass[k] * g[d] * u[3 * k + d];
    for (PetscInt q = 0; q < fab->bodies.n; q++) {
      PetscReal gb[3], Kb[9];
      E += BodyEnergy(&fab->bodies.body[q], c[q], u + 3 * k, gb, Kb);
    }
  }
  if (fab->grid.load_index >= 0)
    for (int d = 0; d < 3; d++)
      E -= fab->load.load_factor * fab->s.load.point_load[d] * u[3 * fab->grid.load_index + d];
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCall(GlobalSum(fab->comm, &E, 1));
  *pi = E;
  PetscFunctionReturn(0);
}

/* The tangent is assembled by rows. An instance owned by a point of grid row j (a segment, a
   bending centre, a shear crossing) has its points within one of its owner, so it adds only to
   the block rows of grid rows j-1, j and j+1: those three rows (with the ghost points either side
   of the patch) are accumulated in a ring of row buffers while the owners of row j are visited,
   and row j-1, then complete, is inserted, one MatSetValuesBlockedLocal per crossing. A block row
   has a slot per stencil neighbour: (di, dj) in the 3x3 box and (+-2, 0), (0, +-2) (bending). */
#define ROW_SLOTS 13
static const int SlotDi[ROW_SLOTS] = {0, -1, 0, 1, -2, -1, 0, 1, 2, -1, 0, 1, 0};
static const int SlotDj[ROW_SLOTS] = {-2, -1, -1, -1, 0, 0, 0, 0, 0, 1, 1, 1, 2};
#define SLOT_CENTRE 6

static inline int SlotOf(PetscInt di, PetscInt dj)
{
  static const int slot[5][5] = {
    {-1, -1, 0, -1, -1}, {-1, 1, 2, 3, -1}, {4, 5, 6, 7, 8}, {-1, 9, 10, 11, -1}, {-1, -1, 12, -1, -1}};
  return (di < -2 || di > 2 || dj < -2 || dj > 2) ? -1 : slot[dj + 2][di + 2];
}

/* the slots a tangent of these terms fills: the star of width 1 (traction), the box's corners
   with shear, the points two apart along a yarn with bending */
static PetscBool SlotUsed(const Patch *p, int s)
{
  const int ai = PetscAbsInt(SlotDi[s]), aj = PetscAbsInt(SlotDj[s]);
  if (ai + aj <= 1) return PETSC_TRUE;
  if (ai == 1 && aj == 1) return p->shear;
  return p->bending;
}

/* a TermBlocksFn: adds the blocks between free crossings (those of held ones are left out) to
   the rows of the ring */
static PetscErrorCode AddFreeBlocks(void *ctx, PetscInt n, const PetscInt i[], const PetscInt j[], const PetscReal K[])
{
  StaticSolver ss = (StaticSolver) ctx;
  RowRing     *rr = &ss->ring;
  const Patch *p  = &ss->fab->grid.patch;
  int          held[TERM_MAX_POINTS];

  PetscFunctionBeginUser;
  for (PetscInt q = 0; q < n; q++) held[q] = !ss->free_g[(j[q] - p->gys) * p->gxm + (i[q] - p->gxs)];
  for (PetscInt a = 0; a < n; a++) {
    PetscReal *row;
    if (held[a]) continue;
    PetscCheck(j[a] >= rr->jo - 1 && j[a] <= rr->jo + 1 && i[a] >= p->xs - 1 && i[a] <= p->xs + p->xm, PETSC_COMM_SELF,
               PETSC_ERR_PLIB,
               "a tangent block of row (%" PetscInt_FMT ", %" PetscInt_FMT ") from an owner in row %" PetscInt_FMT,
               i[a], j[a], rr->jo);
    row = rr->buf[(j[a] - p->ys + 1) % 3] + 9 * ROW_SLOTS * (i[a] - p->xs + 1);
    for (PetscInt b = 0; b < n; b++) {
      const int s = held[b] ? -1 : SlotOf(i[b] - i[a], j[b] - j[a]);
      if (held[b]) continue;
      PetscCheck(s >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "a tangent block outside the stencil");
      for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) row[9 * s + 3 * r + c] += K[(3 * a + r) * 3 * n + 3 * b + c];
    }
  }
  PetscFunctionReturn(0);
}

/* inserts the block rows of grid row jr held in the ring and clears them: an owned crossing's row
   with every slot of the stencil inside the grid (zeros too, so that the matrix keeps one nonzero
   structure), a ghost crossing's with its nonzero blocks only (they go to the owner at assembly) */
static PetscErrorCode FlushRow(StaticSolver ss, PetscInt jr)
{
  RowRing     *rr = &ss->ring;
  const Patch *p  = &ss->fab->grid.patch;
  PetscReal   *buf;
  PetscInt     gxs, gys, gxm, gym, zs, zm;

  PetscFunctionBeginUser;
  if (jr < p->ys - 1) PetscFunctionReturn(0);
  buf = rr->buf[(jr - p->ys + 1) % 3];
  if (jr >= 0 && jr < p->ny && ss->stencil) { /* the row's blocks into the stencil's slots */
    StencilData *d;
    PetscCall(StencilMatGetData(ss->J, &d));
    for (PetscInt i = PetscMax(p->xs - 1, 0); i < PetscMin(p->xs + p->xm + 1, p->nx); i++) {
      const PetscReal *row = buf + 9 * ROW_SLOTS * (i - p->xs + 1);
      PetscReal       *B   = d->blk + 9 * d->ns * ((jr - d->gys) * d->gxm + (i - d->gxs));
      for (int s = 0; s < ROW_SLOTS; s++)
        if (ss->sslot[s] >= 0) PetscCall(PetscArraycpy(B + 9 * ss->sslot[s], row + 9 * s, 9));
    }
  } else if (jr >= 0 && jr < p->ny) {
    PetscCall(DMDAGetGhostCorners(ss->dm, &gxs, &gys, &zs, &gxm, &gym, &zm));
    for (PetscInt i = PetscMax(p->xs - 1, 0); i < PetscMin(p->xs + p->xm + 1, p->nx); i++) {
      const PetscReal *row   = buf + 9 * ROW_SLOTS * (i - p->xs + 1);
      const PetscBool  owned = (i >= p->xs && i < p->xs + p->xm && jr >= p->ys && jr < p->ys + p->ym) ? PETSC_TRUE
                                                                                                       : PETSC_FALSE;
      const PetscInt   lrow  = (jr - gys) * gxm + (i - gxs);
      PetscInt         nc    = 0, cols[ROW_SLOTS];
      int              sl[ROW_SLOTS];
      PetscReal        vals[9 * ROW_SLOTS];
      for (int s = 0; s < ROW_SLOTS; s++) {
        const PetscInt ic = i + SlotDi[s], jc = jr + SlotDj[s];
        PetscBool      keep;
        if (ic < 0 || ic >= p->nx || jc < 0 || jc >= p->ny || !rr->used[s]) continue;
        keep = owned;
        for (int e = 0; e < 9 && !keep; e++) keep = row[9 * s + e] != 0 ? PETSC_TRUE : PETSC_FALSE;
        if (!keep) continue;
        cols[nc] = (jc - gys) * gxm + (ic - gxs);
        sl[nc++] = s;
      }
      for (PetscInt q = 0; q < nc; q++) /* 3 rows of 3 nc values */
        for (int r = 0; r < 3; r++)
          for (int c = 0; c < 3; c++) vals[r * 3 * nc + 3 * q + c] = row[9 * sl[q] + 3 * r + c];
      if (nc) PetscCall(MatSetValuesBlockedLocal(ss->J, 1, &lrow, nc, cols, vals, ADD_VALUES));
    }
  }
  PetscCall(PetscArrayzero(buf, 9 * ROW_SLOTS * (p->xm + 2)));
  PetscFunctionReturn(0);
}

/* the pretension shift k_s I on the segments owned by the points of row j (each owns its +x and
   +y segment) */
static PetscErrorCode AddShift(StaticSolver ss, PetscInt j)
{
  const Patch    *p  = &ss->fab->grid.patch;
  const PetscReal ks = ss->h->shift * ss->k_ref;
  PetscReal       K[36];

  PetscFunctionBeginUser;
  if (!(ks > 0)) PetscFunctionReturn(0);
  for (int a = 0; a < 6; a++)
    for (int b = 0; b < 6; b++) K[6 * a + b] = (a % 3 == b % 3) ? (a / 3 == b / 3 ? ks : -ks) : 0.0;
  for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
    const PetscInt g = (j - p->gys) * p->gxm + (i - p->gxs);
    if (!p->exists[g]) continue;
    if (i + 1 < p->nx && p->exists[g + 1] && !p->broken_x[g]) {
      const PetscInt ii[2] = {i, i + 1}, jj[2] = {j, j};
      PetscCall(AddFreeBlocks(ss, 2, ii, jj, K));
    }
    if (j + 1 < p->ny && p->exists[g + p->gxm] && !p->broken_y[g]) {
      const PetscInt ii[2] = {i, i}, jj[2] = {j, j + 1};
      PetscCall(AddFreeBlocks(ss, 2, ii, jj, K));
    }
  }
  PetscFunctionReturn(0);
}

/* the bodies' penalty Hessians on the free points of row j and the held points' scaled identity
   rows */
static void AddPointBlocks(StaticSolver ss, const PetscScalar *u, const PetscReal c[][3], PetscInt j)
{
  Fabric       fab = ss->fab;
  const Patch *p   = &fab->grid.patch;

  for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
    const PetscInt k   = (j - p->ys) * p->xm + (i - p->xs);
    PetscReal     *row = ss->ring.buf[(j - p->ys + 1) % 3] + 9 * ROW_SLOTS * (i - p->xs + 1) + 9 * SLOT_CENTRE;
    if (fab->grid.inv_m[k] > 0) {
      for (PetscInt q = 0; q < fab->bodies.n; q++) {
        PetscReal gb[3], Kb[9];
        if (!(BodyEnergy(&fab->bodies.body[q], c[q], u + 3 * k, gb, Kb) > 0)) continue;
        if (ss->opt.convex) SymPositivePart(3, Kb); /* a curved body's tangential part is negative */
        for (int e = 0; e < 9; e++) row[e] += Kb[e];
      }
    } else
      row[0] += ss->k_ref, row[4] += ss->k_ref, row[8] += ss->k_ref;
  }
}

static PetscErrorCode FreeForceMax(StaticSolver ss, Vec R, PetscReal *fmax);

/* The tangent's geometric part of a compressed segment: dropped (the tension field, max(T,0)/L: positive
   semi-definite, so CG and the line search work far from balance), or kept (the exact Hessian) where the
   iterate's balance ratio, its largest free force over the balance test's scale, is below
   -static_exact_tangent: on a mostly slack fabric near rest the tension field's Newton converges only linearly,
   the exact Hessian's quadratically. Decided afresh at each tangent from its iterate alone, so that a restart
   takes the same steps. -snes_convex_tangent drops the part in any case. */
static PetscErrorCode ChooseTangent(StaticSolver ss, Vec U, PetscBool *exact)
{
  Fabric    fab = ss->fab;
  Vec       R;
  PetscReal fmax, ratio;

  PetscFunctionBeginUser;
  *exact = PETSC_FALSE;
  if (!(ss->opt.exact_below > 0) || ss->opt.convex) PetscFunctionReturn(0);
  PetscCall(DMGetGlobalVector(fab->grid.da, &R));
  PetscCall(FormFunction(NULL, U, R, ss));
  PetscCall(FreeForceMax(ss, R, &fmax));
  PetscCall(DMRestoreGlobalVector(fab->grid.da, &R));
  ratio  = fmax / PetscMax(ss->tmax, fab->step.force_floor);
  *exact = ratio < ss->opt.exact_below ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PetscInfo(NULL, "tangent at balance ratio %g: %s\n", (double) ratio, *exact ? "exact" : "tension field"));
  PetscFunctionReturn(0);
}

static PetscErrorCode FormJacobian(SNES snes, Vec U, Mat A, Mat P, void *ctx)
{
  StaticSolver       ss  = (StaticSolver) ctx;
  Fabric             fab = ss->fab;
  const Patch       *p   = &fab->grid.patch;
  RowRing           *rr  = &ss->ring;
  const PetscScalar *xl, *u;
  PetscReal          c[BODY_KINDS][3];
  PetscBool          exact;

  PetscFunctionBeginUser;
  (void) snes;
  (void) A;
  if (P != ss->J) { /* a solver asked the grid's DM for the tangent in another matrix (say PCTelescope's) */
    char given[448];
    SolverOptionsGiven(given, sizeof given);
    SETERRQ(fab->comm, PETSC_ERR_SUP,
            "a solver asked for the tangent in a matrix of its own; the quasi-static solver assembles only its own%s%s%s",
            given[0] ? " (the solver options given: " : "", given, given[0] ? ")" : "");
  }
  PetscCall(ChooseTangent(ss, U, &exact));
  PetscCall(MatZeroEntries(P));
  ss->tangents++;
  PetscCall(HaloExchange(fab->grid.da, U, fab->state.Xl));
  for (PetscInt q = 0; q < fab->bodies.n; q++) BodyPosition(&fab->bodies.body[q], fab->load.travel_now, c[q]);
  for (int s = 0; s < ROW_SLOTS; s++) rr->used[s] = SlotUsed(p, s);
  for (int q = 0; q < 3; q++) PetscCall(PetscArrayzero(rr->buf[q], 9 * ROW_SLOTS * (p->xm + 2)));
  PetscCall(VecGetArrayRead(fab->state.Xl, &xl));
  PetscCall(VecGetArrayRead(U, &u));
  fab->grid.patch.tension_field = !exact; /* for this tangent only: else the kernels' Hessians are exact */
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++) { /* the ring holds rows j-1, j, j+1 */
    const PetscInt row[4] = {p->xs, p->xs + p->xm, j, j + 1};
    rr->jo                = j;
    PetscCall(InternalTangent(p, xl, row, ss->opt.convex, AddFreeBlocks, ss));
    PetscCall(AddShift(ss, j));
    AddPointBlocks(ss, u, (const PetscReal(*)[3]) c, j);
    PetscCall(FlushRow(ss, j - 1)); /* complete: its buffer becomes row j+2's */
  }
  fab->grid.patch.tension_field = PETSC_FALSE;
  PetscCall(FlushRow(ss, p->ys + p->ym - 1));
  PetscCall(FlushRow(ss, p->ys + p->ym));
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCall(VecRestoreArrayRead(fab->state.Xl, &xl));
  if (ss->stencil) PetscCall(StencilMatAssemble(P)); /* the coarse operators follow: RefreshLevels */
  else {
    PetscCall(MatAssemblyBegin(P, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(P, MAT_FINAL_ASSEMBLY));
  }
  PetscFunctionReturn(0);
}

/* The line search along the Newton step Y (X - lambda Y). Far from balance it searches on Pi:
   a full step if it decreases Pi enough (Armijo), else backtracking with a safeguarded
   quadratic fit. Near balance the decrease Newton predicts falls below the rounding noise of
   Pi (each segment's energy comes from a strain L/L0 - 1 with a relative error of about
   1e-16/strain, and Pi sums them over every crossing): there the step is judged by |F| instead
   (the forces are exact to far smaller errors), a full step first, halved until |F| decreases. */
static PetscErrorCode EnergyLineSearch(SNESLineSearch ls, void *ctx)
{
  StaticSolver ss = (StaticSolver) ctx;
  SNES         snes;
  Vec          X, F, Y, W, G;
  PetscReal    xnorm, fnorm, ynorm, gnorm = 0, pi0, pi1, slope, lambda, minlambda;
  PetscInt     max_it;
  PetscBool    ok = PETSC_FALSE, noise;

  PetscFunctionBeginUser;
  /* PETSc's line-search options: -snes_linesearch_max_it tries (40 here), the first step -snes_linesearch_damping
     (1), none below -snes_linesearch_minlambda (0 here); read here, so that PETSc's own line searches keep theirs */
  {
    const char *prefix;
    max_it = 40, minlambda = 0;
    PetscCall(PetscObjectGetOptionsPrefix((PetscObject) ls, &prefix));
    PetscCall(PetscOptionsGetInt(NULL, prefix, "-snes_linesearch_max_it", &max_it, NULL));
    PetscCall(PetscOptionsGetReal(NULL, prefix, "-snes_linesearch_minlambda", &minlambda, NULL));
  }
  PetscCall(SNESLineSearchGetDamping(ls, &lambda));
  PetscCall(SNESLineSearchGetSNES(ls, &snes));
  PetscCall(SNESLineSearchGetVecs(ls, &X, &F, &Y, &W, &G));
  PetscCall(SNESLineSearchGetNorms(ls, &xnorm, &fnorm, &ynorm));
  { /* the held crossings stay exactly where the load step put them (Xbc): the linear solve leaves rounding noise
       in their rows (their residual is 0), which moved them by 1e-50 m, so that a restart within the solve, whose
       Xbc is the checkpoint's iterate, did not take the same steps */
    PetscScalar *y;
    PetscCall(VecGetArray(Y, &y));
    for (PetscInt k = 0; k < ss->fab->grid.nloc; k++)
      if (!(ss->fab->grid.inv_m[k] > 0)) y[3 * k] = y[3 * k + 1] = y[3 * k + 2] = 0;
    PetscCall(VecRestoreArray(Y, &y));
  }
  PetscCall(FormObjective(snes, X, &pi0, ss));
  PetscCall(VecDot(F, Y, &slope));
  slope = -slope; /* d Pi(X - lambda Y)/d lambda at 0 = -grad Pi . Y */
  noise = !(slope < 0) || -slope < ENERGY_NOISE * PetscAbsReal(pi0);
  for (PetscInt k = 0; k < max_it && !ok && lambda >= minlambda; k++) {
    PetscCall(VecWAXPY(W, -lambda, Y, X));
    if (noise) {
      PetscCall(SNESComputeFunction(snes, W, G));
      PetscCall(VecNorm(G, NORM_2, &gnorm));
      ok = gnorm < fnorm ? PETSC_TRUE : PETSC_FALSE;
      if (!ok) lambda *= 0.5;
      continue;
    }
    PetscCall(FormObjective(snes, W, &pi1, ss));
    if (pi1 <= pi0 + 1e-4 * lambda * slope)
      ok = PETSC_TRUE;
    else {
      const PetscReal fit = -slope * lambda * lambda / (2.0 * (pi1 - pi0 - slope * lambda));
      lambda              = (isfinite(fit) && fit > 0.1 * lambda && fit < 0.5 * lambda) ? fit : 0.5 * lambda;
    }
  }
  if (!ok) { /* the norms of this step, not of the last one that succeeded: newtonls's step-length test reads them
                after a failed search (a stale small step ended the solve, unbalanced, and a restart, whose norms
                start fresh, went on) */
    PetscCall(VecNorm(X, NORM_2, &xnorm));
    PetscCall(VecNorm(Y, NORM_2, &ynorm));
    PetscCall(SNESLineSearchSetNorms(ls, xnorm, fnorm, ynorm));
    PetscCall(SNESLineSearchSetReason(ls, SNES_LINESEARCH_FAILED_REDUCT));
    PetscFunctionReturn(0);
  }
  if (!noise) PetscCall(SNESComputeFunction(snes, W, G));
  PetscCall(VecCopy(W, X));
  PetscCall(VecCopy(G, F));
  PetscCall(SNESLineSearchSetLambda(ls, lambda));
  PetscCall(SNESLineSearchComputeNorms(ls));
  PetscFunctionReturn(0);
}

/* the shift for the Newton step after one whose line search took lambda of it and whose linear solve ended
   kreason */
static PetscReal NextShift(PetscReal shift, PetscReal lambda, KSPConvergedReason kreason)
{
  if (kreason < 0) return PetscMax(10.0 * shift, 1e-6); /* an indefinite tangent (CG met negative curvature): stiffer */
  if (lambda >= 1.0) return shift / 10.0 < SHIFT_FLOOR ? 0.0 : shift / 10.0;
  if (lambda < 0.25) return PetscMax(4.0 * shift, SHIFT_FLOOR);
  return shift;
}

/* how the last Newton step went: its line search's fraction and its linear solve's end */
static PetscErrorCode LastStep(SNES snes, PetscReal *lambda, KSPConvergedReason *kreason)
{
  SNESLineSearch ls;
  KSP            ksp;

  PetscFunctionBeginUser;
  PetscCall(SNESGetLineSearch(snes, &ls));
  PetscCall(SNESLineSearchGetLambda(ls, lambda));
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPGetConvergedReason(ksp, kreason));
  PetscFunctionReturn(0);
}

/* before each Newton step: adapt the shift to how the last step went */
static PetscErrorCode AdaptShift(SNES snes, PetscInt step)
{
  StaticSolver       ss;
  PetscReal          lambda;
  KSPConvergedReason kreason;

  PetscFunctionBeginUser;
  PetscCall(SNESGetApplicationContext(snes, &ss));
  if (step == 0) PetscFunctionReturn(0); /* a restart within a solve: the checkpoint's shift is NextShift's */
  PetscCall(LastStep(snes, &lambda, &kreason));
  ss->h->shift = NextShift(ss->h->shift, lambda, kreason);
  PetscCall(PetscInfo(snes, "Newton step %" PetscInt_FMT ": the last step's line search took %g of it, its linear solve %s; the shift now %g\n",
                      step, (double) lambda, KSPConvergedReasons[kreason], (double) ss->h->shift));
  PetscFunctionReturn(0);
}

/* the largest force on a free crossing, from the residual R at the current iterate */
static PetscErrorCode FreeForceMax(StaticSolver ss, Vec R, PetscReal *fmax)
{
  Fabric             fab = ss->fab;
  const PetscScalar *r;
  PetscReal          f2 = 0;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(R, &r));
  for (PetscInt k = 0; k < fab->grid.nloc; k++)
    if (fab->grid.inv_m[k] > 0)
      f2 = PetscMax(f2, r[3 * k] * r[3 * k] + r[3 * k + 1] * r[3 * k + 1] + r[3 * k + 2] * r[3 * k + 2]);
  PetscCall(VecRestoreArrayRead(R, &r));
  PetscCall(GlobalMax(fab->comm, &f2, 1));
  *fmax = PetscSqrtReal(f2);
  PetscFunctionReturn(0);
}

/* the balance test of the explicit path at the current iterate; SNES's own tests for divergence */
static PetscErrorCode Converged(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm,
                                SNESConvergedReason *reason, void *ctx)
{
  StaticSolver ss  = (StaticSolver) ctx;
  Fabric       fab = ss->fab;
  Vec          R;
  PetscReal    fmax = 0;

  PetscFunctionBeginUser;
  PetscCall(SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, NULL));
  if (it == 0 && ss->rnorm0 > 0) { /* a restart within the attempt: its relative tests' reference is the attempt's
                                      first residual */
    snes->rnorm0 = ss->rnorm0;
    snes->ttol   = ss->rnorm0 * snes->rtol;
  }
  if (*reason < 0) PetscFunctionReturn(0); /* diverged: NaN, too many evaluations or iterations */
  PetscCall(SNESGetFunction(snes, &R, NULL, NULL));
  PetscCall(FreeForceMax(ss, R, &fmax));
  *reason = fmax <= fab->s.num.balance_tol * PetscMax(ss->tmax, fab->step.force_floor) ? SNES_CONVERGED_FNORM_ABS
                                                                                       : SNES_CONVERGED_ITERATING;
  if (*reason == SNES_CONVERGED_ITERATING && it > 0 && ss->watch) { /* the solve goes on: the driver's look */
    StaticProgress     p;
    PetscReal          lambda;
    KSPConvergedReason kreason;
    PetscInt           lits, lag[2], max_it;
    /* at a Newton step whose next one forms its tangent and preconditioner afresh (-snes_lag_jacobian,
       -snes_lag_preconditioner: 2 here): a restart, whose first step forms both, then takes the same steps (a
       lagged one is not in the checkpoint); not after the attempt's last step (SNES tests it, then stops) */
    PetscCall(SNESGetLagJacobian(snes, &lag[0]));
    PetscCall(SNESGetLagPreconditioner(snes, &lag[1]));
    PetscCall(SNESGetTolerances(snes, NULL, NULL, NULL, &max_it, NULL));
    if ((lag[0] > 1 && it % lag[0]) || (lag[1] > 1 && it % lag[1]) || it >= max_it) PetscFunctionReturn(0);
    PetscCall(LastStep(snes, &lambda, &kreason));
    PetscCall(SNESGetLinearSolveIterations(snes, &lits));
    p = (StaticProgress){ss->base + it, ss->done_its + it, ss->done_lits + lits, NextShift(ss->h->shift, lambda, kreason),
                         snes->rnorm0};
    PetscCall(ss->watch->look(ss->watch->ctx, &p, &ss->watch_stop));
    if (ss->watch_stop) *reason = SNES_DIVERGED_MAX_IT; /* stopped here (PETSc 3.18 has no DIVERGED_USER) */
  }
  PetscFunctionReturn(0);
}

/* The multigrid smoother: alternating block-line relaxation. A yarn is stiff along itself (EA/L)
   and soft across (its tension T/L, about the strain times EA/L): the in-plane displacement along
   x is strongly coupled along the warp yarns (x-lines) only, the one along y along the weft
   yarns (y-lines) only, an anisotropy of 1/strain that point smoothers (SOR, Jacobi) cannot
   smooth, so that multigrid slows as the net grows and its strain falls. A sweep solves exactly
   along every line of one direction (a block-tridiagonal solve, 3x3 blocks: a crossing's
   coupling to its neighbours along the line) on the residual the sweep before left; the down
   smoother sweeps the x-lines then the y-lines, the up smoother the y-lines then the x-lines (a
   symmetric V-cycle for CG). Only the couplings across lines stay in the residual.
   A line that lies on one rank is solved in place: an x-line along its points, the y-lines side
   by side (one point of every y-line after the other, in memory order). The lines of a direction
   that crosses ranks (x-lines when the process grid has more than one column, y-lines when it has
   more than one row) are dealt out whole among the ranks that share them: each rank receives its
   share of those lines, every point's blocks at set-up and every residual at a sweep (a PetscSF
   from the points' owners), solves them and sends the solution back. */
static PetscLogEvent EV_LineSetUp, EV_LineSolve, EV_Galerkin;

typedef struct {
  PetscInt     xs, ys, xm, ym;           /* the level's owned patch */
  PetscBool    cut[2];                   /* the lines of direction dir (0: x, 1: y) cross ranks */
  PetscReal   *fac[2];                   /* a direction not cut: per owned point S^-1, S^-1 U (FactorLines) */
  PetscSF      sf[2];                    /* a cut direction: the points of the lines dealt to this rank
                                            (leaves, line after line, along each) from their owners (roots) */
  PetscInt     nlines[2], len[2];        /* the lines dealt to this rank, their length */
  PetscReal   *lfac[2], *lr[2], *lx[2];  /* their factors (as fac), right-hand side and solution */
  MPI_Datatype t3, tfac;                 /* a point's 3 unknowns, its LINE_FAC reals */
  Vec          t, s;                     /* work: residual, one line sweep's correction */
  PetscBool    pivot_fixed;              /* a non-positive 3x3 pivot was replaced by its diagonal (indefinite level) */
  PetscReal    lump;                     /* this times the couplings outside the star added to the lines' diagonal */
  PetscInt     refs;                     /* the level's down and up smoothers share it */
  Mat             A;                     /* the operator factored, at tangent number factored */
  PetscInt        factored;
  const PetscInt *tangents;              /* the tangents assembled so far (FormJacobian) */
  PetscErrorCode (*refresh)(void *);     /* brings a stencil level operator up to the tangent (RefreshLevels) */
  void           *refresh_ctx;
} LineSmoother;

typedef struct {     /* one smoother (PCSHELL context): the level's factors, its sweeps */
  LineSmoother *ls;
  int           order[3]; /* the line directions of one application, -1 ends */
} LineShell;

/* inverse of a 3x3 block; a pivot that is not positive definite enough is replaced by the absolute
   values of its diagonal (an indefinite tangent: the smoother stays a symmetric positive one) */
static PetscBool Invert3(const PetscReal a[9], PetscReal inv[9])
{
  const PetscReal c0 = a[4] * a[8] - a[5] * a[7], c1 = a[5] * a[6] - a[3] * a[8], c2 = a[3] * a[7] - a[4] * a[6];
  const PetscReal det = a[0] * c0 + a[1] * c1 + a[2] * c2, scale = PetscAbsReal(a[0]) + PetscAbsReal(a[4]) + PetscAbsReal(a[8]);

  if (!(det > 1e-12 * scale * scale * scale) || !(a[0] > 0 && a[4] > 0 && a[8] > 0)) {
    for (int e = 0; e < 9; e++) inv[e] = 0;
    for (int d = 0; d < 3; d++) inv[4 * d] = PetscAbsReal(a[4 * d]) > 0 ? 1.0 / PetscAbsReal(a[4 * d]) : 0.0;
    return PETSC_TRUE;
  }
  inv[0] = c0 / det, inv[3] = c1 / det, inv[6] = c2 / det;
  inv[1] = (a[2] * a[7] - a[1] * a[8]) / det, inv[4] = (a[0] * a[8] - a[2] * a[6]) / det, inv[7] = (a[1] * a[6] - a[0] * a[7]) / det;
  inv[2] = (a[1] * a[5] - a[2] * a[4]) / det, inv[5] = (a[2] * a[3] - a[0] * a[5]) / det, inv[8] = (a[0] * a[4] - a[1] * a[3]) / det;
  return PETSC_FALSE;
}

static inline void Mul3(const PetscReal a[9], const PetscReal b[9], PetscReal c[9])
{
  for (int r = 0; r < 3; r++)
    for (int q = 0; q < 3; q++) c[3 * r + q] = a[3 * r] * b[q] + a[3 * r + 1] * b[3 + q] + a[3 * r + 2] * b[6 + q];
}

/* Lines of len points, point q of a line at k, its predecessor at k - qs. A line's operator is
   block-tridiagonal and symmetric: D_q on the diagonal, U_q coupling q to q + 1 and U_{q-1}^T
   coupling q to q - 1, so a point keeps LINE_FAC = 18 reals: on input D_q, U_q; factored
   (in place) S_q^-1, W_q = S_q^-1 U_q, where S_0 = D_0, S_q = D_q - U_{q-1}^T W_{q-1}.
   Solve T x = r: forward b_q = r_q - W_{q-1}^T b_{q-1} (= r_q - U_{q-1}^T S_{q-1}^-1 b_{q-1}, S
   symmetric), held in x; backward x_q = S_q^-1 b_q - W_q x_{q+1}. */
#define LINE_FAC 18
static inline void Mul3T(const PetscReal a[9], const PetscReal b[9], PetscReal c[9]) /* c = a^T b */
{
  for (int r = 0; r < 3; r++)
    for (int q = 0; q < 3; q++) c[3 * r + q] = a[r] * b[q] + a[3 + r] * b[3 + q] + a[6 + r] * b[6 + q];
}

/* factors point k (q-th of its line) in place; up: U_{q-1} on entry, U_q on return */
static inline PetscBool FactorPoint(PetscReal *fac, PetscReal up[9], PetscInt k, PetscInt q, PetscInt qs)
{
  PetscReal *f = fac + LINE_FAC * k, S[9], U[9];
  PetscBool  fixed;

  for (int e = 0; e < 9; e++) S[e] = f[e], U[e] = f[9 + e];
  if (q > 0) { /* S -= U_{q-1}^T W_{q-1} */
    PetscReal UW[9];
    Mul3T(up, fac + LINE_FAC * (k - qs) + 9, UW);
    for (int e = 0; e < 9; e++) S[e] -= UW[e];
    for (int r = 0; r < 3; r++) /* symmetric to the last bit (U^T W is, up to rounding) */
      for (int c = r + 1; c < 3; c++) S[3 * r + c] = S[3 * c + r] = 0.5 * (S[3 * r + c] + S[3 * c + r]);
  }
  fixed = Invert3(S, f);
  Mul3(f, U, f + 9);
  for (int e = 0; e < 9; e++) up[e] = U[e];
  return fixed;
}

static inline void ForwardPoint(const PetscReal *fac, const PetscScalar *r, PetscScalar *x, PetscInt k, PetscInt q,
                                PetscInt qs)
{
  for (int c = 0; c < 3; c++) x[3 * k + c] = r[3 * k + c];
  if (q > 0) {
    const PetscReal   *W = fac + LINE_FAC * (k - qs) + 9;
    const PetscScalar *b = x + 3 * (k - qs);
    for (int c = 0; c < 3; c++) x[3 * k + c] -= W[c] * b[0] + W[3 + c] * b[1] + W[6 + c] * b[2];
  }
}

static inline void BackwardPoint(const PetscReal *fac, PetscScalar *x, PetscInt k, PetscInt q, PetscInt len, PetscInt qs)
{
  const PetscReal  *Si = fac + LINE_FAC * k, *W = Si + 9;
  const PetscScalar b[3] = {x[3 * k], x[3 * k + 1], x[3 * k + 2]};

  for (int c = 0; c < 3; c++) x[3 * k + c] = Si[3 * c] * b[0] + Si[3 * c + 1] * b[1] + Si[3 * c + 2] * b[2];
  if (q < len - 1) {
    const PetscScalar *y = x + 3 * (k + qs);
    for (int c = 0; c < 3; c++) x[3 * k + c] -= W[3 * c] * y[0] + W[3 * c + 1] * y[1] + W[3 * c + 2] * y[2];
  }
}

/* nlines lines, point q of line l at k = l * lstride + q * qs: one of the strides is 1, and the
   loop over it is the inner one (a line after the other, or all lines a point at a time); up:
   9 reals a line, work */
static PetscBool FactorLines(PetscReal *fac, PetscInt nlines, PetscInt len, PetscInt lstride, PetscInt qs,
                             PetscReal *up)
{
  PetscBool fixed = PETSC_FALSE;

  if (qs == 1) {
    for (PetscInt l = 0; l < nlines; l++)
      for (PetscInt q = 0; q < len; q++) fixed |= FactorPoint(fac, up, l * lstride + q, q, 1);
  } else {
    for (PetscInt q = 0; q < len; q++)
      for (PetscInt l = 0; l < nlines; l++) fixed |= FactorPoint(fac, up + 9 * l, l * lstride + q * qs, q, qs);
  }
  return fixed;
}

static void SolveLines(const PetscReal *fac, PetscInt nlines, PetscInt len, PetscInt lstride, PetscInt qs,
                       const PetscScalar *r, PetscScalar *x)
{
  if (qs == 1) {
    for (PetscInt l = 0; l < nlines; l++) {
      for (PetscInt q = 0; q < len; q++) ForwardPoint(fac, r, x, l * lstride + q, q, 1);
      for (PetscInt q = len - 1; q >= 0; q--) BackwardPoint(fac, x, l * lstride + q, q, len, 1);
    }
  } else {
    for (PetscInt q = 0; q < len; q++)
      for (PetscInt l = 0; l < nlines; l++) ForwardPoint(fac, r, x, l * lstride + q * qs, q, qs);
    for (PetscInt q = len - 1; q >= 0; q--)
      for (PetscInt l = 0; l < nlines; l++) BackwardPoint(fac, x, l * lstride + q * qs, q, len, qs);
  }
}

/* the global index of the natural point (i, j) of a layout: its rank's first index plus its place
   in the rank's patch (ox, oy: each column's and row's rank column and row; x0, y0: their first
   points; start: each rank's first point) */
typedef struct {
  PetscInt M, N, m, *ox, *oy, *x0, *y0, *start;
  const PetscInt *lx;
} Numbering;

static PetscErrorCode NumberingCreate(DM da, Numbering *nb)
{
  PetscInt        n;
  const PetscInt *ly;

  PetscFunctionBeginUser;
  PetscCall(DMDAGetInfo(da, NULL, &nb->M, &nb->N, NULL, &nb->m, &n, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
  PetscCall(DMDAGetOwnershipRanges(da, &nb->lx, &ly, NULL));
  PetscCall(PetscMalloc5(nb->M, &nb->ox, nb->N, &nb->oy, nb->m, &nb->x0, n, &nb->y0, nb->m * n + 1, &nb->start));
  for (PetscInt a = 0, s = 0; a < nb->m; s += nb->lx[a++]) {
    nb->x0[a] = s;
    for (PetscInt i = s; i < s + nb->lx[a]; i++) nb->ox[i] = a;
  }
  for (PetscInt a = 0, s = 0; a < n; s += ly[a++]) {
    nb->y0[a] = s;
    for (PetscInt j = s; j < s + ly[a]; j++) nb->oy[j] = a;
  }
  nb->start[0] = 0;
  for (PetscInt r = 0; r < nb->m * n; r++) nb->start[r + 1] = nb->start[r] + nb->lx[r % nb->m] * ly[r / nb->m];
  PetscFunctionReturn(0);
}

static inline PetscInt NumberingIndex(const Numbering *nb, PetscInt i, PetscInt j)
{
  const PetscInt a = nb->ox[i], b = nb->oy[j];
  return nb->start[b * nb->m + a] + (j - nb->y0[b]) * nb->lx[a] + (i - nb->x0[a]);
}

static PetscErrorCode NumberingDestroy(Numbering *nb)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree5(nb->ox, nb->oy, nb->x0, nb->y0, nb->start));
  PetscFunctionReturn(0);
}

/* the lines of a cut direction dealt to this rank: those of its patch's rows (x-lines) or columns
   (y-lines) in equal shares among the ranks of its process row (column), each whole; the PetscSF
   from their points' owners, point q of line l the leaf l * len + q */
static PetscErrorCode DealLines(LineSmoother *ls, MPI_Comm comm, int dir, PetscInt M, PetscInt N, PetscInt m,
                                PetscInt n,
                                const PetscInt lxr[], const PetscInt ox[], const PetscInt oy[],
                                const PetscInt x0[], const PetscInt y0[], PetscMPIInt rank)
{
  const PetscInt pi = rank % m, pj = rank / m;
  PetscInt       first, nl, len;
  PetscSFNode   *remote;

  PetscFunctionBeginUser;
  if (dir == 0) first = ls->ys + (pi * ls->ym) / m, nl = ls->ys + ((pi + 1) * ls->ym) / m - first, len = M;
  else first = ls->xs + (pj * ls->xm) / n, nl = ls->xs + ((pj + 1) * ls->xm) / n - first, len = N;
  PetscCall(PetscMalloc1(nl * len, &remote));
  for (PetscInt l = 0; l < nl; l++)
    for (PetscInt q = 0; q < len; q++) {
      PetscSFNode *e = remote + l * len + q;
      if (dir == 0) { /* point (q, first + l) */
        const PetscInt qi = ox[q];
        e->rank  = pj * m + qi;
        e->index = (first + l - y0[pj]) * lxr[qi] + (q - x0[qi]);
      } else { /* point (first + l, q) */
        const PetscInt qj = oy[q];
        e->rank  = qj * m + pi;
        e->index = (q - y0[qj]) * lxr[pi] + (first + l - x0[pi]);
      }
    }
  ls->nlines[dir] = nl, ls->len[dir] = len;
  PetscCall(PetscSFCreate(comm, &ls->sf[dir]));
  PetscCall(
      PetscSFSetGraph(ls->sf[dir], ls->xm * ls->ym, nl * len, NULL, PETSC_OWN_POINTER, remote, PETSC_OWN_POINTER));
  PetscCall(PetscSFSetUp(ls->sf[dir]));
  PetscCall(PetscMalloc3(LINE_FAC * nl * len, &ls->lfac[dir], 3 * nl * len, &ls->lr[dir], 3 * nl * len, &ls->lx[dir]));
  PetscFunctionReturn(0);
}

/* a line smoother's blocks from an operator stored by stencil: per owned point, each row c of
   the centre block into both directions' D, of the +x block into the x-lines' U, of the +y block
   into the y-lines' U; the magnitudes of the row's other blocks but the -x and -y ones (the
   couplings outside the star) times lump added to its diagonal */
static void StencilLineBlocks(const StencilData *d, PetscReal lump, PetscReal *blk[2])
{
  for (PetscInt j = d->ys; j < d->ys + d->ym; j++)
    for (PetscInt i = d->xs; i < d->xs + d->xm; i++) {
      const PetscInt k = (j - d->ys) * d->xm + (i - d->xs), g = (j - d->gys) * d->gxm + (i - d->gxs);
      PetscReal      D[9], Ux[9], Uy[9], l[3] = {0, 0, 0};
      StencilBlock(d, g, 0, 0, D);
      StencilBlock(d, g, 1, 0, Ux);
      StencilBlock(d, g, 0, 1, Uy);
      for (int dj = -2; dj <= 2 && lump != 0; dj++)
        for (int di = -2; di <= 2; di++) {
          PetscReal K[9];
          if (PetscAbsInt(di) + PetscAbsInt(dj) <= 1 || i + di < 0 || i + di >= d->M || j + dj < 0 || j + dj >= d->N ||
              !StencilBlock(d, g, di, dj, K))
            continue;
          for (int c = 0; c < 3; c++)
            l[c] += PetscAbsReal(K[3 * c]) + PetscAbsReal(K[3 * c + 1]) + PetscAbsReal(K[3 * c + 2]);
        }
      for (int c = 0; c < 3; c++) {
        for (int cc = 0; cc < 3; cc++) {
          blk[0][LINE_FAC * k + 3 * c + cc] = blk[1][LINE_FAC * k + 3 * c + cc] = D[3 * c + cc];
          blk[0][LINE_FAC * k + 9 + 3 * c + cc] = Ux[3 * c + cc];
          blk[1][LINE_FAC * k + 9 + 3 * c + cc] = Uy[3 * c + cc];
        }
        for (int dir = 0; dir < 2; dir++) blk[dir][LINE_FAC * k + 4 * c] += lump * l[c];
      }
    }
}

/* the blocks of the level operator along the lines, factored */
static PetscErrorCode LineSmootherSetUp(PC pc)
{
  LineSmoother   *ls;
  DM              dm;
  Mat             A;
  MPI_Comm        comm = PetscObjectComm((PetscObject) pc);
  PetscMPIInt     rank;
  PetscInt        rstart, rend, npts, zs, zm, M, N, m, n, *ox, *oy, *x0, *y0;
  const PetscInt *lxr;
  Numbering       num;
  PetscReal      *blk[2] = {NULL, NULL}; /* per owned point, D and U of each direction's lines (FactorLines) */
  PetscReal      *up;                    /* FactorLines' work */
  LineShell      *sh;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &sh));
  ls = sh->ls;
  PetscCall(PCGetOperators(pc, NULL, &A));
  if (ls->t && ls->A == A && ls->factored == *ls->tangents) PetscFunctionReturn(0); /* the level's other smoother did */
  PetscCall(PetscLogEventBegin(EV_LineSetUp, pc, 0, 0, 0));
  PetscCall(PCGetDM(pc, &dm));
  PetscCheck(dm, comm, PETSC_ERR_SUP, "the line smoother needs the level's DMDA");
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(DMDAGetCorners(dm, &ls->xs, &ls->ys, &zs, &ls->xm, &ls->ym, &zm));
  PetscCall(DMDAGetInfo(dm, NULL, &M, &N, NULL, &m, &n, NULL, NULL, NULL, NULL, NULL, NULL, NULL));

  PetscCall(MatGetOwnershipRange(A, &rstart, &rend));
  npts = ls->xm * ls->ym;
  PetscCheck(rend - rstart == 3 * npts, PETSC_COMM_SELF, PETSC_ERR_SUP, "the line smoother needs 3 unknowns a point");
  /* the process column of each grid column, the process row of each grid row, their first points */
  PetscCall(NumberingCreate(dm, &num));
  ox = num.ox, oy = num.oy, x0 = num.x0, y0 = num.y0, lxr = num.lx;
  if (!ls->t) {
    PetscCall(MatCreateVecs(A, &ls->t, &ls->s));
    PetscCallMPI(MPI_Type_contiguous(3, MPIU_SCALAR, &ls->t3));
    PetscCallMPI(MPI_Type_commit(&ls->t3));
    PetscCallMPI(MPI_Type_contiguous(LINE_FAC, MPIU_REAL, &ls->tfac));
    PetscCallMPI(MPI_Type_commit(&ls->tfac));
    ls->cut[0] = m > 1 ? PETSC_TRUE : PETSC_FALSE;
    ls->cut[1] = n > 1 ? PETSC_TRUE : PETSC_FALSE;
    for (int dir = 0; dir < 2; dir++) {
      if (ls->cut[dir]) PetscCall(DealLines(ls, comm, dir, M, N, m, n, lxr, ox, oy, x0, y0, rank));
      else PetscCall(PetscMalloc1(LINE_FAC * npts, &ls->fac[dir]));
    }
  }
  /* each direction's blocks, by the global block indices of each point and its neighbours (on
     any rank): into its factors (a direction on this rank) or into the blocks its lines' owners
     receive; the couplings outside the star (shear corners, bending's points two apart) lumped */
  for (int dir = 0; dir < 2; dir++) {
    if (ls->cut[dir]) PetscCall(PetscMalloc1(LINE_FAC * npts, &blk[dir]));
    else blk[dir] = ls->fac[dir];
    PetscCall(PetscArrayzero(blk[dir], LINE_FAC * npts));
  }
  if (StencilMatIs(A)) { /* the same from the blocks by stencil */
    StencilData *d;
    PetscCall(ls->refresh(ls->refresh_ctx));
    PetscCall(StencilMatGetData(A, &d));
    StencilLineBlocks(d, ls->lump, blk);
  } else
    for (PetscInt k = 0; k < npts; k++) {
      const PetscInt i = ls->xs + k % ls->xm, j = ls->ys + k / ls->xm;
      const PetscInt ni[5] = {i, i - 1, i + 1, i, i}, nj[5] = {j, j, j, j - 1, j + 1};
      PetscInt       nb[5];
      for (int w = 0; w < 5; w++) {
        const PetscInt a = ni[w], b = nj[w];
        nb[w] = (a < 0 || a >= M || b < 0 || b >= N) ? -1 : NumberingIndex(&num, a, b);
      }
      for (int c = 0; c < 3; c++) {
        PetscInt           ncols;
        const PetscInt    *cols;
        const PetscScalar *vals;
        PetscReal          lump = 0;
        PetscCall(MatGetRow(A, rstart + 3 * k + c, &ncols, &cols, &vals));
        for (PetscInt q = 0; q < ncols; q++) {
          const PetscInt kk = cols[q] / 3, cc = cols[q] % 3;
          if (kk == nb[0]) blk[0][LINE_FAC * k + 3 * c + cc] = blk[1][LINE_FAC * k + 3 * c + cc] = vals[q];
          else if (kk == nb[2]) blk[0][LINE_FAC * k + 9 + 3 * c + cc] = vals[q];
          else if (kk == nb[4]) blk[1][LINE_FAC * k + 9 + 3 * c + cc] = vals[q];
          else if (kk != nb[1] && kk != nb[3]) lump += PetscAbsScalar(vals[q]);
        }
        PetscCall(MatRestoreRow(A, rstart + 3 * k + c, &ncols, &cols, &vals));
        for (int dir = 0; dir < 2; dir++) blk[dir][LINE_FAC * k + 4 * c] += ls->lump * lump;
      }
    }
  ls->pivot_fixed = PETSC_FALSE;
  PetscCall(PetscMalloc1(9 * PetscMax(1, ls->xm), &up)); /* y-lines side by side: 9 reals each */
  for (int dir = 0; dir < 2; dir++) {
    if (!ls->cut[dir]) {
      if (dir == 0) ls->pivot_fixed |= FactorLines(ls->fac[0], ls->ym, ls->xm, ls->xm, 1, up);
      else ls->pivot_fixed |= FactorLines(ls->fac[1], ls->xm, ls->ym, 1, ls->xm, up);
    } else { /* the dealt lines' blocks, factored in place (by a copy of the PetscSF, whose
                buffers for the blocks go with it instead of staying in the sweeps' one) */
      PetscReal *lb = ls->lfac[dir];
      PetscSF    sf;
      PetscCall(PetscSFDuplicate(ls->sf[dir], PETSCSF_DUPLICATE_GRAPH, &sf));
      PetscCall(PetscSFBcastBegin(sf, ls->tfac, blk[dir], lb, MPI_REPLACE));
      PetscCall(PetscSFBcastEnd(sf, ls->tfac, blk[dir], lb, MPI_REPLACE));
      PetscCall(PetscSFDestroy(&sf));
      PetscCall(PetscFree(blk[dir]));
      ls->pivot_fixed |= FactorLines(lb, ls->nlines[dir], ls->len[dir], ls->len[dir], 1, up);
    }
  }
  PetscCall(PetscFree(up));
  PetscCall(NumberingDestroy(&num));
  ls->A = A, ls->factored = *ls->tangents;
  PetscCall(PetscLogEventEnd(EV_LineSetUp, pc, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* x = T^-1 r for the block-tridiagonal T of every line of direction dir (0: x-lines, 1: y-lines) */
static PetscErrorCode LineSolve(LineSmoother *ls, int dir, const PetscScalar *r, PetscScalar *x)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(EV_LineSolve, 0, 0, 0, 0));
  if (!ls->cut[dir]) {
    if (dir == 0) SolveLines(ls->fac[0], ls->ym, ls->xm, ls->xm, 1, r, x);
    else SolveLines(ls->fac[1], ls->xm, ls->ym, 1, ls->xm, r, x);
  } else {
    const PetscInt nl = ls->nlines[dir], len = ls->len[dir];
    PetscCall(PetscSFBcastBegin(ls->sf[dir], ls->t3, r, ls->lr[dir], MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(ls->sf[dir], ls->t3, r, ls->lr[dir], MPI_REPLACE));
    SolveLines(ls->lfac[dir], nl, len, len, 1, ls->lr[dir], ls->lx[dir]);
    PetscCall(PetscSFReduceBegin(ls->sf[dir], ls->t3, ls->lx[dir], x, MPI_REPLACE));
    PetscCall(PetscSFReduceEnd(ls->sf[dir], ls->t3, ls->lx[dir], x, MPI_REPLACE));
  }
  PetscCall(PetscLogEventEnd(EV_LineSolve, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* One sweep over the lines of direction dir: x += T^-1 (b - A x), or x = T^-1 b from x = 0. */
static PetscErrorCode LineSweep(LineSmoother *ls, Mat A, int dir, Vec b, Vec x, PetscBool zero)
{
  const PetscScalar *rr;
  PetscScalar       *zz;

  PetscFunctionBeginUser;
  if (zero) {
    PetscCall(VecGetArrayRead(b, &rr));
    PetscCall(VecGetArrayWrite(x, &zz));
    PetscCall(LineSolve(ls, dir, rr, zz));
    PetscCall(VecRestoreArrayWrite(x, &zz));
    PetscCall(VecRestoreArrayRead(b, &rr));
    PetscFunctionReturn(0);
  }
  PetscCall(MatMult(A, x, ls->t));
  PetscCall(VecAYPX(ls->t, -1.0, b));
  PetscCall(VecGetArrayRead(ls->t, &rr));
  PetscCall(VecGetArrayWrite(ls->s, &zz));
  PetscCall(LineSolve(ls, dir, rr, zz));
  PetscCall(VecRestoreArrayWrite(ls->s, &zz));
  PetscCall(VecRestoreArrayRead(ls->t, &rr));
  PetscCall(VecAXPY(x, 1.0, ls->s));
  PetscFunctionReturn(0);
}

/* z = M^-1 r: one application (the sweeps of ls->order, each on the residual the last left) */
static PetscErrorCode LineSmootherApply(PC pc, Vec r, Vec z)
{
  LineShell *sh;
  Mat        A;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &sh));
  PetscCall(PCGetOperators(pc, &A, NULL));
  for (int q = 0; q < 3 && sh->order[q] >= 0; q++) PetscCall(LineSweep(sh->ls, A, sh->order[q], r, z, q == 0));
  PetscFunctionReturn(0);
}

/* the smoother's Richardson iterations without a separate residual: maxits applications to
   A x = b, the first from x = 0 if guesszero (no product with A) */
static PetscErrorCode LineSmootherRichardson(PC pc, Vec b, Vec x, Vec r, PetscReal rtol, PetscReal abstol,
                                             PetscReal dtol, PetscInt maxits, PetscBool guesszero, PetscInt *its,
                                             PCRichardsonConvergedReason *reason)
{
  LineShell *sh;
  Mat        A;

  PetscFunctionBeginUser;
  (void) r, (void) rtol, (void) abstol, (void) dtol;
  PetscCall(PCShellGetContext(pc, &sh));
  PetscCall(PCGetOperators(pc, &A, NULL));
  for (PetscInt it = 0; it < maxits; it++)
    for (int q = 0; q < 3 && sh->order[q] >= 0; q++)
      PetscCall(LineSweep(sh->ls, A, sh->order[q], b, x, guesszero && it == 0 && q == 0 ? PETSC_TRUE : PETSC_FALSE));
  *its    = maxits;
  *reason = PCRICHARDSON_CONVERGED_ITS;
  PetscFunctionReturn(0);
}

static PetscErrorCode LineSmootherDestroy(PC pc)
{
  LineShell    *sh;
  LineSmoother *ls;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &sh));
  ls = sh->ls;
  PetscCall(PetscFree(sh));
  if (--ls->refs > 0) PetscFunctionReturn(0);
  PetscCall(VecDestroy(&ls->t));
  PetscCall(VecDestroy(&ls->s));
  for (int dir = 0; dir < 2; dir++) {
    PetscCall(PetscFree(ls->fac[dir]));
    PetscCall(PetscSFDestroy(&ls->sf[dir]));
    PetscCall(PetscFree3(ls->lfac[dir], ls->lr[dir], ls->lx[dir]));
  }
  if (ls->t3 != MPI_DATATYPE_NULL) PetscCallMPI(MPI_Type_free(&ls->t3));
  if (ls->tfac != MPI_DATATYPE_NULL) PetscCallMPI(MPI_Type_free(&ls->tfac));
  PetscCall(PetscFree(ls));
  PetscFunctionReturn(0);
}

/* a smoother of a level: one application of the line smoother (Richardson, one iteration) with
   the level's factors ls (shared by its down and up smoothers) */
static PetscErrorCode SetLineSmoother(KSP ksp, const int order[3], LineSmoother *ls)
{
  PC         pc;
  LineShell *sh;

  PetscFunctionBeginUser;
  PetscCall(KSPSetType(ksp, KSPRICHARDSON));
  PetscCall(KSPSetTolerances(ksp, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, 1));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCSHELL));
  PetscCall(PetscNew(&sh));
  for (int q = 0; q < 3; q++) sh->order[q] = order[q];
  sh->ls = ls;
  ls->refs++;
  PetscCall(PCShellSetContext(pc, sh));
  PetscCall(PCShellSetName(pc, "alternating block-line relaxation"));
  PetscCall(PCShellSetSetUp(pc, LineSmootherSetUp));
  PetscCall(PCShellSetApply(pc, LineSmootherApply));
  PetscCall(PCShellSetApplyRichardson(pc, LineSmootherRichardson));
  PetscCall(PCShellSetDestroy(pc, LineSmootherDestroy));
  PetscFunctionReturn(0);
}

/* One coarsening of the grid's layout: the coarse point I lies on the fine point min(2I, M - 1)
   (M / 2 + 1 points: every other fine point and both ends, for any M; where M - 1 is odd the last
   coarse spacing is one fine spacing), owned by the rank that owns that fine point; ghosts of the
   fine layout's width in a box (the reach of the Galerkin operator's stencil). Returns the
   coarse layout and the fewest coarse points of a rank's column or row (no layout if 0). */
static PetscErrorCode CoarsenLayout(DM fine, DM *coarse, PetscInt *fewest)
{
  PetscInt        M, N, m, n, Mc, Nc, *lxc, *lyc, s = 0, w;
  const PetscInt *lx, *ly;

  PetscFunctionBeginUser;
  PetscCall(DMDAGetInfo(fine, NULL, &M, &N, NULL, &m, &n, NULL, NULL, &w, NULL, NULL, NULL, NULL));
  PetscCall(DMDAGetOwnershipRanges(fine, &lx, &ly, NULL));
  Mc = M / 2 + 1, Nc = N / 2 + 1;
  PetscCall(PetscMalloc2(m, &lxc, n, &lyc));
  *fewest = PETSC_MAX_INT;
  for (PetscInt a = 0; a < m; s += lx[a++]) { /* the even points of [s, s + lx[a]), and the end */
    lxc[a] = (s + lx[a] + 1) / 2 - (s + 1) / 2 + (a == m - 1 && M % 2 == 0 ? 1 : 0);
    *fewest = PetscMin(*fewest, lxc[a]);
  }
  s = 0;
  for (PetscInt a = 0; a < n; s += ly[a++]) {
    lyc[a] = (s + ly[a] + 1) / 2 - (s + 1) / 2 + (a == n - 1 && N % 2 == 0 ? 1 : 0);
    *fewest = PetscMin(*fewest, lyc[a]);
  }
  *coarse = NULL;
  if (*fewest >= 1) {
    PetscCall(DMDACreate2d(PetscObjectComm((PetscObject) fine), DM_BOUNDARY_NONE, DM_BOUNDARY_NONE,
                           DMDA_STENCIL_BOX, Mc, Nc, m, n, 3, w, lxc, lyc, coarse));
    PetscCall(DMSetUp(*coarse));
  }
  PetscCall(PetscFree2(lxc, lyc));
  PetscFunctionReturn(0);
}

/* bilinear interpolation from the coarse layout to the fine one, each of the 3 components alone */
static PetscErrorCode CreateInterpolation(DM coarse, DM fine, Mat *P)
{
  Numbering nc;
  PetscInt  M, N, xs, ys, xm, ym, xcm, ycm, rstart;

  PetscFunctionBeginUser;
  PetscCall(DMDAGetInfo(fine, NULL, &M, &N, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
  PetscCall(DMDAGetCorners(fine, &xs, &ys, NULL, &xm, &ym, NULL));
  PetscCall(DMDAGetCorners(coarse, NULL, NULL, NULL, &xcm, &ycm, NULL));
  PetscCall(NumberingCreate(coarse, &nc));
  { /* preallocated exactly: the coarse points over each fine point, on this rank (the owner of the
       fine point a coarse point lies on) or not */
    PetscInt *dnz, *onz;
    PetscCall(PetscMalloc2(3 * xm * ym, &dnz, 3 * xm * ym, &onz));
    for (PetscInt j = ys; j < ys + ym; j++)
      for (PetscInt i = xs; i < xs + xm; i++) {
        const PetscInt row = 3 * ((j - ys) * xm + (i - xs));
        PetscInt       ci[2], cj[2], d = 0, o = 0;
        PetscReal      wi[2], wj[2];
        const int      ni = StencilUnder(i, M, ci, wi), nj = StencilUnder(j, N, cj, wj);
        for (int b = 0; b < nj; b++)
          for (int a = 0; a < ni; a++) {
            const PetscInt fi = PetscMin(2 * ci[a], M - 1), fj = PetscMin(2 * cj[b], N - 1);
            if (fi >= xs && fi < xs + xm && fj >= ys && fj < ys + ym) d++;
            else o++;
          }
        for (PetscInt c = 0; c < 3; c++) dnz[row + c] = d, onz[row + c] = o;
      }
    PetscCall(MatCreateAIJ(PetscObjectComm((PetscObject) fine), 3 * xm * ym, 3 * xcm * ycm, PETSC_DETERMINE,
                           PETSC_DETERMINE, 0, dnz, 0, onz, P));
    PetscCall(PetscFree2(dnz, onz));
  }
  PetscCall(MatSetOption(*P, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  PetscCall(MatGetOwnershipRange(*P, &rstart, NULL));
  for (PetscInt j = ys; j < ys + ym; j++)
    for (PetscInt i = xs; i < xs + xm; i++) {
      const PetscInt row = 3 * ((j - ys) * xm + (i - xs));
      PetscInt       ci[2], cj[2];
      PetscReal      wi[2], wj[2];
      const int      ni = StencilUnder(i, M, ci, wi), nj = StencilUnder(j, N, cj, wj);
      for (int b = 0; b < nj; b++)
        for (int a = 0; a < ni; a++) {
          const PetscInt col = 3 * NumberingIndex(&nc, ci[a], cj[b]);
          for (PetscInt c = 0; c < 3; c++) {
            const PetscInt    r = rstart + row + c, q = col + c;
            const PetscScalar v = wi[a] * wj[b];
            PetscCall(MatSetValues(*P, 1, &r, 1, &q, &v, INSERT_VALUES));
          }
        }
    }
  PetscCall(MatAssemblyBegin(*P, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(*P, MAT_FINAL_ASSEMBLY));
  PetscCall(NumberingDestroy(&nc));
  PetscFunctionReturn(0);
}

/* The geometric multigrid hierarchy: the grid's layout coarsened (CoarsenLayout) while
   MultigridCoarsens (stencil.h) lets it and every rank keeps at least 2 points of each side, at most
   12 levels; dms[levels - 1] is the grid's own layout, Ps[l] interpolates from level l - 1 to l
   (both new references but the finest layout). */
static PetscErrorCode MultigridHierarchy(DM da, PetscInt *levels, DM dms[MG_MAX_LEVELS], Mat Ps[MG_MAX_LEVELS])
{
  DM       top[MG_MAX_LEVELS];
  Mat      Pt[MG_MAX_LEVELS];
  PetscInt L = 1;

  PetscFunctionBeginUser;
  top[0] = da, Pt[0] = NULL;
  while (L < MG_MAX_LEVELS) {
    PetscInt M, N, m, n, fewest = 0;
    DM       c;
    PetscCall(DMDAGetInfo(top[L - 1], NULL, &M, &N, NULL, &m, &n, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
    if (!MultigridCoarsens(M, N, m, n)) break;
    PetscCall(CoarsenLayout(top[L - 1], &c, &fewest));
    if (fewest < 2) {
      PetscCall(DMDestroy(&c));
      break;
    }
    top[L] = c;
    PetscCall(CreateInterpolation(c, top[L - 1], &Pt[L - 1]));
    L++;
  }
  /* top[0] is the finest; the levels count from the coarsest */
  for (PetscInt l = 0; l < L; l++) dms[l] = top[L - 1 - l];
  Ps[0] = NULL;
  for (PetscInt l = 1; l < L; l++) Ps[l] = Pt[L - 1 - l];
  *levels = L;
  PetscFunctionReturn(0);
}

/* The stencil operators of the levels below the finest brought up to the last tangent: each the
   Galerkin operator of the one above it, the coarsest also assembled for its direct solve. Called
   by the line smoother of a level whose operator changed (the finest one at every tangent); not
   while SNES reuses the preconditioner (-snes_lag_preconditioner), which then keeps the coarse
   levels as PCMG keeps its Galerkin products. A level's smoother and the coarse solve set
   themselves up again at their next solve, their operator having changed. */
static PetscErrorCode RefreshLevels(void *ctx)
{
  StaticSolver ss    = (StaticSolver) ctx;
  PetscBool    reuse = PETSC_FALSE;

  PetscFunctionBeginUser;
  if (ss->levels_at == ss->tangents) PetscFunctionReturn(0);
  if (!ss->opt.tao && ss->levels_at >= 0) {
    KSP ksp;
    PetscCall(SNESGetKSP(ss->snes, &ksp));
    PetscCall(KSPGetReusePreconditioner(ksp, &reuse));
  }
  if (reuse) PetscFunctionReturn(0);
  PetscCall(PetscLogEventBegin(EV_Galerkin, 0, 0, 0, 0));
  for (PetscInt l = ss->levels - 2; l >= 0; l--)
    PetscCall(StencilMatGalerkin(l == ss->levels - 2 ? ss->J : ss->Ac[l + 1], ss->Ac[l]));
  PetscCall(StencilMatToAIJ(ss->Ac[0], ss->Acoarse));
  ss->levels_at = ss->tangents;
  PetscCall(PetscLogEventEnd(EV_Galerkin, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* The preconditioner of the tangent's linear solves: geometric multigrid on the grid's hierarchy
   with the line smoother (its coarse operators PETSc's Galerkin products of an AIJ tangent, or
   ours of a stencil one), or on a grid too small to coarsen MUMPS's LU (GAMG with the rigid-body modes without
   it) */
static PetscErrorCode SetPreconditioner(StaticSolver ss, KSP ksp)
{
  Fabric       fab    = ss->fab;
  const PetscInt levels = ss->levels;
  PC           pc;
  MatNullSpace rigid;

  PetscFunctionBeginUser;
  PetscCall(KSPGetPC(ksp, &pc));
  if (levels > 1) {
    PetscCall(PCSetType(pc, PCMG));
    PetscCall(PCMGSetLevels(pc, levels, NULL));
    PetscCall(PCMGSetGalerkin(pc, ss->stencil ? PC_MG_GALERKIN_EXTERNAL : PC_MG_GALERKIN_BOTH));
    for (PetscInt l = 1; l < levels; l++) { /* each level's layout (for its line smoother); its stencil operator */
      KSP k;
      PetscCall(PCMGSetInterpolation(pc, l, ss->Ps[l]));
      PetscCall(PCMGGetSmootherDown(pc, l, &k));
      PetscCall(KSPSetDM(k, ss->dms[l]));
      PetscCall(KSPSetDMActive(k, PETSC_FALSE));
      if (ss->stencil && l < levels - 1) PetscCall(KSPSetOperators(k, ss->Ac[l], ss->Ac[l]));
      PetscCall(PCMGGetSmootherUp(pc, l, &k));
      PetscCall(KSPSetDM(k, ss->dms[l]));
      PetscCall(KSPSetDMActive(k, PETSC_FALSE));
      if (ss->stencil && l < levels - 1) PetscCall(KSPSetOperators(k, ss->Ac[l], ss->Ac[l]));
    }
    if (ss->stencil) {
      KSP k;
      PetscCall(PCMGGetCoarseSolve(pc, &k));
      PetscCall(KSPSetOperators(k, ss->Acoarse, ss->Acoarse));
    }
    for (PetscInt l = 1; l < levels && ss->opt.line_smoother; l++) { /* down x then y lines, up y then x */
      const int     down[3] = {0, 1, -1}, up[3] = {1, 0, -1};
      KSP           smoother;
      LineSmoother *lines; /* the level's factors, shared */
      PetscCall(PetscNew(&lines));
      lines->t3 = lines->tfac = MPI_DATATYPE_NULL;
      /* the fine level's lines carry the fabric's couplings outside the star (bending, shear);
         the coarse operators' corners are not lumped: they did not make the V-cycle indefinite,
         and lumping them slowed it (docs/static.md) */
      lines->lump        = l == levels - 1 ? ss->opt.line_lump : 0.0;
      lines->tangents    = &ss->tangents;
      lines->refresh     = RefreshLevels;
      lines->refresh_ctx = ss;
      PetscCall(PCMGGetSmootherDown(pc, l, &smoother));
      PetscCall(SetLineSmoother(smoother, down, lines));
      PetscCall(KSPSetInitialGuessNonzero(smoother, PETSC_FALSE));
      PetscCall(PCMGGetSmootherUp(pc, l, &smoother));
      PetscCall(SetLineSmoother(smoother, up, lines));
    }
  } else { /* a grid too small for multigrid on its layout (a small one, or a strip a few yarns wide): a direct
              solve by MUMPS, which PETSc's Debian build has; GAMG, which balances no slack net, only without it */
    PetscBool   mumps;
    PetscMPIInt size;
    PetscCall(PetscHasExternalPackage("mumps", &mumps));
    PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject) pc), &size));
    if (mumps && size > 1) { /* MUMPS's parallel factors sum the fronts' contributions in the order its messages
                                arrive: they differ in the last bits from run to run, and so did Newton's path (a
                                restart on the same ranks was not the uninterrupted run). Each rank factors the whole
                                (small) tangent by MUMPS itself, -pc_type redundant: the same from run to run.
                                TAO's Newton factors the tangent unshifted first: on a slack net it is singular, and
                                after MUMPS's failed factors there TAO's solve stopped the run (INFOG(1)=-3); PETSc's
                                own LU reports the zero pivot, and TAO shifts the tangent */
      KSP inner;
      PC  lu;
      PetscCall(PCSetType(pc, PCREDUNDANT));
      PetscCall(PCRedundantGetKSP(pc, &inner));
      PetscCall(KSPGetPC(inner, &lu));
      PetscCall(PCSetType(lu, PCLU));
      PetscCall(PCFactorSetMatSolverType(lu, ss->opt.tao ? MATSOLVERPETSC : MATSOLVERMUMPS));
    } else if (mumps) {
      PetscCall(PCSetType(pc, PCLU));
      PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
    } else
      PetscCall(PCSetType(pc, PCGAMG));
  }
  if (!ss->stencil) {
    PetscCall(MatNullSpaceCreateRigidBody(fab->grid.X0, &rigid)); /* GAMG's near-null space */
    PetscCall(MatSetNearNullSpace(ss->J, rigid));
    PetscCall(MatNullSpaceDestroy(&rigid));
  }
  PetscFunctionReturn(0);
}

/* A failed factorisation's mark, cleared in pc and the preconditioners inside it (redundant's, bjacobi's and
   asm's blocks, once set up): PETSc's set-up does not clear it, so a reset preconditioner still failed */
static PetscErrorCode ClearFailures(PC pc)
{
  PetscBool redundant, blocks;
  PetscInt  n = 0;
  KSP      *sub = NULL, inner;

  PetscFunctionBeginUser;
  PetscCall(PCSetFailedReason(pc, PC_NOERROR));
  if (!pc->setupcalled) PetscFunctionReturn(0); /* no blocks to reach */
  PetscCall(PetscObjectTypeCompare((PetscObject) pc, PCREDUNDANT, &redundant));
  if (redundant) {
    PetscCall(PCRedundantGetKSP(pc, &inner));
    sub = &inner, n = 1;
  } else {
    PetscCall(PetscObjectTypeCompare((PetscObject) pc, PCBJACOBI, &blocks));
    if (blocks) PetscCall(PCBJacobiGetSubKSP(pc, &n, NULL, &sub));
    else {
      PetscCall(PetscObjectTypeCompare((PetscObject) pc, PCASM, &blocks));
      if (blocks) PetscCall(PCASMGetSubKSP(pc, &n, NULL, &sub));
    }
  }
  for (PetscInt i = 0; i < n; i++) {
    PC sub_pc;
    PetscCall(KSPGetPC(sub[i], &sub_pc));
    PetscCall(ClearFailures(sub_pc));
  }
  PetscFunctionReturn(0);
}

/* A retry's preconditioner from scratch: after a numeric factorisation of a singular tangent fails (from
   -snes_shift_start 0 on a slack net), PETSc keeps the failed factor on the same pattern and refactors no more
   (MUMPS says "called after analysis phase fails", ILU and LU skip the numeric step, bjacobi and asm blocks
   alike), so the stiffer retries failed too and the load step ended unbalanced with 0 Newton steps. Reset
   whole (the outer preconditioner with its blocks: a block reset alone was left empty where
   -snes_lag_preconditioner -2 never set the outer one up again), it is set up anew on the next tangent. The
   multigrid keeps its hierarchy (the grid's interpolations; its smoothers do not factor by default). */
static PetscErrorCode FreshFactors(StaticSolver ss)
{
  KSP       ksp;
  PC        pc;
  PetscBool mg;

  PetscFunctionBeginUser;
  PetscCall(SNESGetKSP(ss->snes, &ksp));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(ClearFailures(pc));
  PetscCall(PetscObjectTypeCompare((PetscObject) pc, PCMG, &mg));
  /* one never set up has nothing to reset (and SuperLU_DIST's reset then read a communicator attribute it had not made:
     MPI_ERR_KEYVAL, an abort) */
  if (!mg && pc->setupcalled) PetscCall(PCReset(pc));
  PetscFunctionReturn(0);
}

static PetscErrorCode SetDefaults(StaticSolver ss)
{
  KSP            ksp;
  SNESLineSearch ls;

  PetscFunctionBeginUser;
  PetscCall(SNESSetType(ss->snes, SNESNEWTONLS));
  PetscCall(SNESGetLineSearch(ss->snes, &ls));
  PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHSHELL));
  PetscCall(SNESLineSearchShellSetUserFunc(ls, EnergyLineSearch, ss));
  PetscCall(SNESSetTolerances(ss->snes, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, 200, 100000));
  /* CG stops at negative curvature with a descent direction (its iterate so far): the line
     search takes it, and AdaptShift stiffens the next tangent */
  PetscCall(SNESSetMaxLinearSolveFailures(ss->snes, PETSC_MAX_INT));
  /* the multigrid hierarchy (Galerkin products, line factors) of every second tangent: the
     Krylov count grows a little, the time falls a little (3 % on the pushing test; docs/static.md) */
  PetscCall(SNESSetLagPreconditioner(ss->snes, 2));
  PetscCall(SNESGetKSP(ss->snes, &ksp));
  PetscCall(KSPSetType(ksp, KSPCG));
  /* the true residual's reduction: the preconditioned norm of a multigrid on this anisotropic
     tangent overstates it, and Newton then takes an extra step per load step */
  PetscCall(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED));
  PetscCall(KSPSetTolerances(ksp, 1e-3, PETSC_DEFAULT, PETSC_DEFAULT, 1000));
  PetscCall(SetPreconditioner(ss, ksp));
  PetscFunctionReturn(0);
}

/* The grid's layout (same sizes and ownership, so the same global vectors) with the stencil
   the tangent needs: a segment couples neighbours along a yarn (star, width 1), a shear crossing
   its diagonal neighbours too (box, width 1), a bending centre the points two apart (star,
   width 2), both the box of width 2. Its ghost points number the tangent's columns
   (MatSetValuesBlockedLocal); the tangent's own preallocation is CreateTangent's, and the
   multigrid levels are its coarsenings. */
static PetscErrorCode CreateMatrixDM(Fabric fab, DM *dm)
{
  const Patch    *p = &fab->grid.patch;
  const PetscInt *lx, *ly;
  PetscInt        m, n;
  DMDAStencilType type  = p->shear ? DMDA_STENCIL_BOX : DMDA_STENCIL_STAR;
  PetscInt        width = p->bending ? 2 : 1;

  PetscFunctionBeginUser;
  PetscCall(DMDAGetInfo(fab->grid.da, NULL, NULL, NULL, NULL, &m, &n, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
  PetscCall(DMDAGetOwnershipRanges(fab->grid.da, &lx, &ly, NULL));
  PetscCall(
      DMDACreate2d(fab->comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, type, p->nx, p->ny, m, n, 3, width, lx, ly, dm));
  PetscCall(DMSetUp(*dm));
  PetscFunctionReturn(0);
}

/* The tangent: an AIJ matrix of the grid's layout (3x3 blocks, the DM's local numbering)
   preallocated with the blocks the terms fill, the slots of SlotUsed: 5 a row for traction alone,
   9 with shear, 13 with shear and bending, where the DMDA's box of width 2 would reserve 25.
   FormJacobian inserts every one of them in an owned row, so the structure stays fixed. */
static PetscErrorCode CreateTangent(StaticSolver ss)
{
  const Patch           *p    = &ss->fab->grid.patch;
  const PetscInt         npts = p->xm * p->ym;
  PetscInt              *dnz, *onz;
  ISLocalToGlobalMapping l2g;

  PetscFunctionBeginUser;
  if (ss->stencil) { /* the same slots by stencil; the levels' Galerkin operators on theirs */
    int          di[ROW_SLOTS], dj[ROW_SLOTS], dic[STENCIL_MAX_SLOTS], djc[STENCIL_MAX_SLOTS];
    PetscInt     ns = 0, nsc;
    StencilData *d;
    for (int s = 0; s < ROW_SLOTS; s++)
      if (SlotUsed(p, s)) di[ns] = SlotDi[s], dj[ns] = SlotDj[s], ns++;
    PetscCall(StencilMatCreate(ss->dm, ns, di, dj, &ss->J));
    PetscCall(StencilMatGetData(ss->J, &d));
    for (int s = 0; s < ROW_SLOTS; s++)
      ss->sslot[s] = SlotUsed(p, s) ? d->slot[SlotDj[s] + 2][SlotDi[s] + 2] : -1;
    PetscCall(StencilCoarseSlots(ss->J, &nsc, dic, djc));
    for (PetscInt l = 0; l < ss->levels - 1; l++)
      PetscCall(StencilMatCreate(ss->dms[l], nsc, dic, djc, &ss->Ac[l]));
    PetscCall(DMCreateMatrix(ss->dms[0], &ss->Acoarse));
    ss->levels_at = -1;
    PetscFunctionReturn(0);
  }
  {
    PetscInt nb = 0; /* blocks a row */
    for (int s = 0; s < ROW_SLOTS; s++) nb += SlotUsed(p, s) ? 1 : 0;
    PetscCall(CheckRankEntries(ss->fab->comm, 9.0 * (double) nb * (double) npts, 9 * nb, "its tangent's entries"));
  }
  PetscCall(PetscCalloc2(npts, &dnz, npts, &onz));
  for (PetscInt k = 0; k < npts; k++) {
    const PetscInt i = p->xs + k % p->xm, j = p->ys + k / p->xm;
    for (int s = 0; s < ROW_SLOTS; s++) {
      const PetscInt ic = i + SlotDi[s], jc = j + SlotDj[s];
      if (!SlotUsed(p, s) || ic < 0 || ic >= p->nx || jc < 0 || jc >= p->ny) continue;
      if (ic >= p->xs && ic < p->xs + p->xm && jc >= p->ys && jc < p->ys + p->ym) dnz[k]++;
      else onz[k]++;
    }
  }
  PetscCall(MatCreate(ss->fab->comm, &ss->J));
  PetscCall(MatSetSizes(ss->J, 3 * npts, 3 * npts, PETSC_DETERMINE, PETSC_DETERMINE));
  PetscCall(MatSetBlockSize(ss->J, 3));
  PetscCall(MatSetType(ss->J, MATAIJ));
  PetscCall(MatXAIJSetPreallocation(ss->J, 3, dnz, onz, NULL, NULL));
  PetscCall(PetscFree2(dnz, onz));
  PetscCall(DMGetLocalToGlobalMapping(ss->dm, &l2g));
  PetscCall(MatSetLocalToGlobalMapping(ss->J, l2g, l2g));
  PetscCall(MatSetDM(ss->J, ss->dm));
  PetscCall(MatSetOption(ss->J, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  PetscFunctionReturn(0);
}

/* TAO's view of the same problem (-static_minimizer tao): Pi and its gradient (the residual),
   the tangent without the shift (TAO's Newton methods perturb or bound the step themselves), and
   the explicit path's balance test */
static PetscErrorCode TaoObjectiveAndGradient(Tao tao, Vec U, PetscReal *pi, Vec G, void *ctx)
{
  PetscFunctionBeginUser;
  (void) tao;
  PetscCall(FormObjective(NULL, U, pi, ctx));
  PetscCall(FormFunction(NULL, U, G, ctx));
  PetscFunctionReturn(0);
}

static PetscErrorCode TaoHessian(Tao tao, Vec U, Mat H, Mat Hpre, void *ctx)
{
  StaticSolver ss = (StaticSolver) ctx;

  PetscFunctionBeginUser;
  (void) tao;
  ss->h->shift = 0;
  PetscCall(FormJacobian(NULL, U, H, Hpre, ctx));
  PetscFunctionReturn(0);
}

static PetscErrorCode TaoBalanced(Tao tao, void *ctx)
{
  StaticSolver       ss  = (StaticSolver) ctx;
  Fabric             fab = ss->fab;
  Vec                X, G;
  PetscReal          fmax;
  TaoConvergedReason reason;

  PetscFunctionBeginUser;
  /* the residual and the largest tension at the iterate: the last evaluation may have been at a
     trial point the trust region rejected, whose tension (the test's scale) can be far larger */
  PetscCall(TaoGetSolution(tao, &X));
  PetscCall(DMGetGlobalVector(fab->grid.da, &G));
  PetscCall(FormFunction(NULL, X, G, ss));
  PetscCall(FreeForceMax(ss, G, &fmax));
  PetscCall(DMRestoreGlobalVector(fab->grid.da, &G));
  if (fmax <= fab->s.num.balance_tol * PetscMax(ss->tmax, fab->step.force_floor)) {
    PetscCall(TaoSetConvergedReason(tao, TAO_CONVERGED_USER));
    PetscFunctionReturn(0);
  }
  PetscCall(TaoDefaultConvergenceTest(tao, NULL)); /* NaN, iteration and evaluation limits */
  PetscCall(TaoGetConvergedReason(tao, &reason));
  if (reason > 0) PetscCall(TaoSetConvergedReason(tao, reason = TAO_CONTINUE_ITERATING)); /* only the balance test converges */
  if (reason == TAO_CONTINUE_ITERATING && ss->watch) { /* the solve goes on: the driver's look */
    StaticProgress p = {0, 0, 0, 0, 0};
    PetscCall(TaoGetIterationNumber(tao, &p.its));
    PetscCall(TaoGetLinearSolveIterations(tao, &p.lits));
    p.attempt_its = ss->base + p.its;
    if (p.its > 0) PetscCall(ss->watch->look(ss->watch->ctx, &p, &ss->watch_stop));
    if (ss->watch_stop) PetscCall(TaoSetConvergedReason(tao, TAO_DIVERGED_USER));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode CreateTao(StaticSolver ss)
{
  KSP ksp;

  PetscFunctionBeginUser;
  PetscCall(TaoCreate(ss->fab->comm, &ss->tao));
  PetscCall(TaoSetType(ss->tao, TAONLS));
  PetscCall(TaoSetSolution(ss->tao, ss->fab->state.X));
  PetscCall(TaoSetObjectiveAndGradient(ss->tao, NULL, TaoObjectiveAndGradient, ss));
  PetscCall(TaoSetHessian(ss->tao, ss->J, ss->J, TaoHessian, ss));
  PetscCall(TaoSetConvergenceTest(ss->tao, TaoBalanced, ss));
  PetscCall(TaoSetTolerances(ss->tao, 0, 0, 0));
  PetscCall(TaoSetMaximumIterations(ss->tao, 200));
  PetscCall(TaoSetFromOptions(ss->tao)); /* first: a -tao_type replaces the KSP */
  /* the KSP of the type chosen (options prefix -tao_nls_, -tao_ntr_ ...): the SNES path's
     tolerance and preconditioner, at most 100 iterations (TAO's Newton step is a truncated CG:
     one cut short is still a descent direction; the drape by -tao_type ntr spent most of its CG
     iterations in the few steps that ran past 100, docs/static.md), then its options */
  PetscCall(TaoGetKSP(ss->tao, &ksp)); /* a type without one is refused by StaticOptionsCheck */
  PetscCall(KSPSetDM(ksp, ss->dm));
  PetscCall(KSPSetDMActive(ksp, PETSC_FALSE));
  PetscCall(KSPSetTolerances(ksp, 1e-3, PETSC_DEFAULT, PETSC_DEFAULT, 100));
  PetscCall(SetPreconditioner(ss, ksp));
  PetscCall(KSPSetFromOptions(ksp));
  PetscFunctionReturn(0);
}

static PetscErrorCode SequenceSetUp(StaticSolver ss);

/* the solver of fab with -static_sequence's coarser fabrics below it (sequence < 0: as the option says) */
static PetscErrorCode StaticCreateLevel(Fabric fab, PetscInt sequence, StaticSolver *out)
{
  StaticSolver ss;
  const Patch *p = &fab->grid.patch;
  Vec          flag, flagl;
  PetscScalar *a;
  PetscReal    mmax = 0;

  PetscFunctionBeginUser;
  if (!EV_LineSolve) {
    PetscClassId id;
    PetscCall(PetscClassIdRegister("Static", &id));
    PetscCall(PetscLogEventRegister("StaticLineSetUp", id, &EV_LineSetUp));
    PetscCall(PetscLogEventRegister("StaticLineSolve", id, &EV_LineSolve));
    PetscCall(PetscLogEventRegister("StaticGalerkin", id, &EV_Galerkin));
  }
  PetscCall(PetscNew(&ss));
  ss->fab = fab;
  PetscCall(CreateMatrixDM(fab, &ss->dm));
  PetscCall(StaticOptionsRead(fab->comm, &ss->opt));
  if (sequence >= 0) ss->opt.sequence = sequence;
  PetscCall(MultigridHierarchy(ss->dm, &ss->levels, ss->dms, ss->Ps));
  ss->stencil = ss->opt.tangent == TANGENT_STENCIL && StaticOptionsStencilFits(&ss->opt) && ss->levels > 1 ? PETSC_TRUE
                                                                                                : PETSC_FALSE;
  if (sequence < 0 && ss->opt.tangent_set && ss->opt.tangent == TANGENT_STENCIL && ss->levels < 2) { /* said with -quiet too: not a progress line */
    PetscBool mumps;
    PetscCall(PetscHasExternalPackage("mumps", &mumps));
    PetscCall(PetscPrintf(fab->comm,
                          "fabric: -static_tangent stencil: %" PetscInt_FMT " x %" PetscInt_FMT " crossings on %d ranks are too "
                          "few for multigrid on the grid's layout (4 crossings a rank a side); the tangent is stored in AIJ "
                          "for %s\n",
                          fab->s.spec.nx, fab->s.spec.ny, fab->size, mumps ? "a direct solve" : "GAMG"));
  }
  PetscCall(CreateTangent(ss));
  PetscCall(MatSetOption(ss->J, MAT_SYMMETRIC, PETSC_TRUE));
  PetscCall(VecDuplicate(fab->state.X, &ss->Xbc));
  PetscCall(VecDuplicate(fab->state.X, &ss->Xstart));
  ss->h = &fab->state.hist; /* restored by a restart, else empty */
  for (int q = 0; q < 3; q++)
    if (!ss->h->Xh[q]) PetscCall(VecDuplicate(fab->state.X, &ss->h->Xh[q]));
  /* the free flags, ghosted */
  PetscCall(DMGetGlobalVector(fab->grid.da, &flag));
  PetscCall(DMGetLocalVector(fab->grid.da, &flagl));
  PetscCall(VecGetArray(flag, &a));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) {
    a[3 * k] = a[3 * k + 1] = a[3 * k + 2] = fab->grid.inv_m[k] > 0 ? 1.0 : 0.0;
    if (fab->grid.inv_m[k] > 0) mmax = PetscMax(mmax, fab->grid.mass[k]);
  }
  PetscCall(VecRestoreArray(flag, &a));
  PetscCall(HaloExchange(fab->grid.da, flag, flagl));
  PetscCall(PetscMalloc1(p->gxm * p->gym, &ss->free_g));
  for (int q = 0; q < 3; q++) PetscCall(PetscMalloc1(9 * ROW_SLOTS * (p->xm + 2), &ss->ring.buf[q]));
  PetscCall(VecGetArray(flagl, &a));
  for (PetscInt g = 0; g < p->gxm * p->gym; g++) ss->free_g[g] = a[3 * g] > 0.5 ? 1 : 0;
  PetscCall(VecRestoreArray(flagl, &a));
  PetscCall(DMRestoreLocalVector(fab->grid.da, &flagl));
  PetscCall(DMRestoreGlobalVector(fab->grid.da, &flag));
  /* a segment's stiffness, from the stable step's bound: omega_max^2 m ~ 8 k for four springs */
  PetscCall(GlobalMax(fab->comm, &mmax, 1));
  ss->k_ref = PetscMax(fab->step.omega_max * fab->step.omega_max * mmax / 8.0, PETSC_SMALL);
  PetscCall(SNESCreate(fab->comm, &ss->snes));
  PetscCall(SNESSetDM(ss->snes, ss->dm));
  PetscCall(SNESSetApplicationContext(ss->snes, ss));
  PetscCall(SNESSetFunction(ss->snes, NULL, FormFunction, ss));
  PetscCall(SNESSetObjective(ss->snes, FormObjective, ss));
  PetscCall(SNESSetJacobian(ss->snes, ss->J, ss->J, FormJacobian, ss));
  PetscCall(SNESSetUpdate(ss->snes, AdaptShift));
  PetscCall(SNESSetConvergenceTest(ss->snes, Converged, ss, NULL));
  PetscCall(SetDefaults(ss));
  if (ss->opt.tao) PetscCall(CreateTao(ss)); /* its own options; the SNES path's are refused (StaticOptionsCheck) */
  else PetscCall(SNESSetFromOptions(ss->snes));
  if (ss->stencil) { /* a preconditioner chosen under an options prefix (TAO's KSP) */
    KSP       ksp;
    PC        pc;
    PetscBool mg;
    if (ss->opt.tao) PetscCall(TaoGetKSP(ss->tao, &ksp));
    else PetscCall(SNESGetKSP(ss->snes, &ksp));
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PetscObjectTypeCompare((PetscObject) pc, PCMG, &mg));
    if (!mg) { /* a Krylov method that brings its own preconditioner (-ksp_type fetidp) set another */
      PCType type;
      char   given[512];
      PetscCall(PCGetType(pc, &type));
      SolverOptionsGiven(given, sizeof given);
      SETERRQ(fab->comm, PETSC_ERR_USER_INPUT,
              "the solver options given (%s) set the preconditioner %s; the tangent stored by stencil (the default, "
              "-static_tangent stencil) needs the multigrid (mg): add -static_tangent aij for another one",
              given, type ? type : "none");
    }
  }
  PetscCall(SequenceSetUp(ss));
  *out = ss;
  PetscFunctionReturn(0);
}

PetscErrorCode StaticCreate(Fabric fab, StaticSolver *out)
{
  char     list[256] = "";
  PetscInt used      = 0;

  PetscFunctionBeginUser;
  PetscCall(StaticCreateLevel(fab, -1, out));
  if ((*out)->opt.tao && (fab->s.yarns.warp.break_ey > 0 || fab->s.yarns.weft.break_ey > 0)) /* with -quiet too */
    PetscCall(PetscPrintf(fab->comm,
                          "fabric: warning: -static_minimizer tao with yarns that can break: on the states after a tear "
                          "TAO's Newton stalls (its line search: 'rounding errors may prevent further progress'), and the "
                          "load steps after it end unbalanced or the run stops; SNES (the default) balances them "
                          "(docs/static.md)\n"));
  for (StaticSolver c = (*out)->coarse; c; c = c->coarse, used++) {
    size_t len;
    PetscCall(PetscStrlen(list, &len));
    PetscCall(PetscSNPrintf(list + len, sizeof list - len, "%s%" PetscInt_FMT " x %" PetscInt_FMT, used ? ", " : "",
                            c->fab->s.spec.nx, c->fab->s.spec.ny));
  }
  if ((*out)->opt.sequence > used) /* say so, with -quiet too: the option asked for more */
    PetscCall(PetscPrintf(fab->comm,
                          "fabric: -static_sequence %" PetscInt_FMT ": %" PetscInt_FMT " coarser fabric%s%s%s%s (a coarser one "
                          "needs an odd number of crossings a side, a point load on an even crossing, multigrid levels on %d rank%s and a "
                          "ball at least two of its yarn spacings wide; not the strip or bias test)\n",
                          (*out)->opt.sequence, used, used == 1 ? "" : "s", used ? " (" : "", list, used ? ")" : "",
                          fab->size, fab->size == 1 ? "" : "s"));
  PetscFunctionReturn(0);
}

/* a vector of the coarse fabric's grid to the multigrid level below this one (the same crossings
   in another layout), through the natural ordering */
static PetscErrorCode ToLevelBelow(StaticSolver ss, Vec c)
{
  PetscFunctionBeginUser;
  PetscCall(DMDAGlobalToNaturalBegin(ss->cfab->grid.da, c, INSERT_VALUES, ss->cnat));
  PetscCall(DMDAGlobalToNaturalEnd(ss->cfab->grid.da, c, INSERT_VALUES, ss->cnat));
  PetscCall(VecScatterBegin(ss->nat, ss->cnat, ss->lnat, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(ss->nat, ss->cnat, ss->lnat, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(DMDANaturalToGlobalBegin(ss->dms[ss->levels - 2], ss->lnat, INSERT_VALUES, ss->clevel));
  PetscCall(DMDANaturalToGlobalEnd(ss->dms[ss->levels - 2], ss->lnat, INSERT_VALUES, ss->clevel));
  PetscFunctionReturn(0);
}

/* -static_sequence: the fabric at half the thread density (FabricCreateCoarse) and its own solver,
   with one coarser fabric fewer below it; none where its crossings are not every other one of
   this grid's, or where this grid's multigrid has no level of its size or its own would have no
   level below it (a grid too small for the ranks) */
static PetscErrorCode SequenceSetUp(StaticSolver ss)
{
  Fabric       fab = ss->fab, cf = NULL;
  PetscInt     M = 0, N = 0;
  PetscScalar *a;

  PetscFunctionBeginUser;
  ss->corrected_at = ss->solved_at = -1;
  if (ss->opt.sequence < 1 || ss->levels < 2) PetscFunctionReturn(0);
  PetscCall(DMDAGetInfo(ss->dms[ss->levels - 2], NULL, &M, &N, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL,
                        NULL));
  if (2 * M - 1 != fab->s.spec.nx || 2 * N - 1 != fab->s.spec.ny) PetscFunctionReturn(0);
  PetscCall(FabricCreateCoarse(fab, &cf));
  if (!cf) PetscFunctionReturn(0);
  PetscCall(StableStep(cf)); /* its stiffness scale (StaticCreateLevel's k_ref) */
  cf->step.bound_fresh = PETSC_TRUE;
  ss->cfab             = cf;
  PetscCall(StaticCreateLevel(cf, ss->opt.sequence - 1, &ss->coarse));
  if (ss->coarse->levels < 2) { /* too small for its own multigrid: it would cost more than it saves */
    PetscCall(StaticDestroy(&ss->coarse));
    PetscCall(FabricDestroy(&ss->cfab));
    PetscFunctionReturn(0);
  }
  PetscCall(VecDuplicate(cf->state.X, &ss->coarse->guess));
  PetscCall(DMDACreateNaturalVector(cf->grid.da, &ss->cnat));
  PetscCall(DMDACreateNaturalVector(ss->dms[ss->levels - 2], &ss->lnat));
  {
    IS       is;
    PetscInt lo, hi;
    PetscCall(VecGetOwnershipRange(ss->lnat, &lo, &hi));
    PetscCall(ISCreateStride(fab->comm, hi - lo, lo, 1, &is));
    PetscCall(VecScatterCreate(ss->cnat, is, ss->lnat, is, &ss->nat));
    PetscCall(ISDestroy(&is));
  }
  PetscCall(DMCreateGlobalVector(ss->dms[ss->levels - 2], &ss->clevel));
  PetscCall(VecDuplicate(fab->state.X, &ss->fcorr));
  PetscCall(VecDuplicate(fab->state.X, &ss->fwt));
  PetscCall(VecDuplicate(cf->state.X, &ss->cmask));
  PetscCall(VecGetArray(ss->cmask, &a));
  {
    const Patch *p = &cf->grid.patch;
    for (PetscInt j = 0; j < p->ym; j++)
      for (PetscInt i = 0; i < p->xm; i++) {
        const PetscInt k = j * p->xm + i;
        a[3 * k] = a[3 * k + 1] = a[3 * k + 2] = p->exists[(j + p->ys - p->gys) * p->gxm + i + p->xs - p->gxs] ? 1.0
                                                                                                                : 0.0;
      }
  }
  PetscCall(VecRestoreArray(ss->cmask, &a));
  PetscCall(ToLevelBelow(ss, ss->cmask));
  PetscCall(MatMult(ss->Ps[ss->levels - 1], ss->clevel, ss->fwt)); /* the weight of the existing coarse points */
  PetscFunctionReturn(0);
}

void StaticCoarser(StaticSolver ss, Fabric *cfab, StaticSolver *coarse)
{
  *cfab   = ss->cfab;
  *coarse = ss->coarse;
}

/* Grid sequencing: the coarse fabric's solve of this load step moved its crossings from its first
   guess by dX (its balanced state minus that guess); each free crossing of this grid moves by
   dX interpolated bilinearly from the existing coarse crossings around it (their weights scaled to
   1; a crossing with none around it stays). Where the coarse solve started from its rest state while
   this one starts from a balanced state (a restart), the coarse displacement from rest is put on
   this grid's rest state instead. */
static PetscErrorCode CoarseGuess(StaticSolver ss, PetscBool *moved)
{
  Fabric             fab = ss->fab;
  StaticSolver       cs  = ss->coarse;
  const PetscBool    from_rest = cs && cs->guess_rest && ss->h->nhist > 0 ? PETSC_TRUE : PETSC_FALSE;
  PetscScalar       *x;
  const PetscScalar *c, *w, *x0;

  PetscFunctionBeginUser;
  *moved = PETSC_FALSE;
  if (!cs || cs->solved_at != fab->load.load_step || !cs->solved_balanced || ss->corrected_at == fab->load.load_step)
    PetscFunctionReturn(0);
  ss->corrected_at = fab->load.load_step;
  if (from_rest) PetscCall(VecWAXPY(cs->guess, -1.0, ss->cfab->grid.X0, ss->cfab->state.X)); /* dX, in the guess's place */
  else PetscCall(VecAYPX(cs->guess, -1.0, ss->cfab->state.X));
  PetscCall(VecPointwiseMult(cs->guess, cs->guess, ss->cmask));
  PetscCall(ToLevelBelow(ss, cs->guess));
  PetscCall(MatMult(ss->Ps[ss->levels - 1], ss->clevel, ss->fcorr));
  PetscCall(VecGetArray(fab->state.X, &x));
  PetscCall(VecGetArrayRead(ss->fcorr, &c));
  PetscCall(VecGetArrayRead(ss->fwt, &w));
  PetscCall(VecGetArrayRead(fab->grid.X0, &x0));
  for (PetscInt k = 0; k < 3 * fab->grid.nloc; k++)
    if (fab->grid.inv_m[k / 3] > 0 && w[k] > 0) x[k] = (from_rest ? x0[k] : x[k]) + c[k] / w[k];
  PetscCall(VecRestoreArrayRead(fab->grid.X0, &x0));
  PetscCall(VecRestoreArrayRead(ss->fwt, &w));
  PetscCall(VecRestoreArrayRead(ss->fcorr, &c));
  PetscCall(VecRestoreArray(fab->state.X, &x));
  *moved = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode StaticDestroy(StaticSolver *pss)
{
  StaticSolver ss = *pss;

  PetscFunctionBeginUser;
  if (!ss) PetscFunctionReturn(0);
  PetscCall(SNESDestroy(&ss->snes));
  PetscCall(TaoDestroy(&ss->tao));
  PetscCall(MatDestroy(&ss->J));
  PetscCall(MatDestroy(&ss->Acoarse));
  for (PetscInt l = 0; l < ss->levels - 1; l++) {
    PetscCall(MatDestroy(&ss->Ac[l]));
    PetscCall(DMDestroy(&ss->dms[l]));
    PetscCall(MatDestroy(&ss->Ps[l + 1]));
  }
  PetscCall(DMDestroy(&ss->dm));
  PetscCall(VecDestroy(&ss->Xbc));
  PetscCall(VecDestroy(&ss->Xstart));
  PetscCall(StaticDestroy(&ss->coarse));
  PetscCall(FabricDestroy(&ss->cfab));
  PetscCall(VecDestroy(&ss->cnat));
  PetscCall(VecDestroy(&ss->lnat));
  PetscCall(VecScatterDestroy(&ss->nat));
  PetscCall(VecDestroy(&ss->clevel));
  PetscCall(VecDestroy(&ss->fcorr));
  PetscCall(VecDestroy(&ss->fwt));
  PetscCall(VecDestroy(&ss->cmask));
  PetscCall(VecDestroy(&ss->guess));
  PetscCall(PetscFree(ss->free_g));
  for (int q = 0; q < 3; q++) PetscCall(PetscFree(ss->ring.buf[q]));
  PetscCall(PetscFree(ss));
  *pss = NULL;
  PetscFunctionReturn(0);
}

/* Newton's first guess from the balanced states of the last load steps: the free crossings'
   positions extrapolated in the load factor by the polynomial through the last order + 1 of them
   (order 1: the secant; 2: a parabola), where nothing else moved them since the last (a
   prediction of the driver is kept). The held crossings stay where the load step put them. */
static PetscErrorCode Extrapolate(StaticSolver ss)
{
  Fabric             fab = ss->fab;
  const PetscInt     np  = PetscMin(ss->h->nhist, ss->opt.order + 1);
  const PetscReal    l   = fab->load.load_factor;
  PetscReal          w[3], moved = 0;
  PetscScalar       *x;
  const PetscScalar *h[3];

  PetscFunctionBeginUser;
  if (np < 2 || !(l > ss->h->lh[0]) || fab->stats.rupture.segments != ss->h->segments)
    PetscFunctionReturn(0); /* yarns broke since: the states are of another fabric */
  for (PetscInt a = 0; a < np; a++) { /* Lagrange weights at l */
    w[a] = 1;
    for (PetscInt b = 0; b < np; b++)
      if (b != a) w[a] *= (l - ss->h->lh[b]) / (ss->h->lh[a] - ss->h->lh[b]);
  }
  PetscCall(VecGetArray(fab->state.X, &x));
  for (PetscInt a = 0; a < np; a++) PetscCall(VecGetArrayRead(ss->h->Xh[a], &h[a]));
  for (PetscInt k = 0; k < 3 * fab->grid.nloc; k++)
    if (fab->grid.inv_m[k / 3] > 0) moved = PetscMax(moved, PetscAbsReal(x[k] - h[0][k]));
  PetscCall(GlobalMax(fab->comm, &moved, 1));
  if (moved == 0)
    for (PetscInt k = 0; k < 3 * fab->grid.nloc; k++) {
      if (!(fab->grid.inv_m[k / 3] > 0)) continue;
      x[k] = 0;
      for (PetscInt a = 0; a < np; a++) x[k] += w[a] * h[a][k];
    }
  for (PetscInt a = 0; a < np; a++) PetscCall(VecRestoreArrayRead(ss->h->Xh[a], &h[a]));
  PetscCall(VecRestoreArray(fab->state.X, &x));
  PetscFunctionReturn(0);
}

/* Without a prediction (-predict none) the ball is put at its new place with the fabric where it
   was: a free crossing closer to its centre than the contact distance (the ball's radius and half
   the thickness) moves out radially onto that distance. From inside, a crossing's penalty force
   (the contact stiffness times a penetration of up to a load step's travel) threw Newton far off
   (docs/static.md). */
static PetscErrorCode LeaveSphere(StaticSolver ss)
{
  Fabric       fab = ss->fab;
  PetscScalar *x;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(fab->state.X, &x));
  for (PetscInt q = 0; q < fab->bodies.n; q++) {
    const Body *b = &fab->bodies.body[q];
    PetscReal   c[3];
    if (b->kind != BODY_SPHERE) continue;
    BodyPosition(b, fab->load.travel_now, c);
    for (PetscInt k = 0; k < fab->grid.nloc; k++) {
      PetscScalar    *y    = x + 3 * k;
      const PetscReal d[3] = {y[0] - c[0], y[1] - c[1], y[2] - c[2]};
      const PetscReal r    = PetscSqrtReal(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      if (!(fab->grid.inv_m[k] > 0) || !(r < b->reach)) continue;
      for (int e = 0; e < 3; e++) y[e] = c[e] + (r > 0 ? d[e] * (b->reach / r) : b->reach * b->dir[e]); /* at the centre: ahead */
    }
  }
  PetscCall(VecRestoreArray(fab->state.X, &x));
  PetscFunctionReturn(0);
}

/* remember a balanced state. If yarns broke since the last, the states before are forgotten: a fabric with broken
   yarns is another fabric, and a polynomial through states on both sides of a tear threw the next load step's
   first guess far off (a strip's force ran to 14 times its maximum). */
static PetscErrorCode KeepBalanced(StaticSolver ss)
{
  Fabric fab = ss->fab;

  PetscFunctionBeginUser;
  if (fab->stats.rupture.segments != ss->h->segments) ss->h->nhist = 0;
  if (!(ss->h->nhist > 0 && fab->load.load_factor == ss->h->lh[0])) {
    Vec t = ss->h->Xh[2];
    ss->h->Xh[2] = ss->h->Xh[1], ss->h->lh[2] = ss->h->lh[1];
    ss->h->Xh[1] = ss->h->Xh[0], ss->h->lh[1] = ss->h->lh[0];
    ss->h->Xh[0] = t;
    ss->h->nhist = PetscMin(ss->h->nhist + 1, 3);
  }
  ss->h->segments = fab->stats.rupture.segments;
  ss->h->lh[0] = fab->load.load_factor;
  PetscCall(VecCopy(fab->state.X, ss->h->Xh[0]));
  PetscFunctionReturn(0);
}

/* the largest move of a free crossing from the first guess, m (infinite if a position is NaN or Inf) */
static PetscErrorCode SolveMove(StaticSolver ss, PetscReal *move)
{
  Fabric             fab = ss->fab;
  const PetscScalar *x, *x0;
  PetscReal          m = 0;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(fab->state.X, &x));
  PetscCall(VecGetArrayRead(ss->Xstart, &x0));
  for (PetscInt k = 0; k < 3 * fab->grid.nloc; k++) {
    const PetscReal d = PetscAbsReal(x[k] - x0[k]);
    if (!(fab->grid.inv_m[k / 3] > 0)) continue;
    m = d <= PETSC_MAX_REAL ? PetscMax(m, d) : PETSC_INFINITY;
  }
  PetscCall(VecRestoreArrayRead(ss->Xstart, &x0));
  PetscCall(VecRestoreArrayRead(fab->state.X, &x));
  PetscCall(GlobalMax(fab->comm, &m, 1));
  *move = m;
  PetscFunctionReturn(0);
}

void StaticResume(StaticSolver ss, PetscInt attempt_its)
{
  ss->resume = attempt_its;
}

/* the first guess: the positions now, extrapolated from the last balanced states, out of the ball, corrected
   by the coarser fabrics' solve; the shift to start from */
static PetscErrorCode FirstGuess(StaticSolver ss)
{
  Fabric fab = ss->fab;

  PetscFunctionBeginUser;
  PetscCall(Extrapolate(ss));
  if (fab->s.num.predict == PREDICT_NONE && !(ss->h->nhist > 0 && fab->load.load_factor == ss->h->lh[0]))
    PetscCall(LeaveSphere(ss)); /* the ball moved (not a re-solve after yarns broke) */
  if (ss->guess) { /* a coarse level: the finer one's correction starts from here */
    PetscCall(VecCopy(fab->state.X, ss->guess));
    ss->guess_rest = ss->h->nhist ? PETSC_FALSE : PETSC_TRUE;
  }
  {
    PetscBool moved;
    PetscCall(CoarseGuess(ss, &moved));
    if (moved) PetscCall(LeaveSphere(ss)); /* the interpolated crossings out of the ball */
  }
  /* the first load step from -snes_shift_start; a later one from where the last ended (a taut
     fabric: nearly plain Newton), raised by AdaptShift if that fails */
  ss->h->shift = ss->h->nhist ? PetscMin(ss->opt.shift_start, ss->opt.shift_carry * ss->h->shift) : ss->opt.shift_start;
  if (ss->corrected_at == fab->load.load_step) /* from the coarse solution: from where its shift ended */
    ss->h->shift = PetscMin(ss->opt.shift_start, ss->opt.shift_carry * ss->coarse->h->shift);
  PetscFunctionReturn(0);
}

PetscErrorCode StaticSolve(StaticSolver ss, const StaticWatch *watch, StaticResult *r)
{
  Fabric              fab    = ss->fab;
  SNESConvergedReason reason = SNES_CONVERGED_ITERATING;
  PetscInt            its, max_it = 0, resume = ss->resume;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(r, sizeof *r));
  PetscCall(VecCopy(fab->state.X, ss->Xbc));
  ss->resume = 0;
  /* a restart within the solve goes on from the checkpoint's iterate and shift, with the Newton steps its attempt
     had left; a failed attempt is then retried from that iterate */
  if (!resume) PetscCall(FirstGuess(ss));
  PetscCall(VecCopy(fab->state.X, ss->Xstart));
  ss->watch      = watch;
  ss->watch_stop = PETSC_FALSE;
  ss->done_its = ss->done_lits = 0;
  ss->base   = resume;                        /* the first attempt's steps before the restart */
  ss->rnorm0 = resume ? ss->h->rnorm0 : 0.0;  /* and its first residual norm */
  ss->h->rnorm0 = 0;
  if (resume) {
    if (ss->tao) PetscCall(TaoGetMaximumIterations(ss->tao, &max_it));
    else PetscCall(SNESGetTolerances(ss->snes, NULL, NULL, NULL, &max_it, NULL));
    if (ss->tao) PetscCall(TaoSetMaximumIterations(ss->tao, PetscMax(max_it - resume, 0)));
    else PetscCall(SNESSetTolerances(ss->snes, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, PetscMax(max_it - resume, 0), PETSC_DEFAULT));
  }
  if (ss->tao) { /* TAO's Newton: one solve */
    TaoConvergedReason treason;
    PetscCall(TaoSolve(ss->tao));
    if (resume) PetscCall(TaoSetMaximumIterations(ss->tao, max_it));
    PetscCall(TaoGetConvergedReason(ss->tao, &treason));
    PetscCall(TaoGetIterationNumber(ss->tao, &its));
    PetscCall(TaoGetLinearSolveIterations(ss->tao, &r->linear_iterations));
    r->nonlinear_iterations = its;
    PetscCall(PetscStrncpy(r->reason, TaoConvergedReasons[treason], sizeof r->reason));
  }
  for (int attempt = 0; attempt < MAX_ATTEMPTS && !ss->tao; attempt++) { /* a failed solve is retried, stiffer */
    PetscInt  lits;
    PetscReal move;
    /* each attempt's preconditioner afresh: a direct solve's factors that failed (a singular tangent: every yarn of
       a piece broken) are not factored again on the next tangent (MUMPS: "called after analysis phase fails"), and
       the next load step's solve then stopped the run with MUMPS's INFOG(1)=-3 */
    PetscCall(FreshFactors(ss));
    ss->done_its = r->nonlinear_iterations, ss->done_lits = r->linear_iterations;
    PetscCall(SNESSolve(ss->snes, NULL, fab->state.X));
    if (resume && attempt == 0) PetscCall(SNESSetTolerances(ss->snes, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, max_it, PETSC_DEFAULT));
    ss->base = 0, ss->rnorm0 = 0; /* a retry is an attempt of its own */
    PetscCall(SNESGetConvergedReason(ss->snes, &reason));
    PetscCall(SNESGetIterationNumber(ss->snes, &its));
    PetscCall(SNESGetLinearSolveIterations(ss->snes, &lits));
    r->nonlinear_iterations += its;
    r->linear_iterations += lits;
    if (ss->watch_stop) break; /* the run stops (a signal): its checkpoint holds the iterate */
    if (reason == SNES_CONVERGED_SNORM_RELATIVE) { /* PETSc's step-length test, which the balance test does not
                                                      override: after a failed linear solve (CG at an indefinite
                                                      preconditioner) the step was next to nothing, and the load step
                                                      ended unbalanced where a stiffer shift balances it */
      KSP                ksp;
      KSPConvergedReason kreason;
      Vec                R;
      PetscReal          fmax;
      PetscCall(SNESGetKSP(ss->snes, &ksp));
      PetscCall(KSPGetConvergedReason(ksp, &kreason));
      PetscCall(DMGetGlobalVector(fab->grid.da, &R)); /* the residual and the largest tension at the iterate (the
                                                         last evaluation may be a trial point the search refused) */
      PetscCall(FormFunction(NULL, fab->state.X, R, ss));
      PetscCall(FreeForceMax(ss, R, &fmax));
      PetscCall(DMRestoreGlobalVector(fab->grid.da, &R));
      if (kreason < 0 && !(fmax <= fab->s.num.balance_tol * PetscMax(ss->tmax, fab->step.force_floor))) {
        PetscCall(PetscInfo(NULL, "load step %" PetscInt_FMT ": the step-length test ended the solve after a failed linear solve (%s), unbalanced: retried as a failed linear solve\n",
                            fab->load.load_step, KSPConvergedReasons[kreason]));
        reason = SNES_DIVERGED_LINEAR_SOLVE;
      }
    }
    PetscCall(SolveMove(ss, &move));
    if (!(move <= fab->grid.extent) || reason == SNES_DIVERGED_FNORM_NAN ||
        reason == SNES_DIVERGED_DTOL) { /* NaN, Inf, runaway or a residual grown 1e4-fold: again from the first
                                           guess, stiffer */
      PetscCall(PetscInfo(NULL, "load step %" PetscInt_FMT ": the solve moved a crossing %g m, the fabric is %g m (%s)\n",
                          fab->load.load_step, (double) move, (double) fab->grid.extent, SNESConvergedReasons[reason]));
      PetscCall(VecCopy(ss->Xstart, fab->state.X));
      reason = SNES_DIVERGED_FNORM_NAN;
    } else if (reason != SNES_DIVERGED_LINE_SEARCH && reason != SNES_DIVERGED_LINEAR_SOLVE &&
               reason != SNES_DIVERGED_LOCAL_MIN && /* newtonls says a failed line search also so */
               reason != SNES_DIVERGED_TR_DELTA)    /* newtontr's: its trust region shrank to nothing */
      break;
    ss->h->shift = PetscMax(100.0 * ss->h->shift, 1e-6); /* start again from where it stopped, stiffer */
  }
  if (!ss->tao) PetscCall(PetscStrncpy(r->reason, SNESConvergedReasons[reason], sizeof r->reason));
  ss->watch = NULL;
  if (ss->watch_stop) PetscFunctionReturn(0); /* not balanced: the run stops after the iterate's checkpoint */
  {
    PetscReal move = 0;
    char      given[448];
    if (ss->tao) PetscCall(SolveMove(ss, &move));
    SolverOptionsGiven(given, sizeof given);
    char broken[256] = ""; /* pieces the broken yarns cut loose have no state at rest to find */
    if (fab->stats.rupture.segments > 0) /* -rupture_drop_pct: the tests with a force to watch, when it is off */
      PetscCall(PetscSNPrintf(broken, sizeof broken,
                              "; %" PetscInt64_FMT " yarn segments have broken, and a piece they cut loose has no state "
                              "at rest (-solver explicit follows it%s)",
                              (PetscInt64) fab->stats.rupture.segments,
                              ReactionTest(&fab->s) && !(fab->s.rupture.drop > 0)
                                ? "; -rupture_drop_pct 90 ends the test at the rupture"
                                : ""));
    char smaller[160] = ""; /* more load steps make each smaller, up to their limit */
    if (fab->s.load.load_steps < MAX_LOAD_STEPS)
      PetscCall(PetscSNPrintf(smaller, sizeof smaller,
                              ", or the load step is too large a step from its first guess (more -load_steps than %" PetscInt_FMT
                              " make each smaller)",
                              fab->s.load.load_steps));
    PetscCheck(move <= fab->grid.extent && reason != SNES_DIVERGED_FNORM_NAN, fab->comm, PETSC_ERR_FP,
               "numerical failure at load step %" PetscInt_FMT ": the quasi-static solve moved a crossing farther than "
               "the fabric's size %g m, or to NaN or Inf, or its residual diverged (DIVERGED_DTOL)%s; %s%s%s%s%s",
               fab->load.load_step, (double) fab->grid.extent,
               ss->tao ? "" : ", each time from the first guess again with a stiffer shift",
               given[0] ? "the solver options given (" : "the solver's defaults fail on this fabric",
               given, given[0] ? ") may not suit this fabric" : "", smaller, broken);
  }
  /* the state's forces at the solution (the measurements read them) give the balance test */
  {
    const PetscScalar *f;
    const PetscReal   *g      = fab->load.gravity_now;
    PetscReal          red[2] = {0, 0}; /* largest free |F|^2, largest yarn tension */
    PetscCall(ComputeForces(fab, NULL, &red[1]));
    PetscCall(VecGetArrayRead(fab->state.F, &f));
    for (PetscInt k = 0; k < fab->grid.nloc; k++) {
      PetscReal f2 = 0;
      if (!(fab->grid.inv_m[k] > 0)) continue;
      for (int d = 0; d < 3; d++) f2 += PetscSqr(f[3 * k + d] + fab->grid.mass[k] * g[d]);
      red[0] = PetscMax(red[0], f2);
    }
    PetscCall(VecRestoreArrayRead(fab->state.F, &f));
    PetscCall(GlobalMax(fab->comm, red, 2));
    r->residual = PetscSqrtReal(red[0]) / PetscMax(red[1], fab->step.force_floor);
  }
  r->balanced = r->residual <= fab->s.num.balance_tol ? PETSC_TRUE : PETSC_FALSE;
  if (r->balanced) PetscCall(KeepBalanced(ss));
  ss->solved_at       = fab->load.load_step;
  ss->solved_balanced = r->balanced;
  PetscFunctionReturn(0);
}
