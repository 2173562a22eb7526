/* load.c - the load program (MODEL.md 6): how far the grips or the sphere travel at each load
 * step, along which path, at what test time; and putting the grips there.
 */
#include "load.h"

/* The grip's displacement at length a along its path (-grip_path_mm): piecewise linear
   through the waypoints from 0,0,0, held at the last one beyond its end. */
void PathPoint(const LoadProgram *lp, PetscReal a, PetscReal u[3])
{
  PetscInt k = 0;
  while (k < lp->waypoints - 1 && a > lp->path_at[k]) k++;
  const PetscReal a0 = k ? lp->path_at[k - 1] : 0.0, t = PetscMin(1.0, PetscMax(0.0, (a - a0) / (lp->path_at[k] - a0)));
  for (int d = 0; d < 3; d++) {
    const PetscReal p0 = k ? lp->waypoint[k - 1][d] : 0.0;
    u[d]               = p0 + t * (lp->waypoint[k][d] - p0);
  }
}

/* Total travel of what the load program moves, m: the strip's jaw (the length of its path) or
   the punch. */
PetscReal LoadTravel(const Scene *s)
{
  if (s->test == TEST_PUSHING) return s->bodies.sphere_travel;
  return s->load.waypoints ? s->load.path_at[s->load.waypoints - 1] : s->load.elongation * s->spec.gauge;
}

/* The grips' move from length `from` to length `to` along their path: along the pull without a
   path (the straight pull, computed as it always was). */
void GripPathMove(const Scene *s, const PetscReal pull_dir[3], PetscReal from, PetscReal to, PetscReal move[3])
{
  if (!s->load.waypoints) {
    const PetscReal delta = to - from;
    for (int d = 0; d < 3; d++) move[d] = delta * pull_dir[d];
    return;
  }
  PetscReal u0[3], u1[3];
  PathPoint(&s->load, from, u0);
  PathPoint(&s->load, to, u1);
  for (int d = 0; d < 3; d++) move[d] = u1[d] - u0[d];
}

/* curve.csv's elongation at length disp along the grip's path: its displacement along the
   pull / gauge */
PetscReal GripElongation(const Scene *s, const PetscReal pull_dir[3], PetscReal disp)
{
  PetscReal u[3];
  if (!s->load.waypoints) return disp / s->spec.gauge;
  PathPoint(&s->load, disp, u);
  return (u[0] * pull_dir[0] + u[1] * pull_dir[1] + u[2] * pull_dir[2]) / s->spec.gauge;
}

/* Time of the current load step (time_s, frame times), s: the travel at the test speed; for
   the tests that move nothing (square net, drape), the load step number, so that frames have
   distinct times. */
PetscReal TestTime(const Scene *s, const LoadState *ls) { return TestTimeAt(s, ls, ls->travel); }

/* ... with the grips or the sphere at travel (m) */
PetscReal TestTimeAt(const Scene *s, const LoadState *ls, PetscReal travel)
{
  return LoadTravel(s) > 0 ? travel / s->load.speed : (PetscReal) ls->load_step;
}

/* Put the grips at length disp along their path (the pull, or -grip_path_mm). A jump
   (shift_history) also shifts the paper integrator's x(n-1), so the grips do not move back;
   a ramp sets the position at each te step and leaves the history to the integrator. */
PetscErrorCode PlaceGrips(Fabric fab, PetscReal disp, PetscBool shift_history)
{
  PetscReal    move[3];
  PetscScalar *x, *xold = NULL;

  PetscFunctionBeginUser;
  GripPathMove(&fab->s, fab->grid.pull_dir, fab->load.travel_now, disp, move);
  PetscCall(VecGetArray(fab->state.X, &x));
  if (fab->state.Xold && shift_history) PetscCall(VecGetArray(fab->state.Xold, &xold));
  for (PetscInt q = 0; q < fab->grid.nloc; q++) {
    if (fab->grid.kind[q] != POINT_GRIP) continue;
    for (int d = 0; d < 3; d++) {
      x[3 * q + d] += move[d];
      if (xold) xold[3 * q + d] += move[d];
    }
  }
  if (xold) PetscCall(VecRestoreArray(fab->state.Xold, &xold));
  PetscCall(VecRestoreArray(fab->state.X, &x));
  fab->load.travel_now = disp;
  PetscFunctionReturn(0);
}

/* One te step of the jaw's cosine ramp to this load step's position (ApplyLoadStep starts it). */
PetscErrorCode RampGrips(Fabric fab)
{
  LoadState *ls = &fab->load;

  PetscFunctionBeginUser;
  if (ls->ramp_done >= ls->ramp_steps) PetscFunctionReturn(0);
  ls->ramp_done++;
  PetscCall(PlaceGrips(fab,
                       ls->travel_from + (ls->travel - ls->travel_from) * 0.5 *
                                             (1.0 - PetscCosReal(PETSC_PI * ls->ramp_done / ls->ramp_steps)),
                       PETSC_FALSE));
  PetscFunctionReturn(0);
}
