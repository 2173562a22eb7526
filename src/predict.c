/* predict.c - displacement prediction at the start of each load step (MODEL.md 10).
 *
 * linear: with d0 the graph distance to the nearest clamped point and d1 to the nearest
 *   grip point, a free point moves by d0/(d0+d1) times the grip step (the paper's
 *   1/5 X, 2/5 X, ... for a strip of 5 rows). With a sphere (pushing), the crossings its new
 *   position would penetrate play the grips' part, and the step is the sphere's.
 * extrapolate: a free point moves by its converged increment of the previous load step,
 *   scaled by the ratio of the grip steps (the first load step falls back to linear).
 * Distances are integers on the grid graph through existing points, computed by local
 * forward/backward sweeps and halo exchanges until no rank changes (a max-reduction),
 * so they are exact and the same on any number of ranks.
 */
#include "predict.h"
#include "comm.h"
#include "events.h"
#include "load.h"

/* Graph distance of every owned point to the nearest source point, through existing
   points (DIST_INF if none is reachable). Sweeps and halo exchanges until no rank changes. */
PetscErrorCode GraphDistance(MPI_Comm comm, DM da, const Patch *p, const char *source, PetscReal *dist)
{
  DM            da1;
  Vec           D, Dl;
  PetscScalar **d;
  PetscReal     changed;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(EV_Predict, 0, 0, 0, 0));
  PetscCall(DMDACreateCompatibleDMDA(da, 1, &da1));
  PetscCall(DMCreateGlobalVector(da1, &D));
  PetscCall(DMCreateLocalVector(da1, &Dl));
  PetscCall(DMDAVecGetArray(da1, D, &d));
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
    for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
      const PetscInt k = (j - p->ys) * p->xm + (i - p->xs);
      d[j][i]          = (source[k] && p->exists[(j - p->gys) * p->gxm + (i - p->gxs)]) ? 0.0 : DIST_INF;
    }
  PetscCall(DMDAVecRestoreArray(da1, D, &d));
  do {
    changed = 0;
    PetscCall(HaloExchange(da1, D, Dl));
    PetscCall(DMDAVecGetArray(da1, Dl, &d));
    for (int pass = 0; pass < 2; pass++) {
      const int step = pass == 0 ? 1 : -1; /* forward sweep looks left/down, backward right/up */
      for (PetscInt jj = 0; jj < p->ym; jj++) {
        const PetscInt j = pass == 0 ? p->ys + jj : p->ys + p->ym - 1 - jj;
        for (PetscInt ii = 0; ii < p->xm; ii++) {
          const PetscInt i  = pass == 0 ? p->xs + ii : p->xs + p->xm - 1 - ii;
          const PetscInt in = i - step, jn = j - step;
          PetscReal      best = d[j][i];
          if (!p->exists[(j - p->gys) * p->gxm + (i - p->gxs)]) continue;
          if (in >= p->gxs && in < p->gxs + p->gxm && p->exists[(j - p->gys) * p->gxm + (in - p->gxs)])
            best = PetscMin(best, d[j][in] + 1);
          if (jn >= p->gys && jn < p->gys + p->gym && p->exists[(jn - p->gys) * p->gxm + (i - p->gxs)])
            best = PetscMin(best, d[jn][i] + 1);
          if (best < d[j][i]) {
            d[j][i] = best;
            changed = 1;
          }
        }
      }
    }
    PetscCall(DMDAVecRestoreArray(da1, Dl, &d));
    PetscCall(OwnedFromLocal(da1, Dl, D));
    PetscCall(GlobalMax(comm, &changed, 1));
  } while (changed > 0);
  PetscCall(DMDAVecGetArray(da1, D, &d));
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
    for (PetscInt i = p->xs; i < p->xs + p->xm; i++) dist[(j - p->ys) * p->xm + (i - p->xs)] = d[j][i];
  PetscCall(DMDAVecRestoreArray(da1, D, &d));
  PetscCall(VecDestroy(&Dl));
  PetscCall(VecDestroy(&D));
  PetscCall(DMDestroy(&da1));
  PetscCall(PetscLogEventEnd(EV_Predict, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* predict_w = d0/(d0+d1), d0 the graph distance to the clamps, d1 to the moving sources */
static PetscErrorCode LinearWeights(Fabric fab, const char *moving)
{
  PetscReal *d0, *d1;
  char      *src;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc3(fab->grid.nloc, &d0, fab->grid.nloc, &d1, fab->grid.nloc, &src));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) src[k] = (char) (fab->grid.kind[k] == POINT_CLAMPED);
  PetscCall(GraphDistance(fab->comm, fab->grid.da, &fab->grid.patch, src, d0));
  PetscCall(GraphDistance(fab->comm, fab->grid.da, &fab->grid.patch, moving, d1));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) {
    if (d1[k] >= DIST_INF)
      fab->grid.predict_w[k] = 0.0; /* nothing that moves reaches it */
    else if (d0[k] >= DIST_INF)
      fab->grid.predict_w[k] = 1.0; /* moves with the sources */
    else
      fab->grid.predict_w[k] = d0[k] / (d0[k] + d1[k]);
  }
  PetscCall(PetscFree3(d0, d1, src));
  PetscFunctionReturn(0);
}

PetscErrorCode PredictSetUp(Fabric fab)
{
  char *src;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(fab->grid.nloc, &src));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) src[k] = (char) (fab->grid.kind[k] == POINT_GRIP);
  PetscCall(LinearWeights(fab, src));
  PetscCall(PetscFree(src));
  PetscFunctionReturn(0);
}

/* The sphere (pushing): the sources of the linear prediction are the crossings that the
   sphere's position at travel disp would penetrate. They move with it, and the free fabric
   between them and the clamps follows in proportion, a cone from the contact to the ring:
   the membrane's shape, where the flat fabric of the first load step would otherwise have to
   find it by a slow, slack relaxation. */
static PetscErrorCode SphereWeights(Fabric fab, PetscReal disp)
{
  const Scene       *s     = &fab->s;
  const PetscReal    reach = s->bodies.sphere_radius + 0.5 * s->bodies.thickness;
  const PetscScalar *x;
  PetscReal          c[3];
  char              *src;

  PetscFunctionBeginUser;
  for (int d = 0; d < 3; d++) c[d] = fab->grid.centre[d] + s->bodies.sphere_start[d] + disp * s->bodies.sphere_dir[d];
  PetscCall(PetscMalloc1(fab->grid.nloc, &src));
  PetscCall(VecGetArrayRead(fab->state.X, &x));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) {
    const PetscReal r2 = PetscSqr(x[3 * k] - c[0]) + PetscSqr(x[3 * k + 1] - c[1]) + PetscSqr(x[3 * k + 2] - c[2]);
    src[k]             = (char) (fab->grid.kind[k] == POINT_FREE && fab->grid.mass[k] > 0 && r2 < reach * reach);
  }
  PetscCall(VecRestoreArrayRead(fab->state.X, &x));
  PetscCall(LinearWeights(fab, src));
  PetscCall(PetscFree(src));
  PetscFunctionReturn(0);
}

/* Move the free points at the start of a load step whose grips move by grip_step (m) along
   their path, that is by grip_move (m, a vector); *moved: the prediction moved them. A point load
   or the drape's gravity (no grips, no ball) grows by the same share each load step: the
   extrapolating prediction repeats the last converged increment; the linear one has nothing to
   follow. (The static path extrapolates its own balanced states there, static.c.) */
PetscErrorCode PredictLoadStep(Fabric fab, PetscReal grip_step, const PetscReal grip_move[3], PetscBool *moved)
{
  const Scene       *s = &fab->s;
  PetscScalar       *x, *xold = NULL;
  const PetscScalar *a = NULL, *b = NULL;
  const PetscBool    gravity = s->terms.gravity[0] != 0 || s->terms.gravity[1] != 0 || s->terms.gravity[2] != 0;
  /* the square test's gravity acts in full from load step 1 (the drape's grows with the load steps): the first
     increment holds its sag, not a share of the load's, and is not repeated */
  const PetscBool    by_load = (s->test == TEST_DRAPE || (s->test == TEST_SQUARE && !(gravity && fab->load.load_step < 3))) &&
                                   s->num.solver != SOLVER_STATIC
                                   ? PETSC_TRUE
                                   : PETSC_FALSE;
  const PetscBool    have_history = fab->state.Xconv_prev && (fab->load.travel_step_prev != 0 || by_load) ? PETSC_TRUE : PETSC_FALSE;
  /* the static path puts the ball straight at its new place: it starts from the ball's linear
     prediction, which moves the crossings the ball would penetrate with it, never from an
     extrapolation that leaves some inside it (Newton did not recover from that penalty force:
     docs/static.md) */
  const PetscBool ball_static = s->bodies.sphere_radius > 0 && s->num.solver == SOLVER_STATIC ? PETSC_TRUE : PETSC_FALSE;
  PetscBool       extrapolate = s->num.predict == PREDICT_EXTRAPOLATE && have_history && !ball_static ? PETSC_TRUE : PETSC_FALSE;

  PetscFunctionBeginUser;
  if (extrapolate && s->load.waypoints && !by_load) { /* a grip path that turns (or goes back): the last increment
    points the old way, and scaling it pushed the crossings on against the grips (711 te steps at a reversal, against 3
    by the linear prediction); where this step's move is not the last one's direction, the linear prediction */
    PetscReal prev[3], dot = 0, mm = 0, pp = 0;
    GripPathMove(s, fab->grid.pull_dir, fab->load.travel - fab->load.travel_step_prev, fab->load.travel, prev);
    for (int d = 0; d < 3; d++) dot += grip_move[d] * prev[d], mm += grip_move[d] * grip_move[d], pp += prev[d] * prev[d];
    if (!(dot > 0 && dot * dot >= (1 - 1e-12) * mm * pp)) extrapolate = PETSC_FALSE;
  }
  *moved = PETSC_FALSE;
  if (s->num.predict == PREDICT_NONE || (grip_step == 0 && !(by_load && extrapolate))) PetscFunctionReturn(0);
  *moved = PETSC_TRUE;
  if (s->bodies.sphere_radius > 0 && !extrapolate) PetscCall(SphereWeights(fab, fab->load.travel + grip_step));
  PetscCall(PetscLogEventBegin(EV_Predict, 0, 0, 0, 0));
  PetscCall(VecGetArray(fab->state.X, &x));
  if (fab->state.Xold) PetscCall(VecGetArray(fab->state.Xold, &xold));
  if (extrapolate) {
    PetscCall(VecGetArrayRead(fab->state.Xconv, &a));
    PetscCall(VecGetArrayRead(fab->state.Xconv_prev, &b));
  }
  {
    const PetscReal ratio = !extrapolate ? 0.0 : by_load ? 1.0 : grip_step / fab->load.travel_step_prev; /* equal load steps */
    for (PetscInt k = 0; k < fab->grid.nloc; k++) {
      if (fab->grid.kind[k] != POINT_FREE) continue;
      for (int d = 0; d < 3; d++) {
        const PetscReal du = extrapolate ? ratio * (a[3 * k + d] - b[3 * k + d])
                                         : (s->load.waypoints || s->bodies.sphere_radius > 0
                                                ? fab->grid.predict_w[k] * grip_move[d]
                                                : fab->grid.predict_w[k] * grip_step * fab->grid.pull_dir[d]);
        x[3 * k + d] += du;
        if (xold) xold[3 * k + d] += du;
      }
    }
  }
  if (extrapolate) {
    PetscCall(VecRestoreArrayRead(fab->state.Xconv, &a));
    PetscCall(VecRestoreArrayRead(fab->state.Xconv_prev, &b));
  }
  if (xold) PetscCall(VecRestoreArray(fab->state.Xold, &xold));
  PetscCall(VecRestoreArray(fab->state.X, &x));
  PetscCall(PetscLogEventEnd(EV_Predict, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}
