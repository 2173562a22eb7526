/* measure.c - what a load step reports (curve.csv): the reaction on the grips, the sphere and
 * the supports, the load point's travel, the bias specimen's centre shear, the drape outline.
 * Sums over points: reported, never fed back into the positions.
 */
#include "measure.h"
#include "comm.h"
#include "integrate.h"

#include <math.h>

/* Reaction on the moving jaw: minus the sum of the internal forces on the grip points,
   projected on the pull direction (positive in tension). An exact sum (GlobalPointSums): the same
   on any number of ranks and any split, as the break detection that reads it must be. */
static PetscErrorCode GripReaction(MPI_Comm comm, const FabricGrid *g, const PetscScalar *f, PetscReal *force)
{
  PetscReal *t;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(g->nloc, &t));
  for (PetscInt k = 0; k < g->nloc; k++)
    t[k] = g->kind[k] == POINT_GRIP
             ? -(f[3 * k] * g->pull_dir[0] + f[3 * k + 1] * g->pull_dir[1] + f[3 * k + 2] * g->pull_dir[2])
             : 0.0;
  PetscCall(GlobalPointSums(comm, 1, t, g->nloc, force));
  PetscCall(PetscFree(t));
  PetscFunctionReturn(0);
}

/* The contact force of the body of this kind on each owned crossing, t[3 k + d], at the positions x
   ComputeForces has just used: the terms of the bodies' exact reaction sums. Friction is computed on
   a copy of the anchors (measuring moves none). All zero without such a body. */
static PetscErrorCode BodyContactTerms(Fabric fab, BodyKind kind, const PetscScalar *x, PetscReal *t)
{
  const FabricGrid *g = &fab->grid;
  const Body       *b = NULL;
  PetscReal         c[3], *anchor = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscArrayzero(t, 3 * g->nloc));
  for (PetscInt q = 0; q < fab->bodies.n; q++)
    if (fab->bodies.body[q].kind == kind) b = &fab->bodies.body[q];
  if (!b) PetscFunctionReturn(0);
  BodyPosition(b, fab->load.travel_now, c);
  if (fab->state.anchor[kind]) {
    const PetscScalar *a;
    PetscCall(PetscMalloc1(3 * g->nloc, &anchor));
    PetscCall(VecGetArrayRead(fab->state.anchor[kind], &a));
    PetscCall(PetscArraycpy(anchor, a, 3 * g->nloc));
    PetscCall(VecRestoreArrayRead(fab->state.anchor[kind], &a));
  }
  BodyContact(b, c, g->nloc, x, g->inv_m, anchor, t);
  PetscCall(PetscFree(anchor));
  PetscFunctionReturn(0);
}

/* Pushing: the reaction on the sphere is minus the sum of the contact forces on the fabric;
   force_N is its component against the travel (positive while the fabric resists). An exact sum
   (GlobalPointSums) of each crossing's contact force along the path: the same on any number of ranks and
   any split, as the break detection that reads it (a ball burst) must be. */
static PetscErrorCode SphereReaction(Fabric fab, const PetscScalar *x, const PetscReal dir[3], PetscReal travel,
                                     CurveRow *row)
{
  const PetscInt n = fab->grid.nloc;
  PetscReal     *t;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(3 * n, &t));
  PetscCall(BodyContactTerms(fab, BODY_SPHERE, x, t));
  for (PetscInt k = 0; k < n; k++) t[k] = t[3 * k] * dir[0] + t[3 * k + 1] * dir[1] + t[3 * k + 2] * dir[2];
  PetscCall(GlobalPointSums(fab->comm, 1, t, n, &row->force));
  PetscCall(PetscFree(t));
  row->travel = travel;
  PetscFunctionReturn(0);
}

/* Supports (a plane or a pedestal): the force of the fabric on each body, minus the sum of
   the contact forces on the fabric (recomputed at GripReaction's state, BodyContactTerms);
   on the clamps and the grips, the internal forces on the crossings they hold plus their weight
   (they hold it too); and the specimen's weight. At rest the free crossings balance, and the
   internal forces sum to zero over the fabric, so plane + pedestal + clamp = weight, up to
   the residual forces of the balance test. Sums over points: reported, never fed back; exact
   (GlobalPointSums), the same on any number of ranks and any split, as curve.csv must be. */
static PetscErrorCode SupportReactions(Fabric fab, const PetscScalar *x, const PetscScalar *f, CurveRow *row)
{
  const FabricGrid *g = &fab->grid;
  const Patch      *p = &g->patch;
  const PetscReal  *gravity = fab->load.gravity_now;
  PetscReal         acc[12], *t, *b;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(3 * g->nloc, &b, 3 * g->nloc, &t));
  for (int q = 0; q < 2; q++) { /* the plane's and the pedestal's: minus their contact forces on the crossings */
    PetscCall(BodyContactTerms(fab, q == 0 ? BODY_PLANE : BODY_PEDESTAL, x, b));
    for (PetscInt k = 0; k < g->nloc; k++)
      for (int d = 0; d < 3; d++) t[d * g->nloc + k] = -b[3 * k + d];
    PetscCall(GlobalPointSums(fab->comm, 3, t, g->nloc, acc + 3 * q));
  }
  PetscCall(PetscFree2(b, t));
  PetscCall(PetscCalloc1((size_t) 6 * g->nloc, &t)); /* held crossings' forces and every crossing's weight: exact sums (size_t:
                                                        6 nloc passes 2^31 above 358 M points a rank) */
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
    for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
      const PetscInt k = (j - p->ys) * p->xm + (i - p->xs);
      if (!p->exists[(j - p->gys) * p->gxm + (i - p->gxs)]) continue;
      for (int d = 0; d < 3; d++) {
        const PetscReal w = g->mass[k] * gravity[d];
        if (g->kind[k] == POINT_CLAMPED || g->kind[k] == POINT_GRIP) t[(size_t) d * g->nloc + k] = f[3 * k + d] + w;
        t[(size_t) (3 + d) * g->nloc + k] = w;
      }
    }
  PetscCall(GlobalPointSums(fab->comm, 3, t, g->nloc, acc + 6));
  PetscCall(GlobalPointSums(fab->comm, 3, t + (size_t) 3 * g->nloc, g->nloc, acc + 9));
  PetscCall(PetscFree(t));
  for (int d = 0; d < 3; d++) {
    row->plane_force[d]    = acc[d];
    row->pedestal_force[d] = acc[3 + d];
    row->clamp_force[d]    = acc[6 + d];
    row->weight[d]         = acc[9 + d];
  }
  PetscFunctionReturn(0);
}

/* Bias extension: the mean shear angle of the central zone, the crossings within min(W, D)/4
   of the specimen's centre along and across it, D = gauge - width: a square inside the
   pure-shear zone C, the diamond |along| + |across| < D/2 cut by the long edges (for
   length/width 2 it touches the diamond at the middle of its sides). The angle
   at a crossing is asin(cos(angle(tw, tf))) (CrossingShear), as the shear_angle_deg field of
   fabric.h5 (FabricCreate checks that the zone holds a crossing).
   Xl: halo-exchanged by GripReaction. An exact sum over crossings: reported, never fed back. */
static PetscErrorCode CenterShear(MPI_Comm comm, const Scene *s, const Patch *p, const PetscScalar *xl, CurveRow *row)
{
  const PetscInt n = p->xm * p->ym;
  PetscReal      acc[2], *t;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(2 * n, &t)); /* each crossing's angle and 1 if it counts: exact sums */
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
    for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
      const PetscInt k = (j - p->ys) * p->xm + (i - p->xs);
      PetscReal      c, tmin;
      if (!BiasCentreZone(s, i, j)) continue;
      if (!CrossingShear(p, xl, i, j, &c, &tmin)) continue;
      t[k]     = PetscAsinReal(c) * 180.0 / PETSC_PI;
      t[n + k] = 1;
    }
  PetscCall(GlobalPointSums(comm, 2, t, n, acc));
  PetscCall(PetscFree(t));
  row->center_shear = acc[1] > 0 ? acc[0] / acc[1] : 0.0;
  PetscFunctionReturn(0);
}

/* Cusick drape: the shadow of the draped specimen seen from above. The fabric's yarn
   segments are projected on the horizontal plane; along each of DRAPE_RAYS rays from the
   centre the outline r(theta) is the farthest point where the ray crosses a projected
   segment (a max-reduction: exact on any number of ranks). The outline moves continuously
   with the crossings (a yarn is a polyline: where a segment leaves a ray, its neighbour takes
   over at the shared crossing), unlike the largest radius of the crossings in angular bins,
   which jumped by 0.2 % of DC when a crossing moved 60 nm across a bin's edge.
   A_shadow = sum 0.5 r^2 dtheta; DC = (A_shadow - A_disc)/(A_specimen - A_disc), with
   A_specimen the same sum on the flat specimen at rest and A_disc the support disc's (the
   pedestal's, else the clamp ring's).
   Folds: the lobes of the outline taken as its largest radius over each 5-degree sector,
   counted as the local maxima of this periodic sector radius whose prominence exceeds 15 % of
   the outline's range (max - min) and one yarn spacing: the grid's own wobble is below (the
   flat specimen's staircase edge), a lobe of the draped specimen far above (checked against
   the top view, README); the flat specimen has no fold. */
#define DRAPE_RAYS       1440
#define DRAPE_SECTOR     20 /* rays per 5-degree sector */
#define DRAPE_PROMINENCE 0.15

/* the farthest crossing of segment a-b (projected, relative to the centre) with each ray it
   spans, into r */
static void ShadowSegment(const PetscReal a[2], const PetscReal b[2], PetscReal r[DRAPE_RAYS])
{
  const PetscReal h = 2 * PETSC_PI / DRAPE_RAYS, dx = b[0] - a[0], dy = b[1] - a[1], axd = a[0] * dy - a[1] * dx;
  PetscReal       ta = atan2(a[1], a[0]), span = atan2(b[1], b[0]) - ta;

  if (span > PETSC_PI) span -= 2 * PETSC_PI;
  if (span < -PETSC_PI) span += 2 * PETSC_PI;
  if (span < 0) ta += span, span = -span; /* [ta, ta + span]: the arc the segment spans */
  for (PetscInt q = (PetscInt) PetscCeilReal(ta / h - 0.5); (q + 0.5) * h <= ta + span; q++) {
    const PetscReal th = (q + 0.5) * h, ux = PetscCosReal(th), uy = PetscSinReal(th), uxd = ux * dy - uy * dx;
    const int       b_ = (int) (((q % DRAPE_RAYS) + DRAPE_RAYS) % DRAPE_RAYS);
    if (uxd == 0) continue;         /* the ray runs along the segment: its ends are on the neighbours' rays */
    const PetscReal rr = axd / uxd; /* r u = a + t (b - a) */
    if (rr > r[b_]) r[b_] = rr;
  }
}

/* the outline r(theta) of the positions X seen from above (DRAPE_RAYS rays), the area it
   encloses and the largest drop of a crossing; within > 0: of the crossings that far from the centre at most */
static PetscErrorCode Outline(MPI_Comm comm, const FabricGrid *g, Vec X, PetscReal within, PetscReal r[DRAPE_RAYS],
                              PetscReal *area, PetscReal *drop)
{
  const Patch       *p = &g->patch;
  const PetscScalar *x;
  Vec                Xl;

  PetscFunctionBeginUser;
  *area = *drop = 0;
  for (int q = 0; q < DRAPE_RAYS; q++) r[q] = 0;
  PetscCall(DMGetLocalVector(g->da, &Xl));
  PetscCall(HaloExchange(g->da, X, Xl));
  PetscCall(VecGetArrayRead(Xl, &x));
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
    for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
      const PetscInt li = i - p->gxs, lj = j - p->gys, k = lj * p->gxm + li;
      if (!p->exists[k]) continue;
      const PetscReal a[2] = {x[3 * k] - g->centre[0], x[3 * k + 1] - g->centre[1]};
      if (within > 0 && a[0] * a[0] + a[1] * a[1] > within * within * (1 + 1e-12)) continue;
      *drop                = PetscMax(*drop, -x[3 * k + 2]);
      for (int dir = 0; dir < 2; dir++) { /* the segments to the +x and +y neighbours */
        const PetscInt n = dir == 0 ? k + 1 : k + p->gxm;
        if ((dir == 0 ? li + 1 >= p->gxm : lj + 1 >= p->gym) || !p->exists[n]) continue;
        const PetscReal b[2] = {x[3 * n] - g->centre[0], x[3 * n + 1] - g->centre[1]};
        if (within > 0 && b[0] * b[0] + b[1] * b[1] > within * within * (1 + 1e-12)) continue;
        ShadowSegment(a, b, r);
      }
    }
  PetscCall(VecRestoreArrayRead(Xl, &x));
  PetscCall(DMRestoreLocalVector(g->da, &Xl));
  PetscCall(GlobalMax(comm, r, DRAPE_RAYS));
  PetscCall(GlobalMax(comm, drop, 1));
  for (int q = 0; q < DRAPE_RAYS; q++) *area += 0.5 * r[q] * r[q] * 2 * PETSC_PI / DRAPE_RAYS;
  PetscFunctionReturn(0);
}

PetscErrorCode DrapeSetUp(Fabric fab)
{
  const Scene *s = &fab->s;
  PetscReal    r[DRAPE_RAYS], drop, a_disc = PETSC_PI * PetscSqr(DrapeSupportRadius(s));

  PetscFunctionBeginUser;
  PetscCall(Outline(fab->comm, &fab->grid, fab->grid.X0, 0, r, &fab->meas.drape_flat_area, &drop));
  PetscCheck(a_disc < fab->meas.drape_flat_area, fab->comm, PETSC_ERR_USER_INPUT,
             "%s %g mm: the support covers the specimen's flat outline on this grid (the area of a %g mm disc; the grid's "
             "edge lies inside the nominal %g mm disc): nothing hangs over it, and the drape coefficient (A_shadow - "
             "A_disc)/(A_flat - A_disc) has no meaning; use a smaller support or a denser grid",
             DrapeSupportRadius(s) > s->bodies.pedestal_radius ? "-clamp_ring_mm: the support's outer diameter"
                                                               : "-pedestal_diameter_mm",
             2e3 * (double) DrapeSupportRadius(s), 2e3 * (double) PetscSqrtReal(fab->meas.drape_flat_area / PETSC_PI),
             2e3 * (double) s->spec.disc_radius);
  { /* the support as the grid has it: the outline of its crossings within the support's radius. On a coarse grid
       it falls well inside the nominal disc, the skirt hangs inside A_disc, and the drape coefficient came out below
       0 (-30 % at 0.2 threads/cm) */
    PetscReal held;
    PetscCall(Outline(fab->comm, &fab->grid, fab->grid.X0, DrapeSupportRadius(s), r, &held, &drop));
    PetscCall(PetscInfo(NULL, "drape: the support's crossings span %.0f mm^2, %.1f %% of the nominal disc's %.0f mm^2\n",
                        1e6 * (double) held, 100 * (double) (held / a_disc), 1e6 * (double) a_disc));
    PetscCheck(held >= 0.75 * a_disc, fab->comm, PETSC_ERR_USER_INPUT,
               "-ends_per_cm %g -picks_per_cm %g: too coarse a grid for the drape's %g mm support: its crossings there "
               "span %.0f mm^2, %.0f %% of the nominal disc's %.0f mm^2 (A_disc of the drape coefficient), so the skirt "
               "can hang inside that disc and the drape coefficient has no meaning (it can come out below 0); use a "
               "denser grid or a wider support (at least 75 %%)",
               (double) (s->spec.ends_per_m / 100), (double) (s->spec.picks_per_m / 100), 2e3 * (double) DrapeSupportRadius(s),
               1e6 * (double) held, 100 * (double) (held / a_disc), 1e6 * (double) a_disc);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode DrapeOutline(Fabric fab, CurveRow *row)
{
  const Scene *s = &fab->s;
  PetscReal    r[DRAPE_RAYS], area, a_disc, drop;
  PetscInt     folds = 0;

  PetscFunctionBeginUser;
  /* the specimen's own area measured the same way, once, on the flat specimen at rest: the
     outline of the grid's edge lies inside the nominal circle, so the flat specimen gives
     DC = 100 % */
  if (fab->meas.drape_flat_area <= 0)
    PetscCall(Outline(fab->comm, &fab->grid, fab->grid.X0, 0, r, &fab->meas.drape_flat_area, &drop));
  PetscCall(Outline(fab->comm, &fab->grid, fab->state.X, 0, r, &area, &drop));
  a_disc = PETSC_PI * PetscSqr(DrapeSupportRadius(s));
  fab->meas.drape_pct =
      100.0 * ((area - a_disc) / (fab->meas.drape_flat_area - a_disc)); /* the flat specimen: 100 * 1 exactly */
  { /* folds: the outline as its largest radius over each 5-degree sector (DRAPE_SECTOR rays) */
    PetscReal sec[DRAPE_RAYS / DRAPE_SECTOR], lo = PETSC_MAX_REAL, hi = 0;
    const int S = DRAPE_RAYS / DRAPE_SECTOR;
    for (int q = 0; q < S; q++) {
      sec[q] = 0;
      for (int b = q * DRAPE_SECTOR; b < (q + 1) * DRAPE_SECTOR; b++) sec[q] = PetscMax(sec[q], r[b]);
      lo = PetscMin(lo, sec[q]), hi = PetscMax(hi, sec[q]);
    }
    /* a fold: a local maximum of the sector radius whose prominence (its height above the
       higher of the lowest radii on either side before a higher radius) exceeds
       DRAPE_PROMINENCE of the outline's range and one yarn spacing */
    for (int q = 0; q < S; q++) {
      const PetscReal v    = sec[q];
      PetscReal       lo_l = v, lo_r = v;
      if (!(v > sec[(q + S - 1) % S] && v >= sec[(q + 1) % S])) continue;
      for (int t = 1; t < S && sec[(q - t + S) % S] <= v; t++) lo_l = PetscMin(lo_l, sec[(q - t + S) % S]);
      for (int t = 1; t < S && sec[(q + t) % S] <= v; t++) lo_r = PetscMin(lo_r, sec[(q + t) % S]);
      if (v - PetscMax(lo_l, lo_r) >
          PetscMax(DRAPE_PROMINENCE * (hi - lo), PetscMax(1.0 / s->spec.picks_per_m, 1.0 / s->spec.ends_per_m)))
        folds++;
    }
  }
  fab->meas.folds = folds;
  row->travel     = drop; /* curve.csv travel_mm: the largest drop of a crossing */
  PetscFunctionReturn(0);
}

/* Square net: the applied point load and its crossing's displacement along it. One rank owns
   the crossing, the others add zeros: the sum is exact. */
static PetscErrorCode LoadPointTravel(MPI_Comm comm, const FabricGrid *g, const PetscScalar *x, const PetscScalar *x0,
                                      const PetscReal P[3], PetscReal load_factor, CurveRow *row)
{
  const PetscReal Pn     = PetscSqrtReal(P[0] * P[0] + P[1] * P[1] + P[2] * P[2]);
  PetscReal       travel = 0;

  PetscFunctionBeginUser;
  if (g->load_index >= 0 && Pn > 0)
    for (int d = 0; d < 3; d++) travel += (x[3 * g->load_index + d] - x0[3 * g->load_index + d]) * P[d] / Pn;
  PetscCall(GlobalSum(comm, &travel, 1));
  row->travel = travel;
  row->force  = load_factor * Pn;
  PetscFunctionReturn(0);
}

/* The balanced state's measurements for curve.csv: the grips' reaction (its force evaluation
   also gives the bodies' contact sums and the halo the centre shear reads), then what the test
   reports. */
PetscErrorCode MeasureLoadStep(Fabric fab, CurveRow *row)
{
  const Scene       *s = &fab->s;
  const PetscScalar *f, *x, *x0, *xl;
  PetscReal          tension_max;

  PetscFunctionBeginUser;
  PetscCall(ComputeForces(fab, NULL, &tension_max));
  PetscCall(VecGetArrayRead(fab->state.F, &f));
  PetscCall(VecGetArrayRead(fab->state.X, &x));
  PetscCall(VecGetArrayRead(fab->grid.X0, &x0));
  PetscCall(VecGetArrayRead(fab->state.Xl, &xl));
  PetscCall(GripReaction(fab->comm, &fab->grid, f, &row->force));
  if (s->test == TEST_SQUARE)
    PetscCall(LoadPointTravel(fab->comm, &fab->grid, x, x0, s->load.point_load, fab->load.load_factor, row));
  if (s->test == TEST_PUSHING)
    PetscCall(SphereReaction(fab, x, s->bodies.sphere_dir, LoadTravelReached(&fab->load), row));
  if (s->test == TEST_BIAS) PetscCall(CenterShear(fab->comm, s, &fab->grid.patch, xl, row));
  if (s->bodies.plane || s->bodies.pedestal_radius > 0)
    PetscCall(SupportReactions(fab, x, f, row));
  PetscCall(VecRestoreArrayRead(fab->state.Xl, &xl));
  PetscCall(VecRestoreArrayRead(fab->grid.X0, &x0));
  PetscCall(VecRestoreArrayRead(fab->state.X, &x));
  PetscCall(VecRestoreArrayRead(fab->state.F, &f));
  if (s->test == TEST_DRAPE) PetscCall(DrapeOutline(fab, row));
  PetscFunctionReturn(0);
}

/* A curve row as CURVE_COLS numbers (checkpoints): load step, time, elongation, force, inner steps,
   residual, balanced, travel, centre shear, plane force (3), pedestal force (3), clamp force (3), weight (3). */
void CurveRowPack(const CurveRow *r, PetscReal a[CURVE_COLS])
{
  a[0] = (PetscReal) r->load_step, a[1] = r->time, a[2] = r->elongation, a[3] = r->force;
  a[4] = (PetscReal) r->inner_steps, a[5] = r->residual, a[6] = (PetscReal) r->balanced, a[7] = r->travel;
  a[8] = r->center_shear;
  for (int d = 0; d < 3; d++)
    a[9 + d] = r->plane_force[d], a[12 + d] = r->pedestal_force[d], a[15 + d] = r->clamp_force[d],
          a[18 + d] = r->weight[d];
}

void CurveRowUnpack(const PetscReal a[CURVE_COLS], CurveRow *r)
{
  r->load_step    = (PetscInt) a[0];
  r->time         = a[1];
  r->elongation   = a[2];
  r->force        = a[3];
  r->inner_steps  = (PetscInt) a[4];
  r->residual     = a[5];
  r->balanced     = a[6] != 0 ? PETSC_TRUE : PETSC_FALSE;
  r->travel       = a[7];
  r->center_shear = a[8];
  for (int d = 0; d < 3; d++)
    r->plane_force[d] = a[9 + d], r->pedestal_force[d] = a[12 + d], r->clamp_force[d] = a[15 + d],
    r->weight[d] = a[18 + d];
}
