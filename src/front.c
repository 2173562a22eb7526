/* front.c - which crossing points a te step computes: rank propagation and sleeping
 * (MODEL.md 9; sleeping goes beyond the paper).
 *
 * Rank propagation. The force on a point depends on points at most 2 steps away on the
 * grid graph (bending reaches two points along a yarn, shear the diagonal neighbours), so
 * a disturbance spreads by at most 2 per te step. With d the graph distance to the points
 * a load change disturbs (grips, point-load point), only points with d <= 2k can move in
 * the k-th te step after it. The te step computes the global bounding box of those points;
 * every rank takes its part of that box, so the computed set does not depend on the
 * decomposition. A rank whose patch misses the box skips its kernel. Once 2k reaches the
 * largest distance (a max-reduction made once), the front has covered everything and
 * costs nothing more.
 *
 * Sleeping. A point is awake if its residual force or speed exceeds -sleep_tol (relative,
 * like -balance_tol). Each te step computes the bounding box of the awake points grown by
 * the stencil reach (2), so a point next to an awake one is woken. The awake box rides on
 * the balance test's max-reduction: no extra message. The crossings a balance check per
 * crossing finds unbalanced (their forces small beside the largest tension, so they fell
 * asleep) stay awake, with the stencil's reach, until the relaxation round ends.
 */
#include "front.h"
#include "comm.h"
#include "predict.h"

/* box = a ∩ b */
static void BoxIntersect(PetscInt a[4], const PetscInt b[4])
{
  a[0] = PetscMax(a[0], b[0]);
  a[1] = PetscMin(a[1], b[1]);
  a[2] = PetscMax(a[2], b[2]);
  a[3] = PetscMin(a[3], b[3]);
}

static PetscBool BoxEmpty(const PetscInt b[4])
{
  return (b[1] <= b[0] || b[3] <= b[2]) ? PETSC_TRUE : PETSC_FALSE;
}

PetscErrorCode FrontSetUp(Fabric fab)
{
  const Patch *p = &fab->grid.patch;
  PetscReal   *dist, dmax = 0;
  PetscInt     n;
  char        *sources;

  PetscFunctionBeginUser;
  /* the grips' bounding box: a moving jaw keeps its neighbours awake */
  {
    PetscReal b[4] = {-PETSC_MAX_INT, -PETSC_MAX_INT, -PETSC_MAX_INT, -PETSC_MAX_INT};
    for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
      for (PetscInt i = p->xs; i < p->xs + p->xm; i++)
        if (fab->grid.kind[(j - p->ys) * p->xm + (i - p->xs)] == POINT_GRIP &&
            p->exists[(j - p->gys) * p->gxm + (i - p->gxs)]) {
          b[0] = PetscMax(b[0], -i), b[1] = PetscMax(b[1], i + 1), b[2] = PetscMax(b[2], -j),
          b[3] = PetscMax(b[3], j + 1);
        }
    PetscCall(GlobalMax(fab->comm, b, 4));
    fab->front.grip_box[0] = (PetscInt) -b[0], fab->front.grip_box[1] = (PetscInt) b[1],
    fab->front.grip_box[2] = (PetscInt) -b[2], fab->front.grip_box[3] = (PetscInt) b[3];
  }
  if (!fab->s.num.front) PetscFunctionReturn(0);
  PetscCall(PetscMalloc2(fab->grid.nloc, &dist, fab->grid.nloc, &sources));
  {
    const Scene *s      = &fab->s;
    const int    pulled = s->load.elongation > 0 || s->load.waypoints > 0,
              loaded    = s->load.point_load[0] != 0 || s->load.point_load[1] != 0 || s->load.point_load[2] != 0;
    for (PetscInt k = 0; k < fab->grid.nloc; k++)
      sources[k] = (char) ((pulled && fab->grid.kind[k] == POINT_GRIP) || (loaded && k == fab->grid.load_index));
  }
  PetscCall(GraphDistance(fab->comm, fab->grid.da, &fab->grid.patch, sources, dist));
  for (PetscInt k = 0; k < fab->grid.nloc; k++)
    if (dist[k] < DIST_INF) dmax = PetscMax(dmax, dist[k]);
  PetscCall(GlobalMax(fab->comm, &dmax, 1));
  fab->front.front_dmax = (PetscInt) dmax;
  /* boxes[R] = global bounding box of {d <= R}, as maxima of (-imin, imax+1, -jmin, jmax+1) */
  n = fab->front.front_dmax + 1;
  {
    PetscReal *b;
    PetscCall(PetscMalloc1(4 * n, &b));
    for (PetscInt r = 0; r < n; r++) b[4 * r] = b[4 * r + 1] = b[4 * r + 2] = b[4 * r + 3] = -PETSC_MAX_INT;
    for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
      for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
        const PetscReal d = dist[(j - p->ys) * p->xm + (i - p->xs)];
        if (d >= DIST_INF) continue;
        PetscReal *q = b + 4 * (PetscInt) d;
        q[0] = PetscMax(q[0], -i), q[1] = PetscMax(q[1], i + 1), q[2] = PetscMax(q[2], -j),
        q[3] = PetscMax(q[3], j + 1);
      }
    for (PetscInt r = 1; r < n; r++) /* prefix over R */
      for (int c = 0; c < 4; c++) b[4 * r + c] = PetscMax(b[4 * r + c], b[4 * (r - 1) + c]);
    PetscCall(GlobalMax(fab->comm, b, 4 * n));
    PetscCall(PetscMalloc1(4 * n, &fab->front.front_box));
    for (PetscInt r = 0; r < n; r++) {
      fab->front.front_box[4 * r]     = (PetscInt) -b[4 * r];
      fab->front.front_box[4 * r + 1] = (PetscInt) b[4 * r + 1];
      fab->front.front_box[4 * r + 2] = (PetscInt) -b[4 * r + 2];
      fab->front.front_box[4 * r + 3] = (PetscInt) b[4 * r + 3];
    }
    PetscCall(PetscFree(b));
  }
  PetscCall(PetscFree2(dist, sources));
  PetscFunctionReturn(0);
}

/* A load changed: the front starts again from the disturbed points. A prediction that moved the
   points moves every reachable one, gravity disturbs every point at the first step (and at every
   step of the drape, whose gravity grows with them), and a load step that ended unbalanced left
   points moving anywhere: then it is covered (a prediction with nothing to follow, -predict linear
   under a point load, moves none). */
void FrontLoadChange(Fabric fab, PetscBool predicted)
{
  const Scene    *s       = &fab->s;
  const PetscInt  k       = fab->load.load_step;
  const int       gravity = (s->terms.gravity[0] != 0 || s->terms.gravity[1] != 0 || s->terms.gravity[2] != 0) &&
                      (k == 1 || s->test == TEST_DRAPE);
  /* the load step before ended unbalanced (the static path's coarse fabrics keep no rows) */
  const PetscBool moving  = s->num.solver != SOLVER_STATIC && k > 1 && !fab->stats.curve[k - 2].balanced;
  fab->front.front_step    = 0;
  fab->front.front_covered = (!s->num.front || predicted || moving || gravity) ? PETSC_TRUE : PETSC_FALSE;
  if (s->num.sleep_tol > 0) {
    if (predicted || moving || k == 1 || gravity || !fab->front.front_box)
      FrontWakeAll(fab);
    else { /* wake the disturbed points too */
      const PetscInt *src     = fab->front.front_box;
      fab->front.awake_box[0] = PetscMin(fab->front.awake_box[0], src[0]),
      fab->front.awake_box[1] = PetscMax(fab->front.awake_box[1], src[1]);
      fab->front.awake_box[2] = PetscMin(fab->front.awake_box[2], src[2]),
      fab->front.awake_box[3] = PetscMax(fab->front.awake_box[3], src[3]);
    }
  }
}

/* sleeping: every point awake */
void FrontWakeAll(Fabric fab)
{
  fab->front.awake_box[0] = 0, fab->front.awake_box[1] = fab->s.spec.nx, fab->front.awake_box[2] = 0,
  fab->front.awake_box[3] = fab->s.spec.ny;
}

void FrontKeepAwake(Fabric fab, const PetscInt box[4])
{
  PetscInt *k = fab->front.keep_box;
  if (BoxEmpty(box)) return;
  if (BoxEmpty(k)) k[0] = box[0], k[1] = box[1], k[2] = box[2], k[3] = box[3];
  else k[0] = PetscMin(k[0], box[0]), k[1] = PetscMax(k[1], box[1]), k[2] = PetscMin(k[2], box[2]), k[3] = PetscMax(k[3], box[3]);
}

void FrontKeepReset(Fabric fab)
{
  fab->front.keep_box[0] = fab->front.keep_box[1] = fab->front.keep_box[2] = fab->front.keep_box[3] = 0;
}

/* The box of points the next te step computes: global (same on every rank), and the
   owned part of it. Returns the number of crossings it updates: those that exist when it is
   the whole grid (a disc or bias specimen has holes), its area otherwise. */
PetscInt64 FrontStepBox(Fabric fab, PetscInt global[4], PetscInt local[4])
{
  const Scene *s        = &fab->s;
  const Patch *p        = &fab->grid.patch;
  PetscInt     owned[4] = {p->xs, p->xs + p->xm, p->ys, p->ys + p->ym};

  global[0] = 0, global[1] = s->spec.nx, global[2] = 0, global[3] = s->spec.ny;
  fab->front.front_step++;
  if (!fab->front.front_covered) {
    const PetscInt R = 2 * fab->front.front_step;
    if (R >= fab->front.front_dmax)
      fab->front.front_covered = PETSC_TRUE;
    else
      BoxIntersect(global, fab->front.front_box + 4 * R);
  }
  if (s->num.sleep_tol > 0) {
    PetscInt grown[4] = {fab->front.awake_box[0] - 2, fab->front.awake_box[1] + 2, fab->front.awake_box[2] - 2,
                         fab->front.awake_box[3] + 2};
    if (fab->load.ramp_done < fab->load.ramp_steps) { /* the jaw is moving: its neighbours are awake */
      grown[0] = PetscMin(grown[0], fab->front.grip_box[0] - 2),
      grown[1] = PetscMax(grown[1], fab->front.grip_box[1] + 2);
      grown[2] = PetscMin(grown[2], fab->front.grip_box[2] - 2),
      grown[3] = PetscMax(grown[3], fab->front.grip_box[3] + 2);
    }
    if (!BoxEmpty(fab->front.keep_box)) {
      const PetscInt *k = fab->front.keep_box;
      grown[0] = PetscMin(grown[0], k[0] - 2), grown[1] = PetscMax(grown[1], k[1] + 2);
      grown[2] = PetscMin(grown[2], k[2] - 2), grown[3] = PetscMax(grown[3], k[3] + 2);
    }
    BoxIntersect(global, grown);
  }
  if (BoxEmpty(global)) global[0] = global[1] = global[2] = global[3] = 0;
  local[0] = global[0], local[1] = global[1], local[2] = global[2], local[3] = global[3];
  BoxIntersect(local, owned);
  if (BoxEmpty(local)) local[0] = local[1] = local[2] = local[3] = 0;
  if (global[0] == 0 && global[1] == s->spec.nx && global[2] == 0 && global[3] == s->spec.ny) return fab->grid.points;
  return (PetscInt64) (global[1] - global[0]) * (global[3] - global[2]);
}
