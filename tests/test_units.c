/* test_units.c - unit tests of the small pieces the solver is built from, each against an answer
 * worked out by hand, with the tolerance stated (exact equality where the answer is exact).
 *
 *   test_units -case graph_distance|front_box|load_path|curve_row|option_values|drape_defaults|
 *                    predict_extrapolate|break_strain|set_up|scene_units|
 *                    yarn_csv_place
 *
 * graph_distance and front_box check owned points only, on any number of ranks (CTest runs
 * them on 1, 2 and 3): the hand values do not depend on the decomposition, so passing on every
 * rank count means the same values on each.
 */
#include "comm.h"
#include "front.h"
#include "integrate.h"
#include "load.h"
#include "measure.h"
#include "predict.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static int failures = 0; /* the same on every rank: every check is reduced over the ranks */

/* a collective check: bad of total items failed on this rank; one line for all ranks */
static PetscErrorCode Expect(const char *what, PetscInt bad, PetscInt total, const char *tolerance)
{
  PetscInt n[2] = {bad, total}, sum[2];

  PetscFunctionBeginUser;
  PetscCall(MPIU_Allreduce(n, sum, 2, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s %s: %" PetscInt_FMT " of %" PetscInt_FMT " wrong (%s)\n",
                        sum[0] ? "FAIL" : "PASS", what, sum[0], sum[1], tolerance));
  if (sum[0]) failures++;
  PetscFunctionReturn(0);
}

/* a scalar check, the same on every rank: |value - expected| <= tol (0: exact equality) */
static PetscErrorCode ExpectReal(const char *what, PetscReal value, PetscReal expected, PetscReal tol)
{
  const int ok = tol == 0 ? value == expected : PetscAbsReal(value - expected) <= tol;

  PetscFunctionBeginUser;
  if (tol == 0)
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s %s: %.17g, expected %.17g (exact)\n", ok ? "PASS" : "FAIL", what,
                          (double) value, (double) expected));
  else
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s %s: %.17g, expected %.17g (tolerance %.1e)\n", ok ? "PASS" : "FAIL",
                          what, (double) value, (double) expected, (double) tol));
  if (!ok) failures++;
  PetscFunctionReturn(0);
}

/* where the first wrong item was, said by the rank that owns it */
static void Report(PetscInt *bad, const char *fmt, ...)
{
  if (!(*bad)++) {
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stdout, fmt, ap);
    va_end(ap);
    fflush(stdout);
  }
}

static PetscErrorCode NewFabric(const char *opts, Fabric *fab)
{
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsClear(NULL));
  PetscCall(PetscOptionsInsertString(NULL, opts));
  PetscCall(FabricCreate(PETSC_COMM_WORLD, fab));
  PetscFunctionReturn(0);
}

/* no gravity, no output */
#define BASE "-gravity 0,0,0 -output_dir none -quiet "
/* a strip 20 mm x 5 mm at 24 threads/cm: 49 crossings along the pull (i = 0 the clamped jaw,
   i = 48 the moving jaw) by 12 yarns */
#define STRIP BASE "-gauge_mm 20 -width_mm 5 "
/* a 10 mm x 10 mm net at 24 threads/cm (25 x 25), cut to a disc of radius 12 spacings
   about (12,12): the grid's corners are holes */
#define DISC BASE "-test square -shape disc -gauge_mm 10 -width_mm 10 "

/* ---------------- GraphDistance ---------------- */

typedef enum { D_ALONG_I, D_ALONG_J, D_FROM_POINT, D_WALL_TO_GRIP, D_WALL_TO_CLAMP } DistCase;
typedef struct {
  DistCase c;
  PetscInt i0, j0; /* D_ALONG_*: the source's index (i or j); D_FROM_POINT: the source point */
  PetscInt wall;   /* D_WALL_*: the column of holes, open at the top row only */
  PetscInt nx, ny;
} DistHand;

/* the hand-computed graph distance of (i,j) to the source (holes: DIST_INF) */
static PetscReal HandDistance(const DistHand *h, PetscInt i, PetscInt j, int exists)
{
  const PetscInt top = h->ny - 1, w = h->wall;
  if (!exists) return DIST_INF;
  switch (h->c) {
  case D_ALONG_I: return (PetscReal) PetscAbsInt(i - h->i0);
  case D_ALONG_J: return (PetscReal) PetscAbsInt(j - h->j0);
  case D_FROM_POINT: /* a digital disc holds a monotone path between any two of its points */
    return (PetscReal) (PetscAbsInt(i - h->i0) + PetscAbsInt(j - h->j0));
  case D_WALL_TO_GRIP: /* grips at i = nx-1: beyond the wall, round it through (w, top) */
    return (PetscReal) (i > w ? h->nx - 1 - i : (h->nx - 1 - w) + (w - i) + (top - j));
  case D_WALL_TO_CLAMP: /* clamps at i = 0 */ return (PetscReal) (i < w ? i : w + (i - w) + (top - j));
  }
  return -1;
}

/* GraphDistance from the owned points of kind `kind` (or the single point h->i0,h->j0 if kind < 0)
   against the hand values at every owned point, exactly */
static PetscErrorCode CheckDistance(Fabric fab, const char *what, int kind, const DistHand *h)
{
  const Patch *p = &fab->grid.patch;
  PetscReal   *dist;
  char        *src;
  PetscInt     bad = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(fab->grid.nloc, &dist, fab->grid.nloc, &src));
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
    for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
      const PetscInt k = (j - p->ys) * p->xm + (i - p->xs);
      src[k]           = (char) (kind >= 0 ? fab->grid.kind[k] == kind : (i == h->i0 && j == h->j0));
    }
  PetscCall(GraphDistance(fab->comm, fab->grid.da, &fab->grid.patch, src, dist));
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
    for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
      const int       exists = p->exists[(j - p->gys) * p->gxm + (i - p->gxs)];
      const PetscReal got = dist[(j - p->ys) * p->xm + (i - p->xs)], want = HandDistance(h, i, j, exists);
      if (got != want)
        Report(&bad, "  [rank %d] %s at (%d,%d): %g, expected %g\n", fab->rank, what, (int) i, (int) j, (double) got,
               (double) want);
    }
  PetscCall(Expect(what, bad, fab->grid.nloc, "exact"));
  PetscCall(PetscFree2(dist, src));
  PetscFunctionReturn(0);
}

/* make the column i = w a wall of holes for j < ny-1 (on owned and ghost points), or undo it:
   GraphDistance reads the ghosted mask patch.exists, as the kernels do */
static void SetWall(Fabric fab, PetscInt w, unsigned char exists)
{
  const Patch *p = &fab->grid.patch;
  for (PetscInt j = p->gys; j < p->gys + p->gym; j++)
    for (PetscInt i = p->gxs; i < p->gxs + p->gxm; i++)
      if (i == w && j >= 0 && j < p->ny - 1) p->exists[(j - p->gys) * p->gxm + (i - p->gxs)] = exists;
}

static PetscErrorCode TestGraphDistance(void)
{
  Fabric fab;

  PetscFunctionBeginUser;
  /* strip, pulled along the warp: to the clamped jaw i, to the grip 48 - i; prediction weight i/48 */
  PetscCall(NewFabric(STRIP, &fab));
  PetscCall(ExpectReal("strip grid nx (20 mm at 24/cm + 1)", fab->s.spec.nx, 49, 0));
  PetscCall(ExpectReal("strip grid ny (5 mm at 24/cm)", fab->s.spec.ny, 12, 0));
  { /* the decomposition, for the record: the detour round the wall below crosses rank boundaries */
    const Patch *p = &fab->grid.patch;
    PetscCall(PetscSynchronizedPrintf(PETSC_COMM_WORLD, "  rank %d owns i %d..%d, j %d..%d\n", fab->rank, (int) p->xs,
                                      (int) (p->xs + p->xm - 1), (int) p->ys, (int) (p->ys + p->ym - 1)));
    PetscCall(PetscSynchronizedFlush(PETSC_COMM_WORLD, PETSC_STDOUT));
  }
  {
    DistHand h = {D_ALONG_I, 0, 0, 0, 49, 12};
    PetscCall(CheckDistance(fab, "strip (warp): distance to the clamped jaw = i", POINT_CLAMPED, &h));
    h.i0 = 48;
    PetscCall(CheckDistance(fab, "strip (warp): distance to the grip = 48 - i", POINT_GRIP, &h));
  }
  {
    const Patch *p   = &fab->grid.patch;
    PetscInt     bad = 0;
    for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
      for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
        const PetscReal w = fab->grid.predict_w[(j - p->ys) * p->xm + (i - p->xs)];
        if (w != i / 48.0)
          Report(&bad, "  predict_w at (%d,%d): %.17g, expected %d/48\n", (int) i, (int) j, w, (int) i);
      }
    PetscCall(Expect("strip: linear prediction weight d0/(d0+d1) = i/48", bad, fab->grid.nloc, "exact"));
  }
  /* a wall of holes across the strip at i = 24, open in the top row j = 11 only: the distance goes round it */
  {
    DistHand h = {D_WALL_TO_GRIP, 0, 0, 24, 49, 12};
    SetWall(fab, 24, 0);
    PetscCall(CheckDistance(fab, "strip with a wall at i = 24 open at j = 11: distance to the grip round the wall",
                            POINT_GRIP, &h));
    h.c = D_WALL_TO_CLAMP;
    PetscCall(CheckDistance(fab, "strip with a wall at i = 24 open at j = 11: distance to the clamps round the wall",
                            POINT_CLAMPED, &h));
    SetWall(fab, 24, 1);
  }
  PetscCall(FabricDestroy(&fab));

  /* strip pulled along the weft: the jaws are the rows j = 0 and j = 48 */
  PetscCall(NewFabric(STRIP "-pull weft", &fab));
  {
    DistHand h = {D_ALONG_J, 0, 0, 0, 12, 49};
    PetscCall(ExpectReal("weft strip grid ny", fab->s.spec.ny, 49, 0));
    PetscCall(CheckDistance(fab, "strip (weft): distance to the clamped jaw = j", POINT_CLAMPED, &h));
    h.j0 = 48;
    PetscCall(CheckDistance(fab, "strip (weft): distance to the grip = 48 - j", POINT_GRIP, &h));
  }
  PetscCall(FabricDestroy(&fab));

  /* disc: the holes are where (i-12)^2 + (j-12)^2 > 144 */
  PetscCall(NewFabric(DISC, &fab));
  {
    const Patch *p     = &fab->grid.patch;
    PetscInt     bad   = 0;
    PetscInt     count = 0;
    for (PetscInt j = 0; j < 25; j++)
      for (PetscInt i = 0; i < 25; i++) count += (i - 12) * (i - 12) + (j - 12) * (j - 12) <= 144;
    PetscCall(ExpectReal("disc: existing crossings = #{(i-12)^2 + (j-12)^2 <= 144}", fab->grid.points, count, 0));
    for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
      for (PetscInt i = p->xs; i < p->xs + p->xm; i++)
        if (p->exists[(j - p->gys) * p->gxm + (i - p->gxs)] != ((i - 12) * (i - 12) + (j - 12) * (j - 12) <= 144))
          Report(&bad, "  disc: existence of (%d,%d)\n", (int) i, (int) j);
    PetscCall(Expect("disc: the holes are the points beyond radius 12", bad, fab->grid.nloc, "exact"));
  }
  {
    DistHand h = {D_FROM_POINT, 0, 12, 0, 25, 25};
    PetscCall(
        CheckDistance(fab, "disc: distance to its leftmost point (0,12) = |i| + |j - 12|, holes at infinity", -1, &h));
    h.i0 = 4, h.j0 = 4; /* (4,4) exists (64 + 64 <= 144), (3,3) and (4,3) are holes (162, 145 > 144) */
    PetscCall(CheckDistance(fab, "disc: distance to (4,4) on the rim, next to holes = |i - 4| + |j - 4|", -1, &h));
  }
  PetscCall(FabricDestroy(&fab));
  PetscFunctionReturn(0);
}

/* ---------------- FrontStepBox ---------------- */

/* `steps` te steps after a load change: the box (global, half open) and the count against the
   hand values; the owned box = the hand box ∩ the owned points; every owned point within reach
   2k of the sources is in the box, and on a strip (whose box is exactly that set) no other */
static PetscErrorCode CheckFrontSteps(Fabric fab, const char *what, PetscInt steps, PetscInt ci, PetscInt cj,
                                      PetscBool strip, PetscBool disc)
{
  const Patch *p  = &fab->grid.patch;
  PetscInt     nx = fab->s.spec.nx, ny = fab->s.spec.ny, bad = 0, checked = 0;

  PetscFunctionBeginUser;
  FrontLoadChange(fab, PETSC_FALSE); /* the tests run -predict none, or below a prediction that moved the points */
  for (PetscInt k = 1; k <= steps; k++) {
    PetscInt         g[4], l[4], want[4], own[4], area = 0;
    const PetscInt   R   = 2 * k; /* reach: 2 points per te step (the stencil) */
    const PetscInt64 got = FrontStepBox(fab, g, l);
    PetscInt64       count;
    if (strip) { /* grips at i = nx-1: distance nx-1-i */
      want[0] = R >= nx - 1 ? 0 : nx - 1 - R, want[1] = nx, want[2] = 0, want[3] = ny;
    } else { /* the point load at (ci,cj): distance |i-ci| + |j-cj|, its bounding box the square of side 2R+1 */
      const PetscInt dmax = PetscMax(ci, nx - 1 - ci) + PetscMax(cj, ny - 1 - cj);
      want[0] = PetscMax(0, ci - R), want[1] = PetscMin(nx, ci + R + 1);
      want[2] = PetscMax(0, cj - R), want[3] = PetscMin(ny, cj + R + 1);
      if (R >= dmax) want[0] = 0, want[1] = nx, want[2] = 0, want[3] = ny;
    }
    count = (PetscInt64) (want[1] - want[0]) * (want[3] - want[2]);
    if (disc && want[0] == 0 && want[1] == nx && want[2] == 0 && want[3] == ny) count = fab->grid.points;
    checked++;
    if (g[0] != want[0] || g[1] != want[1] || g[2] != want[2] || g[3] != want[3] || got != count)
      Report(&bad, "  %s, te step %d: box [%d,%d) x [%d,%d) count %lld, expected [%d,%d) x [%d,%d) count %lld\n", what,
             (int) k, (int) g[0], (int) g[1], (int) g[2], (int) g[3], (long long) got, (int) want[0], (int) want[1],
             (int) want[2], (int) want[3], (long long) count);
    own[0] = PetscMax(want[0], p->xs), own[1] = PetscMin(want[1], p->xs + p->xm);
    own[2] = PetscMax(want[2], p->ys), own[3] = PetscMin(want[3], p->ys + p->ym);
    if (own[1] <= own[0] || own[3] <= own[2]) own[0] = own[1] = own[2] = own[3] = 0;
    if (l[0] != own[0] || l[1] != own[1] || l[2] != own[2] || l[3] != own[3])
      Report(&bad, "  %s, te step %d, rank %d: owned box [%d,%d) x [%d,%d), expected [%d,%d) x [%d,%d)\n", what,
             (int) k, fab->rank, (int) l[0], (int) l[1], (int) l[2], (int) l[3], (int) own[0], (int) own[1],
             (int) own[2], (int) own[3]);
    for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
      for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
        const PetscInt d   = strip ? nx - 1 - i : PetscAbsInt(i - ci) + PetscAbsInt(j - cj);
        const int      in  = i >= l[0] && i < l[1] && j >= l[2] && j < l[3];
        const int      hit = d <= R;
        if ((hit && !in) || (strip && in && !hit))
          Report(&bad, "  %s, te step %d: point (%d,%d) at distance %d is %s the box\n", what, (int) k, (int) i,
                 (int) j, (int) d, in ? "in" : "not in");
        area += in;
      }
    { /* the owned parts tile the box */
      PetscInt sum;
      PetscCall(MPIU_Allreduce(&area, &sum, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
      if (sum != (want[1] - want[0]) * (want[3] - want[2]))
        Report(&bad, "  %s, te step %d: owned boxes hold %d points, the box %d\n", what, (int) k, (int) sum,
               (int) ((want[1] - want[0]) * (want[3] - want[2])));
    }
  }
  PetscCall(Expect(what, bad, checked, "exact: box, owned box, count, every point within 2k inside"));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestFrontBox(void)
{
  Fabric     fab;
  PetscInt   g[4], l[4];
  PetscInt64 n;

  PetscFunctionBeginUser;
  /* strip: te step k computes i >= 48 - 2k, all 12 yarns, (2k+1) 12 points; covered at k = 24 */
  PetscCall(NewFabric(STRIP "-front 1 -predict none -elongation_pct 1", &fab));
  PetscCall(ExpectReal("strip: front_dmax = 48 (the clamped jaw from the grip)", fab->front.front_dmax, 48, 0));
  PetscCall(CheckFrontSteps(fab, "strip: te step k computes exactly i >= 48 - 2k, (2k+1) x 12 points", 26, 0, 0,
                            PETSC_TRUE, PETSC_FALSE));
  PetscCall(ExpectReal("strip: covered after 24 te steps", fab->front.front_covered, 1, 0));
  /* a second load change starts again from the grips */
  PetscCall(
      CheckFrontSteps(fab, "strip, next load change: starts again from the grips", 3, 0, 0, PETSC_TRUE, PETSC_FALSE));
  PetscCall(FabricDestroy(&fab));

  /* with prediction every point moves at once: the first te step computes the whole grid */
  PetscCall(NewFabric(STRIP "-front 1 -predict linear -elongation_pct 1", &fab));
  FrontLoadChange(fab, PETSC_TRUE);
  n = FrontStepBox(fab, g, l);
  PetscCall(ExpectReal("strip with prediction: first te step computes all 49 x 12 points", (PetscReal) n, 588, 0));
  PetscCall(ExpectReal("strip with prediction: box [0,49) x [0,12)",
                       (g[0] == 0 && g[1] == 49 && g[2] == 0 && g[3] == 12), 1, 0));
  PetscCall(FabricDestroy(&fab));

  /* square net, point load at the centre (12,12): the box of |i-12| + |j-12| <= 2k is [12-2k, 13+2k)^2 */
  PetscCall(
      NewFabric(BASE "-test square -gauge_mm 10 -width_mm 10 -point_load_N 0,0,-0.01 -front 1 -predict none", &fab));
  PetscCall(ExpectReal("square: front_dmax = 24 (centre to corner)", fab->front.front_dmax, 24, 0));
  PetscCall(CheckFrontSteps(fab, "square net, centre load: box [12-2k, 13+2k)^2, count its area", 13, 12, 12,
                            PETSC_FALSE, PETSC_FALSE));
  PetscCall(FabricDestroy(&fab));

  /* sleeping: the box is the awake box grown by the stencil's reach, 2, on every side, and the box kept awake grown
     the same (the 25 x 25 net, front off, the grips at rest) */
  PetscCall(NewFabric(BASE "-test square -gauge_mm 10 -width_mm 10 -point_load_N 0,0,-0.01 -sleep_tol 1e-4", &fab));
  fab->front.front_covered = PETSC_TRUE, fab->load.ramp_done = fab->load.ramp_steps = 0;
  fab->front.awake_box[0] = 5, fab->front.awake_box[1] = 8, fab->front.awake_box[2] = 6, fab->front.awake_box[3] = 9;
  FrontKeepReset(fab);
  n = FrontStepBox(fab, g, l);
  PetscCall(ExpectReal("sleeping: awake [5,8) x [6,9) gives the box [3,10) x [4,11), 49 points",
                       (g[0] == 3 && g[1] == 10 && g[2] == 4 && g[3] == 11 && n == 49), 1, 0));
  {
    const PetscInt keep[4] = {15, 16, 20, 21};
    FrontKeepAwake(fab, keep);
  }
  n = FrontStepBox(fab, g, l);
  PetscCall(ExpectReal("sleeping: with [15,16) x [20,21) kept awake, the box [3,18) x [4,23), 285 points",
                       (g[0] == 3 && g[1] == 18 && g[2] == 4 && g[3] == 23 && n == 285), 1, 0));
  PetscCall(FabricDestroy(&fab));

  /* which crossings a te step finds awake (front.c): its force above -sleep_tol times the force scale (here the floor:
     the net at rest carries no tension), or its speed above -speed_tol x -sleep_tol / -balance_tol. The 25 x 25 net at
     rest, undamped, but for crossing A (5,6), moving out of its plane at 2x the speed bound; B (12,12), under a point
     load of 2x the force bound; C (20,3), moving out of its plane at 0.5x the speed bound (out of the plane: no force
     on the neighbours to first order). The awake box after one te step: A and B, [5,13) x [6,13), exactly */
  PetscCall(NewFabric(BASE "-test square -gauge_mm 10 -width_mm 10 -point_load_N 0,0,-0.01 -integrator damped "
                           "-damping_ratio 0 -sleep_tol 1e-4 -balance_tol 1e-3 -speed_tol 1e-3 -predict none",
                      &fab));
  PetscCall(StableStep(fab));
  fab->front.front_covered = PETSC_TRUE, fab->load.ramp_done = fab->load.ramp_steps = 0;
  FrontWakeAll(fab);
  FrontKeepReset(fab);
  {
    const Patch    *p      = &fab->grid.patch;
    const PetscReal vbound = 1e-3 * 1e-4 / 1e-3, fbound = 1e-4 * fab->step.force_floor;
    const PetscInt  at[3][2] = {{5, 6}, {12, 12}, {20, 3}};
    PetscScalar    *v;
    StepStats       st;
    const PetscInt  li = fab->grid.load_index; /* on the rank that owns it; -1 elsewhere */
    PetscCall(ExpectReal("sleeping: the point load's crossing is B (12,12)",
                         li >= 0 ? (PetscReal) ((p->ys + li / p->xm) * 25 + p->xs + li % p->xm) : 312.0, 312, 0));
    fab->load.load_factor = 2.0 * fbound / 0.01;
    PetscCall(VecGetArray(fab->state.V, &v));
    for (int q = 0; q < 3; q += 2) {
      const PetscInt i = at[q][0], j = at[q][1];
      if (i < p->xs || i >= p->xs + p->xm || j < p->ys || j >= p->ys + p->ym) continue;
      v[3 * ((j - p->ys) * p->xm + (i - p->xs)) + 2] = (q == 0 ? 2.0 : 0.5) * vbound;
    }
    PetscCall(VecRestoreArray(fab->state.V, &v));
    PetscCall(TimeStep(fab, &st));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "  (awake box [%d,%d) x [%d,%d))\n", (int) fab->front.awake_box[0],
                          (int) fab->front.awake_box[1], (int) fab->front.awake_box[2], (int) fab->front.awake_box[3]));
    PetscCall(ExpectReal("sleeping: awake after a te step: A (speed 2x the bound) and B (force 2x the bound), not C "
                         "(speed 0.5x): the box [5,13) x [6,13)",
                         (fab->front.awake_box[0] == 5 && fab->front.awake_box[1] == 13 && fab->front.awake_box[2] == 6 &&
                          fab->front.awake_box[3] == 13),
                         1, 0));
  }
  PetscCall(FabricDestroy(&fab));

  /* disc: the same boxes; once a box is the whole grid, the count is the existing crossings */
  PetscCall(NewFabric(DISC "-point_load_N 0,0,-0.01 -front 1 -predict none", &fab));
  PetscCall(CheckFrontSteps(fab, "disc, centre load: box [12-2k, 13+2k)^2, its area; whole grid: existing points", 13,
                            12, 12, PETSC_FALSE, PETSC_TRUE));
  PetscCall(FabricDestroy(&fab));
  PetscFunctionReturn(0);
}

/* ---------------- PathPoint, GripPathMove, GripElongation, LoadTravel, TestTime ---------------- */

#define U (1.0 / 256) /* a binary unit: every value below is exact in floating point */

static PetscErrorCode ExpectVec(const char *what, const PetscReal got[3], PetscReal x, PetscReal y, PetscReal z)
{
  char text[256];

  PetscFunctionBeginUser;
  for (int d = 0; d < 3; d++) {
    const PetscReal want[3] = {x, y, z};
    PetscCall(PetscSNPrintf(text, sizeof text, "%s [%c]", what, "xyz"[d]));
    PetscCall(ExpectReal(text, got[d], want[d], 0));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode TestLoadPath(void)
{
  Scene     s;
  LoadState ls;
  PetscReal u[3], m[3];
  PetscReal pull[3] = {1, 0, 0};

  PetscFunctionBeginUser;
  /* a path of two waypoints, (3,4,0) U then (3,4,12) U: segment lengths 5 U and 12 U */
  PetscCall(PetscMemzero(&s, sizeof s));
  s.test                = TEST_STRIP;
  s.spec.gauge          = 1.0 / 16;
  s.load.speed          = 1.0 / 64;
  s.load.waypoints      = 2;
  s.load.waypoint[0][0] = 3 * U, s.load.waypoint[0][1] = 4 * U, s.load.waypoint[0][2] = 0;
  s.load.waypoint[1][0] = 3 * U, s.load.waypoint[1][1] = 4 * U, s.load.waypoint[1][2] = 12 * U;
  s.load.path_at[0] = 5 * U, s.load.path_at[1] = 17 * U;

  PathPoint(&s.load, 0, u);
  PetscCall(ExpectVec("PathPoint at 0", u, 0, 0, 0));
  PathPoint(&s.load, -1 * U, u);
  PetscCall(ExpectVec("PathPoint before the start (-1 U): held at 0", u, 0, 0, 0));
  PathPoint(&s.load, 2.5 * U, u);
  PetscCall(ExpectVec("PathPoint mid first segment (2.5 U)", u, 1.5 * U, 2 * U, 0));
  PathPoint(&s.load, 5 * U, u);
  PetscCall(ExpectVec("PathPoint at the first corner (5 U)", u, 3 * U, 4 * U, 0));
  PathPoint(&s.load, 11 * U, u);
  PetscCall(ExpectVec("PathPoint mid second segment (11 U)", u, 3 * U, 4 * U, 6 * U));
  PathPoint(&s.load, 17 * U, u);
  PetscCall(ExpectVec("PathPoint at the end (17 U)", u, 3 * U, 4 * U, 12 * U));
  PathPoint(&s.load, 40 * U, u);
  PetscCall(ExpectVec("PathPoint beyond the end (40 U): held", u, 3 * U, 4 * U, 12 * U));

  GripPathMove(&s, pull, 2.5 * U, 11 * U, m);
  PetscCall(ExpectVec("GripPathMove 2.5 U -> 11 U, across the corner", m, 1.5 * U, 2 * U, 6 * U));
  GripPathMove(&s, pull, 11 * U, 2.5 * U, m);
  PetscCall(ExpectVec("GripPathMove 11 U -> 2.5 U, back", m, -1.5 * U, -2 * U, -6 * U));
  GripPathMove(&s, pull, 17 * U, 30 * U, m);
  PetscCall(ExpectVec("GripPathMove beyond the end: no move", m, 0, 0, 0));

  PetscCall(ExpectReal("GripElongation at 0", GripElongation(&s, pull, 0), 0, 0));
  PetscCall(ExpectReal("GripElongation mid first segment: 1.5 U / gauge", GripElongation(&s, pull, 2.5 * U),
                       1.5 * U * 16, 0));
  PetscCall(ExpectReal("GripElongation at the corner: 3 U / gauge", GripElongation(&s, pull, 5 * U), 3 * U * 16, 0));
  PetscCall(ExpectReal("GripElongation on the out-of-plane segment: 3 U / gauge", GripElongation(&s, pull, 11 * U),
                       3 * U * 16, 0));
  {
    const PetscReal weft[3] = {0, 1, 0};
    PetscCall(ExpectReal("GripElongation along y (weft pull) beyond the end: 4 U / gauge",
                         GripElongation(&s, weft, 40 * U), 4 * U * 16, 0));
  }
  PetscCall(ExpectReal("LoadTravel with a path: its length 17 U", LoadTravel(&s), 17 * U, 0));
  ls.load_step = 3, ls.travel = 11 * U;
  PetscCall(ExpectReal("TestTime: travel / speed = 11 U * 64", TestTime(&s, &ls), 11 * U * 64, 0));

  /* three waypoints, back along the pull: (4,0,0), (4,3,0), (0,3,0) U, lengths 4, 3, 4 */
  s.load.waypoints      = 3;
  s.load.waypoint[0][0] = 4 * U, s.load.waypoint[0][1] = 0, s.load.waypoint[0][2] = 0;
  s.load.waypoint[1][0] = 4 * U, s.load.waypoint[1][1] = 3 * U, s.load.waypoint[1][2] = 0;
  s.load.waypoint[2][0] = 0, s.load.waypoint[2][1] = 3 * U, s.load.waypoint[2][2] = 0;
  s.load.path_at[0] = 4 * U, s.load.path_at[1] = 7 * U, s.load.path_at[2] = 11 * U;
  PathPoint(&s.load, 4 * U, u);
  PetscCall(ExpectVec("3 waypoints: PathPoint at corner 1 (4 U)", u, 4 * U, 0, 0));
  PathPoint(&s.load, 5.5 * U, u);
  PetscCall(ExpectVec("3 waypoints: PathPoint mid segment 2 (5.5 U)", u, 4 * U, 1.5 * U, 0));
  PathPoint(&s.load, 7 * U, u);
  PetscCall(ExpectVec("3 waypoints: PathPoint at corner 2 (7 U)", u, 4 * U, 3 * U, 0));
  PathPoint(&s.load, 9 * U, u);
  PetscCall(ExpectVec("3 waypoints: PathPoint mid segment 3 (9 U)", u, 2 * U, 3 * U, 0));
  PathPoint(&s.load, 12 * U, u);
  PetscCall(ExpectVec("3 waypoints: PathPoint beyond the end (12 U): held", u, 0, 3 * U, 0));
  PetscCall(ExpectReal("3 waypoints: GripElongation mid segment 3 = 2 U / gauge", GripElongation(&s, pull, 9 * U),
                       2 * U * 16, 0));
  PetscCall(
      ExpectReal("3 waypoints: GripElongation at the end = 0 (back at x = 0)", GripElongation(&s, pull, 11 * U), 0, 0));
  PetscCall(ExpectReal("3 waypoints: LoadTravel = 11 U", LoadTravel(&s), 11 * U, 0));

  /* no path: the straight pull */
  s.load.waypoints  = 0;
  s.load.elongation = 0.125;
  GripPathMove(&s, pull, 1 * U, 3 * U, m);
  PetscCall(ExpectVec("no path: GripPathMove 1 U -> 3 U = 2 U along the pull", m, 2 * U, 0, 0));
  PetscCall(ExpectReal("no path: GripElongation = disp / gauge", GripElongation(&s, pull, 3 * U), 3 * U * 16, 0));
  PetscCall(ExpectReal("no path: LoadTravel = elongation * gauge", LoadTravel(&s), 0.125 / 16, 0));
  s.test                 = TEST_PUSHING;
  s.bodies.sphere_travel = 20 * U;
  PetscCall(ExpectReal("pushing: LoadTravel = the sphere's travel", LoadTravel(&s), 20 * U, 0));
  s.test = TEST_SQUARE, s.load.elongation = 0;
  PetscCall(ExpectReal("square (no travel): TestTime = the load step", TestTime(&s, &ls), 3, 0));

  /* the path as the scene reads it: -grip_path_mm 3,4,0,3,4,12 gives corners at 5 mm and 17 mm */
  {
    Scene sc;
    PetscCall(PetscOptionsClear(NULL));
    PetscCall(PetscOptionsInsertString(NULL, STRIP "-grip_path_mm 3,4,0,3,4,12"));
    PetscCall(SceneLoad(PETSC_COMM_WORLD, &sc));
    PetscCall(ExpectReal("-grip_path_mm 3,4,0,3,4,12: waypoints", sc.load.waypoints, 2, 0));
    PetscCall(ExpectReal("-grip_path_mm: length to corner 1 = 5 mm", sc.load.path_at[0], 5e-3, 1e-17));
    PetscCall(ExpectReal("-grip_path_mm: LoadTravel = 17 mm", LoadTravel(&sc), 17e-3, 1e-17));
    PetscCall(ExpectReal("-grip_path_mm: GripElongation at the end = 3 mm / 20 mm",
                         GripElongation(&sc, pull, LoadTravel(&sc)), 3e-3 / 20e-3, 1e-15));
    PetscCall(SceneDestroy(&sc));
    PetscCall(PetscOptionsClear(NULL));
    PetscCall(PetscOptionsInsertString(NULL, STRIP "-elongation_pct 10"));
    PetscCall(SceneLoad(PETSC_COMM_WORLD, &sc));
    PetscCall(ExpectReal("strip, -elongation_pct 10: LoadTravel = 0.1 * gauge (48 spacings of 1/2400 m)",
                         LoadTravel(&sc), 0.1 * (48 / 2400.0), 1e-17));
    PetscCall(SceneDestroy(&sc));
  }
  PetscFunctionReturn(0);
}

/* ---------------- CurveRowPack / CurveRowUnpack ---------------- */

static PetscErrorCode TestCurveRow(void)
{
  CurveRow  r, back;
  PetscReal a[CURVE_COLS], want[CURVE_COLS];
  PetscInt  bad = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&r, sizeof r));
  r.load_step = 7, r.inner_steps = PETSC_MAX_INT; /* the largest count survives the trip through a double */
  r.time = 1.25, r.elongation = 0.0625, r.force = -3.5e2, r.residual = 1.0 / 3, r.travel = 2e-3, r.center_shear = 33.3;
  r.balanced = PETSC_TRUE;
  for (int d = 0; d < 3; d++) {
    r.plane_force[d]    = 10 + d + 0.1;
    r.pedestal_force[d] = 20 + d + 0.2;
    r.clamp_force[d]    = 30 + d + 0.3;
    r.weight[d]         = -(40 + d + 0.4);
  }
  /* the checkpoint's order (/history/curve): the curve.csv columns load_step, time_s,
     elongation, force_N, inner_steps, residual, then the balance flag, travel, center_shear, and
     the plane, pedestal, clamp forces and the weight, x,y,z each */
  {
    const PetscReal order[CURVE_COLS] = {7,       1.25, 0.0625, -3.5e2, (PetscReal) PETSC_MAX_INT,
                                         1.0 / 3, 1,    2e-3,   33.3,   10.1,
                                         11.1,    12.1, 20.2,   21.2,   22.2,
                                         30.3,    31.3, 32.3,   -40.4,  -41.4,
                                         -42.4};
    for (int c = 0; c < CURVE_COLS; c++) want[c] = order[c];
  }
  CurveRowPack(&r, a);
  for (int c = 0; c < CURVE_COLS; c++)
    if (a[c] != want[c]) Report(&bad, "  packed column %d: %.17g, expected %.17g\n", c, a[c], want[c]);
  PetscCall(Expect("CurveRowPack: the 21 columns in the checkpoint's order", bad, CURVE_COLS, "exact"));
  memset(&back, 0xA5, sizeof back); /* a field Unpack left alone would show */
  CurveRowUnpack(a, &back);
  bad = 0;
  {
    const int same = back.load_step == r.load_step && back.inner_steps == r.inner_steps && back.time == r.time &&
                     back.elongation == r.elongation && back.force == r.force && back.residual == r.residual &&
                     back.travel == r.travel && back.center_shear == r.center_shear && back.balanced == r.balanced;
    if (!same) Report(&bad, "  round trip: a scalar field differs\n");
    for (int d = 0; d < 3; d++)
      if (back.plane_force[d] != r.plane_force[d] || back.pedestal_force[d] != r.pedestal_force[d] ||
          back.clamp_force[d] != r.clamp_force[d] || back.weight[d] != r.weight[d])
        Report(&bad, "  round trip: a force component %d differs\n", d);
  }
  PetscCall(Expect("CurveRowUnpack(CurveRowPack(row)) = row, every field", bad, 21, "exact"));
  r.balanced = PETSC_FALSE, r.inner_steps = 0;
  CurveRowPack(&r, a);
  CurveRowUnpack(a, &back);
  PetscCall(ExpectReal("round trip of balanced = false", back.balanced, PETSC_FALSE, 0));
  PetscCall(ExpectReal("round trip of inner_steps = 0", back.inner_steps, 0, 0));
  PetscFunctionReturn(0);
}

/* ---------------- SceneOptionValues against -help ---------------- */

static char  *help_text = NULL;
static size_t help_len = 0, help_cap = 0;

/* PetscPrintf into help_text (rank 0 prints, the only rank these cases run on) */
static PetscErrorCode CaptureVFPrintf(FILE *fd, const char fmt[], va_list ap)
{
  va_list ap2;
  int     n;

  va_copy(ap2, ap);
  n = vsnprintf(NULL, 0, fmt, ap2);
  va_end(ap2);
  if (n < 0) return PETSC_ERR_SYS;
  if (help_len + n + 1 > help_cap) {
    help_cap  = 2 * (help_len + n + 1);
    help_text = (char *) realloc(help_text, help_cap);
    if (!help_text) return PETSC_ERR_MEM;
  }
  vsnprintf(help_text + help_len, n + 1, fmt, ap);
  help_len += n;
  return 0;
}

/* the enum options' choices, to read -help's names as SceneOptionValues' numbers */
static const char *const *Choices(const char *name)
{
  if (!strcmp(name, "test")) return TestNames;
  if (!strcmp(name, "pull")) return PullAxisNames;
  if (!strcmp(name, "shape")) return ShapeNames;
  if (!strcmp(name, "clamp")) return ClampNames;
  if (!strcmp(name, "solver")) return SolverNames;
  if (!strcmp(name, "integrator")) return IntegratorNames;
  if (!strcmp(name, "predict")) return PredictNames;
  return NULL;
}

/* does -help's default text say the values v[0..n)? Numbers as -help prints them (%g) */
static int SameAsHelp(const char *name, const char *def, const PetscReal v[], PetscInt n)
{
  const char *const *choices    = Choices(name);
  char               text[2048] = "";
  if (!strcmp(def, "unset")) return n == 0;
  if (n != 1 && (!strcmp(def, "true") || !strcmp(def, "false"))) return 0;
  if (!strcmp(def, "true")) return v[0] == 1;
  if (!strcmp(def, "false")) return v[0] == 0;
  if (choices) {
    for (int k = 0; choices[k + 2]; k++)
      if (!strcmp(def, choices[k])) return n == 1 && v[0] == k;
    return 0;
  }
  for (PetscInt c = 0; c < n; c++) {
    const size_t at = strlen(text);
    snprintf(text + at, sizeof text - at, "%s%g", c ? "," : "", (double) v[c]);
  }
  return !strcmp(text, def);
}

/* is -name among the options given (its value is then not the default -help prints)? */
static int Given(const char *opts, const char *name)
{
  const size_t len = strlen(name);
  for (const char *at = strstr(opts, name); at; at = strstr(at + 1, name))
    if (at > opts && at[-1] == '-' && (at[len] == ' ' || !at[len])) return 1;
  return 0;
}

#define MAX_OPTS 256
typedef struct {
  char name[64], def[256];
} HelpOption;

/* -help's options of the scene (lines "  -name <default>: help"), from the captured text */
static PetscInt ParseHelp(const char *text, HelpOption *opt)
{
  PetscInt    n    = 0;
  const char *line = text;
  while (line && *line && n < MAX_OPTS) {
    const char *end = strchr(line, '\n'), *lt, *gt;
    if (!strncmp(line, "  -", 3) && (lt = strstr(line, " <")) && (!end || lt < end) && (gt = strstr(lt, ">: ")) &&
        (!end || gt < end)) {
      snprintf(opt[n].name, sizeof opt[n].name, "%.*s", (int) (lt - line - 3), line + 3);
      snprintf(opt[n].def, sizeof opt[n].def, "%.*s", (int) (gt - lt - 2), lt + 2);
      n++;
    }
    line = end ? end + 1 : NULL;
  }
  return n;
}

/* SceneLoad with opts and -help: every option -help lists with a non-empty default (the numeric
   ones; the file and directory options default to empty) comes from SceneOptionValues once,
   with the value -help prints; the names are unique; the only names -help does not list are
   the -weft_... twins of its -warp_... options */
static PetscErrorCode CheckOptionValues(const char *label, const char *opts)
{
  Scene       s;
  HelpOption *help;
  char(*names)[64];
  PetscInt       nhelp, nvals = 0, bad = 0, numeric = 0;
  PetscReal      v[96];
  PetscErrorCode ierr;
  char           what[256];
  PetscErrorCode (*saved_vfprintf)(FILE *, const char[], va_list);

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(MAX_OPTS, &help, MAX_OPTS, &names));
  PetscCall(PetscOptionsClear(NULL));
  PetscCall(PetscOptionsInsertString(NULL, opts));
  PetscCall(PetscOptionsInsertString(NULL, "-help"));
  help_len       = 0;
  saved_vfprintf = PetscVFPrintf;
  PetscVFPrintf  = CaptureVFPrintf;
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = SceneLoad(PETSC_COMM_SELF, &s);
  PetscCall(PetscPopErrorHandler());
  PetscVFPrintf = saved_vfprintf;
  PetscCall(PetscSNPrintf(what, sizeof what, "%s: SceneLoad(%s) succeeds", label, opts));
  PetscCall(ExpectReal(what, ierr == 0, 1, 0));
  if (ierr) {
    const char *text     = NULL;
    char       *specific = NULL;
    PetscCall(PetscErrorMessage(ierr, &text, &specific));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "  SceneLoad(%s): %s\n", opts, specific && specific[0] ? specific : text));
    PetscCall(SceneDestroy(&s));
    PetscCall(PetscFree2(help, names));
    PetscFunctionReturn(0);
  }
  nhelp = ParseHelp(help_text ? help_text : "", help);
  for (PetscInt k = 0; k < MAX_OPTS; k++) {
    PetscInt n = 0;
    if (!SceneOptionValues(&s, k, names[nvals], v, &n)) break;
    for (PetscInt q = 0; q < nvals; q++)
      if (!strcmp(names[q], names[nvals])) Report(&bad, "  %s: -%s twice\n", label, names[q]);
    {
      PetscInt at = -1;
      for (PetscInt h = 0; h < nhelp; h++)
        if (!strcmp(help[h].name, names[nvals])) at = h;
      if (at < 0 && strncmp(names[nvals], "weft_", 5))
        Report(&bad, "  %s: SceneOptionValues gives -%s, which -help does not list\n", label, names[nvals]);
      if (at >= 0 && !Given(opts, names[nvals]) && !SameAsHelp(help[at].name, help[at].def, v, n))
        Report(&bad, "  %s: -%s is %g (%d values), -help says <%s>\n", label, names[nvals], n ? (double) v[0] : 0.0,
               (int) n, help[at].def);
      if (at < 0 && !strncmp(names[nvals], "weft_", 5)) { /* the twin: present in -help as warp_ */
        char warp[64];
        snprintf(warp, sizeof warp, "warp_%s", names[nvals] + 5);
        for (PetscInt h = 0; h < nhelp; h++)
          if (!strcmp(help[h].name, warp)) at = h;
        if (at < 0) Report(&bad, "  %s: -%s has no -warp_ twin in -help\n", label, names[nvals]);
      }
    }
    nvals++;
  }
  for (PetscInt h = 0; h < nhelp; h++) {
    PetscInt found = 0;
    for (PetscInt q = 0; q < nvals; q++) found += !strcmp(names[q], help[h].name);
    if (help[h].def[0]) numeric++;
    if (help[h].def[0] && found != 1)
      Report(&bad, "  %s: -%s <%s> of -help comes %d times from SceneOptionValues\n", label, help[h].name, help[h].def,
             (int) found);
    if (!help[h].def[0] && found)
      Report(&bad, "  %s: -%s (a file or directory, empty by default) comes from SceneOptionValues\n", label,
             help[h].name);
    if (!strncmp(help[h].name, "warp_", 5) && help[h].def[0]) {
      char weft[64];
      snprintf(weft, sizeof weft, "weft_%s", help[h].name + 5);
      found = 0;
      for (PetscInt q = 0; q < nvals; q++) found += !strcmp(names[q], weft);
      if (found != 1) Report(&bad, "  %s: -%s (the twin of -%s) comes %d times\n", label, weft, help[h].name, found);
    }
  }
  PetscCall(PetscSNPrintf(what, sizeof what,
                          "%s: SceneOptionValues = the %d numeric options of -help (+ weft twins), once each, "
                          "defaults as -help prints them",
                          label, (int) numeric));
  PetscCall(Expect(what, bad, nvals, "exact: names, counts, values printed with %g"));
  PetscCall(PetscSNPrintf(what, sizeof what, "%s: -help lists options", label));
  PetscCall(ExpectReal(what, nhelp > 60, 1, 0));
  PetscCall(SceneDestroy(&s));
  PetscCall(PetscFree2(help, names));
  PetscFunctionReturn(0);
}

/* the value of one option in SceneOptionValues (n = -1: not there) */
static void ValueOf(const Scene *s, const char *want, PetscReal v[96], PetscInt *n)
{
  char name[64];
  *n = -1;
  for (PetscInt k = 0; SceneOptionValues(s, k, name, v, n); k++)
    if (!strcmp(name, want)) return;
  *n = -1;
}

/* the test-dependent defaults, by hand (docs/options.md): test, option, value */
static const struct {
  const char *test, *name;
  PetscReal   value;
} ByTest[] = {
    {"strip", "gauge_mm", 200},          {"strip", "elongation_pct", 13},         {"strip", "clamp", CLAMP_JAW},
    {"strip", "shape", SHAPE_RECTANGLE}, {"strip", "sphere_diameter_mm", 0},      {"square", "clamp", CLAMP_EDGE},
    {"square", "elongation_pct", 0},     {"pushing", "sphere_diameter_mm", 25.4}, {"pushing", "sphere_travel_mm", 20},
    {"pushing", "clamp", CLAMP_EDGE},    {"pushing", "elongation_pct", 0},        {"bias", "shape", SHAPE_BIAS},
    {"bias", "clamp", CLAMP_JAW},        {"bias", "elongation_pct", 13},          {"bias", "width_mm", 50},
};

static PetscErrorCode TestOptionValues(void)
{
  const char *tests[] = {"strip", "square", "pushing", "bias"};

  PetscFunctionBeginUser;
  for (int t = 0; t < 4; t++) {
    char  opts[64];
    Scene s;
    PetscCall(PetscSNPrintf(opts, sizeof opts, "-test %s", tests[t]));
    PetscCall(CheckOptionValues(tests[t], opts));
    PetscCall(PetscOptionsClear(NULL));
    PetscCall(PetscOptionsInsertString(NULL, opts));
    PetscCall(SceneLoad(PETSC_COMM_SELF, &s));
    for (size_t e = 0; e < sizeof ByTest / sizeof ByTest[0]; e++) {
      PetscReal v[96];
      PetscInt  n;
      char      what[128];
      if (strcmp(ByTest[e].test, tests[t])) continue;
      ValueOf(&s, ByTest[e].name, v, &n);
      PetscCall(PetscSNPrintf(what, sizeof what, "%s: default -%s (by hand)", tests[t], ByTest[e].name));
      PetscCall(ExpectReal(what, n == 1 ? v[0] : -1, ByTest[e].value, 0));
    }
    PetscCall(SceneDestroy(&s));
  }
  /* a value given: SceneOptionValues gives it, not the default */
  {
    Scene     s;
    char      name[64];
    PetscReal v[96];
    PetscInt  n, got = 0;
    PetscCall(PetscOptionsClear(NULL));
    PetscCall(PetscOptionsInsertString(NULL, "-gauge_mm 20 -weft_tex 33 -gravity 1,2,3"));
    PetscCall(SceneLoad(PETSC_COMM_SELF, &s));
    for (PetscInt k = 0; SceneOptionValues(&s, k, name, v, &n); k++) {
      if (!strcmp(name, "gauge_mm")) got += n == 1 && v[0] == 20;
      if (!strcmp(name, "weft_tex")) got += n == 1 && v[0] == 33;
      if (!strcmp(name, "warp_tex")) got += n == 1 && v[0] == 20;
      if (!strcmp(name, "gravity")) got += n == 3 && v[0] == 1 && v[1] == 2 && v[2] == 3;
    }
    PetscCall(ExpectReal("given values: -gauge_mm 20 -weft_tex 33 -gravity 1,2,3 (warp_tex 20) come back", got, 4, 0));
    PetscCall(SceneDestroy(&s));
  }
  PetscFunctionReturn(0);
}

/* -test drape alone: its own defaults (a 300 mm disc held in the 0,180 mm ring on the 180 mm
   pedestal) load, as -help and docs/options.md say */
static PetscErrorCode TestDrapeDefaults(void)
{
  Scene          s;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(CheckOptionValues("drape", "-test drape"));
  PetscCall(PetscOptionsClear(NULL));
  PetscCall(PetscOptionsInsertString(NULL, "-test drape"));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = SceneLoad(PETSC_COMM_SELF, &s);
  PetscCall(PetscPopErrorHandler());
  if (!ierr) {
    PetscCall(ExpectReal("drape: clamp ring inner radius (m)", s.clamps.ring[0], 0, 0));
    PetscCall(ExpectReal("drape: clamp ring outer radius 90 mm (m)", s.clamps.ring[1], 0.09, 1e-17));
    PetscCall(ExpectReal("drape: pedestal radius 90 mm (m)", s.bodies.pedestal_radius, 0.09, 1e-17));
    PetscCall(ExpectReal("drape: disc radius 150 mm (m)", s.spec.disc_radius, 0.15, 1e-16));
    { /* the ring's default is an option value, as -help and summary.json give it (it was unset there) */
      PetscReal v[96];
      PetscInt  n;
      ValueOf(&s, "clamp_ring_mm", v, &n);
      PetscCall(ExpectReal("drape: -clamp_ring_mm's default has two values", n, 2, 0));
      PetscCall(ExpectReal("drape: -clamp_ring_mm's default 0,180: inner and outer (mm) matched", n == 2 && v[0] == 0 && v[1] == 180, 1, 0));
    }
    PetscCall(SceneDestroy(&s));
  }
  PetscFunctionReturn(0);
}

/* ---------------- breaking strains: the Weibull draw ---------------- */

/* The segments' yarn breaking strains of a 20 tex cotton at 24 threads/cm (breaking strain 6.5 %,
   CV 10 % at a 500 mm gauge): over 10^6 segments their mean is the Weibull mean of the segment
   scale and their CV 10 %, each within 4 standard errors; the smallest of every 1111 (a 500 mm yarn
   of segments 1.08 x 1/2400 m long) averages the yarn test's 6.5 %, within 4 standard errors; no warp draw of
   10^4 segments equals the weft's of the same (i, j), nor the draw of the next seed (exact); a fabric's patch holds each segment's draw by its global index, on any number of ranks. */
static PetscErrorCode TestBreakStrain(void)
{
  const PetscInt  N = 1000000, G = 1111; /* segments; segments of a 500 mm yarn: 0.5 / (1.08 / 2400) = 1111.1 */
  const PetscReal cv = 0.10, mean = 0.065;
  Fabric          fab;
  PetscReal       sum = 0, sum2 = 0, gmin = PETSC_MAX_REAL, gsum = 0, k, seg_mean, m, sd;
  PetscInt        groups = 0, bad = 0, total = 0;

  PetscFunctionBeginUser;
  PetscCall(NewFabric(STRIP "-warp_break_pct 6.5 -weft_break_pct 6.5 -warp_break_cv_pct 10 -weft_break_cv_pct 10 "
                            "-break_seed 7",
                      &fab));
  {
    const YarnLaw *y = &fab->s.yarns.warp;
    k                = y->break_k;
    char what[80];
    PetscCall(PetscSNPrintf(what, sizeof what, "Weibull shape for CV 10 %%, k = %.4f: its CV", (double) k));
    PetscCall(ExpectReal(what, PetscSqrtReal(tgamma(1 + 2 / k) / PetscSqr(tgamma(1 + 1 / k)) - 1), cv, 1e-12));
    seg_mean = y->break_scale * tgamma(1 + 1 / k);
    for (PetscInt n = 0; n < N; n++) {
      const PetscReal ey = (SegmentBreakStrain(y, 7, 0, n % 1000, n / 1000) - y->crimp) / (1 + y->crimp);
      sum += ey, sum2 += ey * ey;
      gmin = PetscMin(gmin, ey);
      if ((n + 1) % G == 0) gsum += gmin, gmin = PETSC_MAX_REAL, groups++;
    }
    m  = sum / N;
    sd = PetscSqrtReal(sum2 / N - m * m);
    PetscCall(ExpectReal("segments' mean breaking strain / its Weibull mean", m / seg_mean, 1, 4 * cv / PetscSqrtReal(N)));
    { /* a segment's draw is its own: the warp's and the weft's at one (i, j) differ, and so do one seed's and the next's */
      PetscInt same[2] = {0, 0};
      for (PetscInt n = 0; n < 10000; n++) {
        const PetscReal e = SegmentBreakStrain(y, 7, 0, n % 100, n / 100);
        same[0] += e == SegmentBreakStrain(y, 7, 1, n % 100, n / 100);
        same[1] += e == SegmentBreakStrain(y, 8, 0, n % 100, n / 100);
      }
      PetscCall(ExpectReal("of 10^4 segments (i, j), warp draws equal to the weft's at (i, j)", same[0], 0, 0));
      PetscCall(ExpectReal("of 10^4 segments, draws of -break_seed 7 equal to those of 8", same[1], 0, 0));
    }
    PetscCall(ExpectReal("segments' CV of the breaking strain", sd / m, cv, 4 * cv / PetscSqrtReal(2.0 * N)));
    PetscCall(ExpectReal("mean of the weakest of 1111 segments (a 500 mm yarn) / 6.5 %", gsum / groups / mean, 1,
                         4 * cv / PetscSqrtReal((PetscReal) groups)));
  }
  { /* the patch: every ghosted segment's strain is the draw of its global index */
    const Patch *p = &fab->grid.patch;
    for (PetscInt lj = 0; lj < p->gym; lj++)
      for (PetscInt li = 0; li < p->gxm; li++, total += 2) {
        const PetscInt q = lj * p->gxm + li, i = p->gxs + li, j = p->gys + lj;
        if (p->break_x[q] != SegmentBreakStrain(p->warp, 7, 0, i, j))
          Report(&bad, "warp segment %" PetscInt_FMT ",%" PetscInt_FMT ": %g\n", i, j, (double) p->break_x[q]);
        if (p->break_y[q] != SegmentBreakStrain(p->weft, 7, 1, i, j))
          Report(&bad, "weft segment %" PetscInt_FMT ",%" PetscInt_FMT ": %g\n", i, j, (double) p->break_y[q]);
      }
    PetscCall(Expect("the patch's breaking strains are the draws of the segments' global indices", bad, total, "exact"));
  }
  PetscCall(FabricDestroy(&fab));
  PetscFunctionReturn(0);
}

/* ---------------- the textile units at the edges: SceneLoad's SI values, summary.json's echo ---------------- */

/* |value - expected| <= 4 ulp of expected: a unit factor applied once (an exact answer rounded once or twice) */
static PetscErrorCode ExpectSI(const char *what, PetscReal value, PetscReal expected)
{
  PetscFunctionBeginUser;
  PetscCall(ExpectReal(what, value, expected, 4 * PETSC_MACHINE_EPSILON * PetscAbsReal(expected)));
  PetscFunctionReturn(0);
}

/* summary.json's options (SceneOptionsJson): option name's line is exactly "name": text */
static PetscErrorCode ExpectJsonLine(const Scene *s, const char *name, const char *text)
{
  FILE *fp = tmpfile();
  char  line[512], want[256], what[320];
  int   found = 0;

  PetscFunctionBeginUser;
  PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "no temporary file");
  snprintf(want, sizeof want, "    \"%s\": %s", name, text);
  SceneOptionsJson(s, fp, "    ");
  rewind(fp);
  while (fgets(line, sizeof line, fp)) {
    size_t n = strcspn(line, "\n");
    line[n] = 0;
    if (n && line[n - 1] == ',') line[n - 1] = 0; /* the member's comma */
    found += !strcmp(line, want);
  }
  fclose(fp);
  PetscCall(PetscSNPrintf(what, sizeof what, "summary.json's options: %s once", want + 4));
  PetscCall(ExpectReal(what, found, 1, 0));
  PetscFunctionReturn(0);
}

/* the scene's yarn options as distinct values for warp and weft, the densities unequal (20 ends x 10 picks per cm),
   every conversion worked out by hand: tex (g/km) -> kg/m is 1e-6, EA = modulus (cN/tex) x tex / 100 N, % / 100,
   mm/min -> m/s is 1e-3/60, ms -> s 1e-3, mm -> m 1e-3. summary.json's options echo every given value exactly
   (%.17g: strtod gives the double back), each yarn its own. */
#define UNIT_YARNS                                                                                                     \
  "-warp_tex 30 -weft_tex 12.5 -warp_modulus_cN_tex 200 -weft_modulus_cN_tex 400 -warp_crimp_pct 6 -weft_crimp_pct 3 " \
  "-warp_contact_pct 40 -weft_contact_pct 25 -warp_law_smoothing_pct 1 -weft_law_smoothing_pct 2 "                    \
  "-warp_bending_Nm2 3e-9 -weft_bending_Nm2 5e-9 -warp_break_pct 7 -weft_break_pct 4 -warp_decrimp_ratio 0.1 "         \
  "-weft_decrimp_ratio 0.2 -ends_per_cm 20 -picks_per_cm 10 "
static PetscErrorCode TestSceneUnits(void)
{
  Scene s;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsClear(NULL));
  PetscCall(PetscOptionsInsertString(NULL, STRIP UNIT_YARNS
                                     "-speed_mm_min 30 -elongation_pct 5 -tear_max_ms 7 -tear_te_safety 0.75 "
                                     "-rupture_drop_pct 40 -break_gauge_mm 250 -plane -plane_point_mm 0,0,-1 "
                                     "-thickness_mm 0.4 -warp_break_cv_pct 0.123456789012345678"));
  PetscCall(SceneLoad(PETSC_COMM_SELF, &s));
  {
    const YarnLaw *w = &s.yarns.warp, *f = &s.yarns.weft;
    PetscCall(ExpectSI("-warp_tex 30: mu 3e-5 kg/m", w->mu, 3e-5));
    PetscCall(ExpectSI("-weft_tex 12.5: mu 1.25e-5 kg/m", f->mu, 1.25e-5));
    PetscCall(ExpectSI("warp EA = 200 cN/tex x 30 tex = 60 N", w->EA, 60));
    PetscCall(ExpectSI("weft EA = 400 cN/tex x 12.5 tex = 50 N", f->EA, 50));
    PetscCall(ExpectSI("-warp_crimp_pct 6: 0.06", w->crimp, 0.06));
    PetscCall(ExpectSI("-weft_crimp_pct 3: 0.03", f->crimp, 0.03));
    PetscCall(ExpectSI("-warp_contact_pct 40: contact at chord strain -0.4", w->e_contact, -0.4));
    PetscCall(ExpectSI("-weft_contact_pct 25: contact at chord strain -0.25", f->e_contact, -0.25));
    PetscCall(ExpectSI("-warp_law_smoothing_pct 1: half-width 0.01", w->smoothing, 0.01));
    PetscCall(ExpectSI("-weft_law_smoothing_pct 2: half-width 0.02", f->smoothing, 0.02));
    PetscCall(ExpectSI("-warp_bending_Nm2 3e-9", w->bending, 3e-9));
    PetscCall(ExpectSI("-weft_bending_Nm2 5e-9", f->bending, 5e-9));
    PetscCall(ExpectSI("-warp_break_pct 7: yarn breaking strain 0.07", w->break_ey, 0.07));
    PetscCall(ExpectSI("-weft_break_pct 4: yarn breaking strain 0.04", f->break_ey, 0.04));
    PetscCall(ExpectSI("warp Ec = 0.1 x 60 N = 6 N", w->Ec, 6));
    PetscCall(ExpectSI("weft Ec = 0.2 x 50 N = 10 N", f->Ec, 10));
    PetscCall(ExpectSI("-break_gauge_mm 250: 0.25 m", w->break_gauge, 0.25));
  }
  PetscCall(ExpectSI("-ends_per_cm 20: 2000 per m", s.spec.ends_per_m, 2000));
  PetscCall(ExpectSI("-picks_per_cm 10: 1000 per m", s.spec.picks_per_m, 1000));
  /* the warp pull: along x the weft spacing 1 mm (gauge 20 mm: 21 crossings), across 5 mm / 0.5 mm = 10 yarns */
  PetscCall(ExpectReal("warp strip 20 x 5 mm at 20 ends x 10 picks/cm: nx 21", s.spec.nx, 21, 0));
  PetscCall(ExpectReal("warp strip: ny 10", s.spec.ny, 10, 0));
  PetscCall(ExpectSI("warp strip: gauge 20 mm", s.spec.gauge, 0.02));
  PetscCall(ExpectSI("warp strip: width 5 mm", s.spec.width, 0.005));
  PetscCall(ExpectSI("-speed_mm_min 30: 5e-4 m/s", s.load.speed, 5e-4));
  PetscCall(ExpectSI("-speed_tol 0: the test speed, 5e-4 m/s", s.num.speed_tol, 5e-4));
  PetscCall(ExpectSI("-elongation_pct 5: 0.05", s.load.elongation, 0.05));
  PetscCall(ExpectSI("-tear_max_ms 7: 7e-3 s", s.rupture.max_time, 7e-3));
  PetscCall(ExpectReal("-tear_te_safety 0.75", s.num.te_safety_tear, 0.75, 0));
  PetscCall(ExpectSI("-rupture_drop_pct 40: 0.4", s.rupture.drop, 0.4));
  PetscCall(ExpectSI("-thickness_mm 0.4: 4e-4 m", s.bodies.thickness, 4e-4));
  PetscCall(ExpectSI("-plane_point_mm 0,0,-1: z -1e-3 m", s.bodies.plane_point[2], -1e-3));
  /* the contact's default penalty: the warp segment's EA/L0, L0 the weft spacing 1 mm: 60 N / 1e-3 m */
  PetscCall(ExpectSI("-contact_stiffness_N_m 0: warp EA x picks per m = 6e4 N/m", s.bodies.contact_k, 6e4));
  { /* summary.json's options: the given values back exactly, warp and weft each their own */
    static const struct {
      const char *name;
      double      value;
    } Echo[] = {{"warp_tex", 30},          {"weft_tex", 12.5},       {"warp_modulus_cN_tex", 200},
                {"weft_modulus_cN_tex", 400}, {"warp_crimp_pct", 6},  {"weft_crimp_pct", 3},
                {"warp_bending_Nm2", 3e-9}, {"weft_bending_Nm2", 5e-9}, {"speed_mm_min", 30},
                {"tear_max_ms", 7},        {"ends_per_cm", 20},      {"picks_per_cm", 10},
                {"warp_break_cv_pct", 0.123456789012345678}, {"weft_break_cv_pct", 0}};
    FILE    *fp = tmpfile();
    char     line[512];
    PetscInt found[sizeof Echo / sizeof Echo[0]] = {0}, bad = 0;
    if (fp) {
      SceneOptionsJson(&s, fp, "    ");
      rewind(fp);
      while (fgets(line, sizeof line, fp))
        for (size_t e = 0; e < sizeof Echo / sizeof Echo[0]; e++) {
          char key[80];
          snprintf(key, sizeof key, "    \"%s\": ", Echo[e].name);
          if (strncmp(line, key, strlen(key))) continue;
          found[e]++;
          if (strtod(line + strlen(key), NULL) != Echo[e].value)
            Report(&bad, "  summary.json: %s", line);
        }
      fclose(fp);
    }
    for (size_t e = 0; e < sizeof Echo / sizeof Echo[0]; e++)
      if (found[e] != 1) Report(&bad, "  summary.json: -%s %d times\n", Echo[e].name, (int) found[e]);
    PetscCall(Expect("summary.json's options: each given value once, exactly (%.17g)", bad,
                     (PetscInt) (sizeof Echo / sizeof Echo[0]), "exact"));
  }
  PetscCall(SceneDestroy(&s));

  /* the weft pull: along y the warp spacing 0.5 mm (gauge 20 mm: 41 crossings), across 5 mm / 1 mm = 5 yarns */
  PetscCall(PetscOptionsClear(NULL));
  PetscCall(PetscOptionsInsertString(NULL, STRIP "-pull weft -ends_per_cm 20 -picks_per_cm 10"));
  PetscCall(SceneLoad(PETSC_COMM_SELF, &s));
  PetscCall(ExpectReal("weft strip 20 x 5 mm at 20 ends x 10 picks/cm: nx 5", s.spec.nx, 5, 0));
  PetscCall(ExpectReal("weft strip: ny 41", s.spec.ny, 41, 0));
  PetscCall(ExpectSI("weft strip: gauge 20 mm", s.spec.gauge, 0.02));
  PetscCall(ExpectSI("weft strip: width 5 mm", s.spec.width, 0.005));
  PetscCall(SceneDestroy(&s));

  /* the square net: gauge along x at the weft spacing 1 mm (21 crossings), width along y at the warp spacing 0.5 mm
     (11 crossings) */
  PetscCall(PetscOptionsClear(NULL));
  PetscCall(PetscOptionsInsertString(NULL, BASE "-test square -gauge_mm 20 -width_mm 5 -ends_per_cm 20 -picks_per_cm 10 "
                                                 "-point_load_N 0,0.25,-1.5 -point_load_at 7,3"));
  PetscCall(SceneLoad(PETSC_COMM_SELF, &s));
  PetscCall(ExpectReal("square net 20 x 5 mm at 20 ends x 10 picks/cm: nx 21", s.spec.nx, 21, 0));
  PetscCall(ExpectReal("square net: ny 11", s.spec.ny, 11, 0));
  PetscCall(ExpectSI("square net: gauge 20 mm", s.spec.gauge, 0.02));
  PetscCall(ExpectSI("square net: width 5 mm", s.spec.width, 0.005));
  PetscCall(ExpectReal("-point_load_at 7,3: i", s.load.load_at[0], 7, 0));
  PetscCall(ExpectReal("-point_load_at 7,3: j", s.load.load_at[1], 3, 0));
  PetscCall(ExpectJsonLine(&s, "point_load_at", "[7, 3]"));
  PetscCall(ExpectJsonLine(&s, "point_load_N", "[0, 0.25, -1.5]"));
  PetscCall(ExpectJsonLine(&s, "test", "\"square\""));
  PetscCall(SceneDestroy(&s));

  /* the bias specimen at unequal densities: a grid of side (gauge + 2 jaw depths + width) / sqrt(2) = 84 mm / sqrt(2)
     = 59.40 mm, along x at the weft spacing (6 picks/cm: round(35.64) + 1 = 37), along y at the warp spacing
     (8 ends/cm: round(47.52) + 1 = 49) */
  PetscCall(PetscOptionsClear(NULL));
  PetscCall(PetscOptionsInsertString(NULL, BASE "-test bias -gauge_mm 60 -width_mm 20 -jaw_depth_mm 2 -ends_per_cm 8 "
                                                 "-picks_per_cm 6"));
  PetscCall(SceneLoad(PETSC_COMM_SELF, &s));
  PetscCall(ExpectReal("bias 60 x 20 mm, jaws 2 mm, at 8 ends x 6 picks/cm: nx 37", s.spec.nx, 37, 0));
  PetscCall(ExpectReal("bias: ny 49", s.spec.ny, 49, 0));
  PetscCall(ExpectSI("bias: gauge 60 mm", s.spec.gauge, 0.06));
  PetscCall(ExpectSI("bias: width 20 mm", s.spec.width, 0.02));
  PetscCall(ExpectSI("bias: jaw depth 2 mm", s.spec.jaw_depth, 0.002));
  PetscCall(SceneDestroy(&s));

  /* -static_sequence's coarser fabric (docs/options.md): half the thread density, each yarn of twice the tex (mass
     and EA) and twice the bending stiffness; the 25 x 25 net at 24 threads/cm gives 13 x 13 */
  {
    Scene     fine, coarse;
    PetscBool fits;
    PetscCall(PetscOptionsClear(NULL));
    PetscCall(PetscOptionsInsertString(NULL, BASE "-test square -gauge_mm 10 -width_mm 10 -warp_bending_Nm2 3e-9"));
    PetscCall(SceneLoad(PETSC_COMM_SELF, &fine));
    PetscCall(SceneCoarsen(PETSC_COMM_SELF, &fine, &coarse, &fits));
    PetscCall(ExpectReal("the 25 x 25 net has a coarser fabric", fits, 1, 0));
    if (fits) {
      PetscCall(ExpectReal("coarse net: nx 13", coarse.spec.nx, 13, 0));
      PetscCall(ExpectSI("coarse net: 1200 ends per m", coarse.spec.ends_per_m, 1200));
      PetscCall(ExpectSI("coarse warp: mu 2 x 20 tex = 4e-5 kg/m", coarse.yarns.warp.mu, 4e-5));
      PetscCall(ExpectSI("coarse warp: EA 2 x 52 N", coarse.yarns.warp.EA, 104));
      PetscCall(ExpectSI("coarse warp: bending 2 x 3e-9 N m^2", coarse.yarns.warp.bending, 6e-9));
      PetscCall(ExpectSI("coarse weft: bending 2 x 2e-9 N m^2", coarse.yarns.weft.bending, 4e-9));
      PetscCall(SceneDestroy(&coarse));
    }
    PetscCall(SceneDestroy(&fine));
  }
  /* the same with a tabulated warp law (a curved one, 2 + 3 s^2 cN at s %, written to a temporary file): the coarse
     yarn stands for two, so its table holds twice the fine table's forces at every node, and EA is twice */
  {
    char      file[] = "/tmp/fabric_coarse_XXXXXX", opts[256];
    int       fd     = mkstemp(file);
    FILE     *fp     = fd >= 0 ? fdopen(fd, "w") : NULL;
    Scene     fine, coarse;
    PetscBool fits;
    PetscReal worst = 0;
    PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write a temporary file");
    fprintf(fp, "strain_pct,force_cN\n0,0\n");
    for (int k = 1; k <= 10; k++) fprintf(fp, "%d,%d\n", k, 2 + 3 * k * k);
    fclose(fp);
    PetscCall(PetscSNPrintf(opts, sizeof opts, BASE "-test square -gauge_mm 10 -width_mm 10 -warp_law_csv %s", file));
    PetscCall(PetscOptionsClear(NULL));
    PetscCall(PetscOptionsInsertString(NULL, opts));
    PetscCall(SceneLoad(PETSC_COMM_SELF, &fine));
    PetscCall(SceneCoarsen(PETSC_COMM_SELF, &fine, &coarse, &fits));
    unlink(file);
    PetscCall(ExpectReal("the 25 x 25 net with a tabulated law has a coarser fabric", fits, 1, 0));
    if (fits) {
      PetscCall(ExpectReal("coarse warp table: as many nodes as the fine", coarse.yarns.warp.ntab, fine.yarns.warp.ntab, 0));
      for (PetscInt k = 0; k < PetscMin(fine.yarns.warp.ntab, coarse.yarns.warp.ntab); k++)
        worst = PetscMax(worst, PetscAbsReal(coarse.yarns.warp.tab_T[k] - 2 * fine.yarns.warp.tab_T[k]) /
                                    PetscMax(PetscAbsReal(2 * fine.yarns.warp.tab_T[k]), 1e-300));
      PetscCall(ExpectReal("coarse warp table: 2 x the fine tension at every node, largest relative difference", worst, 0,
                           1e-15));
      PetscCall(ExpectReal("coarse warp: EA 2 x the fine table's (relative)", coarse.yarns.warp.EA / (2 * fine.yarns.warp.EA),
                           1, 1e-15));
      PetscCall(SceneDestroy(&coarse));
    }
    PetscCall(SceneDestroy(&fine));
  }

  /* the drape's pedestal: 40 mm high, its top at -thickness/2 */
  PetscCall(PetscOptionsClear(NULL));
  PetscCall(PetscOptionsInsertString(NULL, "-test drape -pedestal_height_mm 40 -thickness_mm 0.5"));
  PetscCall(SceneLoad(PETSC_COMM_SELF, &s));
  PetscCall(ExpectSI("-pedestal_height_mm 40: 0.04 m", s.bodies.pedestal_height, 0.04));
  PetscCall(ExpectSI("the pedestal's top at -thickness/2 = -2.5e-4 m", s.bodies.pedestal_top[2], -2.5e-4));
  PetscCall(SceneDestroy(&s));

  /* te's safety and strain window by the integrator (options.md): FIRE 0.8 and 0.005, damped and paper 0.65 and 1 (the
     whole law); a tear's 0.9 (-tear_te_safety) and 1 whatever the integrator; given ones are taken, the window a
     tear's too, the safety not (exact) */
  {
    const char     *given[4]  = {"-integrator fire", "-integrator damped", "-integrator paper",
                                 "-integrator damped -te_safety 0.5 -te_strain_window 0.02"};
    const PetscReal want[4][4] = {{0.8, 0.005, 0.9, 1.0}, {0.65, 1.0, 0.9, 1.0}, {0.65, 1.0, 0.9, 1.0}, {0.5, 0.02, 0.9, 0.02}};
    char            what[160];
    for (int c = 0; c < 4; c++) {
      PetscCall(PetscOptionsClear(NULL));
      PetscCall(PetscOptionsInsertString(NULL, "-test strip"));
      PetscCall(PetscOptionsInsertString(NULL, given[c]));
      PetscCall(SceneLoad(PETSC_COMM_SELF, &s));
      PetscCall(PetscSNPrintf(what, sizeof what, "%s: te_safety %g", given[c], (double) want[c][0]));
      PetscCall(ExpectReal(what, s.num.te_safety, want[c][0], 0));
      PetscCall(PetscSNPrintf(what, sizeof what, "%s: te_strain_window %g", given[c], (double) want[c][1]));
      PetscCall(ExpectReal(what, s.num.te_window, want[c][1], 0));
      PetscCall(PetscSNPrintf(what, sizeof what, "%s: a tear's te safety %g", given[c], (double) want[c][2]));
      PetscCall(ExpectReal(what, s.num.te_safety_tear, want[c][2], 0));
      PetscCall(PetscSNPrintf(what, sizeof what, "%s: a tear's strain window %g", given[c], (double) want[c][3]));
      PetscCall(ExpectReal(what, s.num.te_window_tear, want[c][3], 0));
      PetscCall(SceneDestroy(&s));
    }
  }
  PetscFunctionReturn(0);
}

/* a relative yarn table is the working directory's when it is there, the scene file's directory's only when it is
   not: two linear tables of the same name, 100 cN and 50 cN per % (EA 100 N and 50 N, from the slope of the
   Steffen spline through straight data, to 1e-9), one in the working directory and one beside the scene file;
   a third only beside the scene file. Made in a temporary directory, removed after. */
static PetscErrorCode TestYarnCsvPlace(void)
{
  char           tmp[] = "/tmp/fabric_csv_XXXXXX", cwd[PETSC_MAX_PATH_LEN], path[PETSC_MAX_PATH_LEN + 32];
  const char    *files[3] = {"law.csv", "scene/law.csv", "scene/only.csv"};
  const int      per_pct[3] = {100, 50, 50};
  Scene          s;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCheck(getcwd(cwd, sizeof cwd) && mkdtemp(tmp), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "no temporary directory");
  PetscCall(PetscSNPrintf(path, sizeof path, "%s/scene", tmp));
  PetscCheck(!mkdir(path, 0700), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot make %s", path);
  for (int f = 0; f < 3; f++) {
    FILE *fp;
    PetscCall(PetscSNPrintf(path, sizeof path, "%s/%s", tmp, files[f]));
    fp = fopen(path, "w");
    PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write %s", path);
    fprintf(fp, "strain_pct,force_cN\n");
    for (int k = 0; k <= 4; k++) fprintf(fp, "%d,%d\n", k, k * per_pct[f]);
    fclose(fp);
  }
  PetscCheck(!chdir(tmp), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot enter %s", tmp);
  PetscCall(PetscOptionsClear(NULL));
  PetscCall(PetscOptionsInsertString(NULL, STRIP "-scene scene/x.yaml -warp_law_csv law.csv -weft_law_csv only.csv"));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = SceneLoad(PETSC_COMM_SELF, &s); /* the files are removed below whatever it gives */
  PetscCall(PetscPopErrorHandler());
  PetscCall(ExpectReal("SceneLoad with the two tables succeeds", (PetscReal) ierr, 0, 0));
  if (!ierr) {
    PetscCall(ExpectReal("-warp_law_csv law.csv, in the working directory and beside the scene: the working "
                         "directory's (its path as given)",
                         (PetscReal) !strcmp(s.yarns.warp.csv, "law.csv"), 1, 0));
    PetscCall(ExpectReal("... its law, 100 cN per %: EA 100 N", s.yarns.warp.EA, 100, 1e-7));
    PetscCall(ExpectReal("-weft_law_csv only.csv, beside the scene only: scene/only.csv",
                         (PetscReal) !strcmp(s.yarns.weft.csv, "scene/only.csv"), 1, 0));
    PetscCall(ExpectReal("... its law, 50 cN per %: EA 50 N", s.yarns.weft.EA, 50, 5e-8));
    PetscCall(SceneDestroy(&s));
  }
  PetscCheck(!chdir(cwd), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot return to %s", cwd);
  for (int f = 2; f >= 0; f--) {
    PetscCall(PetscSNPrintf(path, sizeof path, "%s/%s", tmp, files[f]));
    remove(path);
  }
  PetscCall(PetscSNPrintf(path, sizeof path, "%s/scene", tmp));
  rmdir(path);
  rmdir(tmp);
  PetscFunctionReturn(0);
}

/* ---------------- PredictLoadStep, extrapolating ---------------- */

/* -predict extrapolate at load step 3, by hand: the converged states of the last two load steps
   Xconv_prev = X0 and Xconv = X0 + delta (delta a distinct multiple of 2^-20 m per point and axis), the
   positions at Xconv. Each free point moves by ratio x delta, every other stays: ratio = the grip steps'
   ratio (2^-12 m after 2^-13 m: 2) on the strip, 1 under a point load (the load grows by the same share each
   load step: the last increment again). Exact: the expected value is the same operations' result. */
static PetscErrorCode CheckExtrapolate(const char *what, const char *opts, PetscReal step_prev, PetscReal step,
                                       PetscReal ratio)
{
  Fabric             fab;
  const PetscScalar *x, *x0, *xc;
  PetscScalar       *a;
  PetscBool          moved;
  PetscInt           bad = 0;
  const PetscReal    move[3] = {0, 0, 0};

  PetscFunctionBeginUser;
  PetscCall(NewFabric(opts, &fab));
  PetscCall(VecDuplicate(fab->state.X, &fab->state.Xconv));
  PetscCall(VecDuplicate(fab->state.X, &fab->state.Xconv_prev));
  PetscCall(VecCopy(fab->grid.X0, fab->state.Xconv_prev));
  PetscCall(VecGetArray(fab->state.Xconv, &a));
  PetscCall(VecGetArrayRead(fab->grid.X0, &x0));
  for (PetscInt k = 0; k < fab->grid.nloc; k++)
    for (int d = 0; d < 3; d++) a[3 * k + d] = x0[3 * k + d] + ldexp((PetscReal) ((k % 7 + 1) * (d + 1)), -20);
  PetscCall(VecRestoreArrayRead(fab->grid.X0, &x0));
  PetscCall(VecRestoreArray(fab->state.Xconv, &a));
  PetscCall(VecCopy(fab->state.Xconv, fab->state.X));
  fab->load.load_step        = 3;
  fab->load.travel_step_prev = step_prev;
  PetscCall(PredictLoadStep(fab, step, move, &moved));
  PetscCall(VecGetArrayRead(fab->state.X, &x));
  PetscCall(VecGetArrayRead(fab->state.Xconv, &xc));
  PetscCall(VecGetArrayRead(fab->grid.X0, &x0));
  for (PetscInt k = 0; k < fab->grid.nloc; k++)
    for (int d = 0; d < 3; d++) {
      const PetscReal want = fab->grid.kind[k] == POINT_FREE ? xc[3 * k + d] + ratio * (xc[3 * k + d] - x0[3 * k + d])
                                                              : xc[3 * k + d];
      if (x[3 * k + d] != want)
        Report(&bad, "%s: point %" PetscInt_FMT " axis %d at %.17g, expected %.17g\n", what, k, d,
               (double) x[3 * k + d], (double) want);
    }
  PetscCall(VecRestoreArrayRead(fab->grid.X0, &x0));
  PetscCall(VecRestoreArrayRead(fab->state.Xconv, &xc));
  PetscCall(VecRestoreArrayRead(fab->state.X, &x));
  PetscCall(Expect(what, bad + (moved ? 0 : 1), 3 * fab->grid.nloc, "exact"));
  PetscCall(FabricDestroy(&fab));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestPredictExtrapolate(void)
{
  PetscFunctionBeginUser;
  PetscCall(CheckExtrapolate("strip: each free point moves by (grip step 2^-12 / last 2^-13) x its last increment",
                             STRIP "-predict extrapolate", ldexp(1.0, -13), ldexp(1.0, -12), 2.0));
  PetscCall(CheckExtrapolate("square net, point load: each free point moves by its last increment",
                             BASE "-test square -gauge_mm 10 -width_mm 10 -point_load_N 0,0,0.1 -predict extrapolate",
                             0.0, 0.0, 1.0));
  PetscFunctionReturn(0);
}

/* ---------------- the fabric's set-up (fabric.c) and the exact sums (comm.c) ---------------- */

/* A strip at unequal densities and yarns: every owned crossing's mass is half of each yarn segment at it,
   tex (1 + crimp) x the spacing along that yarn (MODEL.md 4), and the bending constants are B / spacing, the shear
   constant G x both spacings, the jamming one jam_factor x that and the lock sin(lock angle), to 1e-15;
   a disc's crossings are those within its radius (counted here in integers); -point_load_at i,j loads crossing (i, j)
   on its rank alone; the pushing test's ball touches at its radius plus half the thickness; the smallest split the
   stencil allows (2 crossings a rank) is taken; GlobalSumsExact sums terms whose largest is a rank's last, and more terms
   than a 64-bit integer can sum; CheckRankEntries refuses on every rank. On any number of ranks. */
static PetscErrorCode TestSetUp(void)
{
  Fabric      fab;
  PetscMPIInt size, rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  { /* 25 picks/cm (warp segments 0.4 mm, along i), 20 ends/cm (weft segments 0.5 mm, along j) */
    const PetscReal mx = 0.5 * 20e-6 * 1.08 * 0.4e-3, my = 0.5 * 30e-6 * 1.05 * 0.5e-3;
    PetscInt        bad = 0;
    PetscCall(NewFabric(STRIP "-ends_per_cm 20 -picks_per_cm 25 -warp_tex 20 -weft_tex 30 -warp_crimp_pct 8 "
                              "-weft_crimp_pct 5 -warp_bending_Nm2 2e-9 -weft_bending_Nm2 3e-9 -shear_G_N_m 7 "
                              "-shear_lock_deg 30 -jam_factor 40",
                        &fab));
    const Patch *p = &fab->grid.patch;
    for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
      for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
        const PetscReal got  = fab->grid.mass[(j - p->ys) * p->xm + (i - p->xs)];
        const PetscReal want = mx * ((i > 0) + (i < p->nx - 1)) + my * ((j > 0) + (j < p->ny - 1));
        if (!(PetscAbsReal(got - want) <= 1e-14 * want))
          Report(&bad, "  [rank %d] mass at (%d,%d): %.17g kg, expected %.17g\n", rank, (int) i, (int) j, (double) got,
                 (double) want);
      }
    PetscCall(Expect("strip 20 x 25 threads/cm, 20 and 30 tex, 8 and 5 % crimp: each crossing's mass", bad,
                     fab->grid.nloc, "1e-14 relative"));
    PetscCall(ExpectReal("warp bending constant B / 0.4 mm (N m)", p->kbx, 2e-9 / 0.4e-3, 1e-15 * 2e-9 / 0.4e-3));
    PetscCall(ExpectReal("weft bending constant B / 0.5 mm (N m)", p->kby, 3e-9 / 0.5e-3, 1e-15 * 3e-9 / 0.5e-3));
    PetscCall(ExpectReal("shear constant G x 0.4 mm x 0.5 mm (N m)", p->Ks, 7 * 0.4e-3 * 0.5e-3, 1e-15 * 7 * 0.4e-3 * 0.5e-3));
    PetscCall(ExpectReal("jamming constant 40 x the shear constant (N m)", p->Kj, 40 * 7 * 0.4e-3 * 0.5e-3,
                         1e-15 * 40 * 7 * 0.4e-3 * 0.5e-3));
    PetscCall(ExpectReal("locking shear sin(30 deg)", p->s_lock, 0.5, 1e-15));
    PetscCall(FabricDestroy(&fab));
  }
  { /* a 37 mm disc on a 50 mm net at 20 threads/cm: 101 x 101 crossings at 0.5 mm, radius 37 spacings; crossings
       on the circle (0 +-37 and 12,35 spacings from the centre, ...) belong to it */
    PetscInt want = 0, bad = 0;
    for (PetscInt j = 0; j < 101; j++)
      for (PetscInt i = 0; i < 101; i++) want += (i - 50) * (i - 50) + (j - 50) * (j - 50) <= 37 * 37;
    PetscCall(NewFabric(BASE "-test square -shape disc -gauge_mm 50 -width_mm 50 -ends_per_cm 20 -picks_per_cm 20 "
                             "-disc_diameter_mm 37",
                        &fab));
    const Patch *p = &fab->grid.patch;
    for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
      for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
        const int in = (i - 50) * (i - 50) + (j - 50) * (j - 50) <= 37 * 37;
        if (p->exists[(j - p->gys) * p->gxm + (i - p->gxs)] != in)
          Report(&bad, "  [rank %d] crossing (%d,%d) %s in the disc\n", rank, (int) i, (int) j, in ? "missing" : "wrongly");
      }
    PetscCall(Expect("disc of 37 mm at 0.5 mm spacings: the crossings within it", bad, fab->grid.nloc, "exact"));
    PetscCall(ExpectReal("disc of 37 mm at 0.5 mm spacings: its crossings (points)", (PetscReal) fab->grid.points,
                         (PetscReal) want, 0));
    PetscCall(FabricDestroy(&fab));
  }
  { /* -point_load_at 7,3 on a 10 mm x 5 mm square net at 20 threads/cm: the point load acts on crossing (i, j) =
       (7, 3), on the rank that owns it, and no other (i and j swapped: (3, 7), also a free crossing) */
    PetscInt bad = 0;
    PetscCall(NewFabric(BASE "-test square -gauge_mm 10 -width_mm 5 -ends_per_cm 20 -picks_per_cm 20 -point_load_at 7,3 "
                             "-point_load_N 0,0,-0.01",
                        &fab));
    const Patch   *p    = &fab->grid.patch;
    const int      owns = 7 >= p->xs && 7 < p->xs + p->xm && 3 >= p->ys && 3 < p->ys + p->ym;
    const PetscInt want = owns ? (3 - p->ys) * p->xm + (7 - p->xs) : -1;
    if (fab->grid.load_index != want)
      Report(&bad, "  [rank %d] the point load at local point %d, expected %d\n", rank, (int) fab->grid.load_index, (int) want);
    PetscCall(Expect("-point_load_at 7,3: the point load's crossing (7, 3), on its rank alone", bad, 1, "exact"));
    PetscCall(FabricDestroy(&fab));
  }
  { /* the pushing test's 25.4 mm ball on a fabric 0.4 mm thick: it touches a crossing at its radius plus half the
       thickness */
    PetscCall(NewFabric(BASE "-test pushing -ends_per_cm 4 -picks_per_cm 4 -thickness_mm 0.4", &fab));
    PetscCall(ExpectReal("pushing: one body, the ball",
                         (PetscReal) (fab->bodies.n == 1 && fab->bodies.body[0].kind == BODY_SPHERE), 1, 0));
    PetscCall(ExpectReal("the ball's radius 12.7 mm (m)", fab->bodies.body[0].radius, 12.7e-3, 1e-15 * 12.7e-3));
    PetscCall(ExpectReal("the ball's contact distance 12.7 mm + 0.2 mm (m)", fab->bodies.body[0].reach, 12.9e-3,
                         1e-15 * 12.9e-3));
    PetscCall(FabricDestroy(&fab));
  }
  if (size > 1) { /* one yarn of 2 crossings a rank: split along it, 2 crossings each */
    char opts[256];
    PetscCall(PetscSNPrintf(opts, sizeof opts, STRIP "-yarns 1 -gauge_mm %.17g", (2.0 * size - 1) / 2.4));
    PetscCall(NewFabric(opts, &fab));
    PetscCall(ExpectReal("one yarn of 2 crossings a rank: its crossings", (PetscReal) fab->grid.points, 2.0 * size, 0));
    PetscCall(Expect("one yarn of 2 crossings a rank: each rank holds 2", fab->grid.patch.xm != 2, 1, "exact"));
    PetscCall(FabricDestroy(&fab));
  }
  { /* 5 terms a rank (a block of 4 and one more), the largest its last: rank r's last terms are 2^r, and 2^20 after
       a 1 (powers of 2: every term is a whole number of quanta, the sums are exact) */
    const PetscReal big = 1048576.0;
    PetscReal       terms[10] = {0, 0, 0, 0, ldexp(1.0, rank), 1, 0, 0, 0, big}, sums[2];
    PetscCall(GlobalSumsExact(PETSC_COMM_WORLD, 2, terms, 5, sums));
    PetscCall(ExpectReal("GlobalSumsExact, each rank's only term its last, 2^rank: 2^ranks - 1", sums[0],
                         ldexp(1.0, size) - 1, 0));
    PetscCall(ExpectReal("GlobalSumsExact, each rank's largest term its last: ranks x (1 + 2^20)", sums[1],
                         size * (1.0 + big), 0));
  }
  { /* a scale below 2^40 / DBL_MAX: 2^40 / scale overflows (every term became LLONG_MIN: the sums were garbage, and
       RoundHalfAway overflowed a signed integer); the same powers of 2 times 2^-1000 and 2^-1070 (subnormal) */
    for (int e = 1000; e <= 1070; e += 70) {
      PetscReal terms[10] = {0, 0, 0, 0, ldexp(1.0, rank - e), ldexp(1.0, 20 - e), 0, 0, 0, -ldexp(1.0, 21 - e)}, sums[2];
      char      what[128];
      PetscCall(GlobalSumsExact(PETSC_COMM_WORLD, 2, terms, 5, sums));
      PetscCall(PetscSNPrintf(what, sizeof what, "GlobalSumsExact of terms 2^-%d times 2^rank: (2^ranks - 1) 2^-%d", e, e));
      PetscCall(ExpectReal(what, sums[0], ldexp(ldexp(1.0, size) - 1, -e), 0));
      PetscCall(PetscSNPrintf(what, sizeof what, "GlobalSumsExact of 2^(20-%d) - 2^(21-%d) a rank: -ranks 2^(20-%d)", e, e, e));
      PetscCall(ExpectReal(what, sums[1], -size * ldexp(1.0, 20 - e), 0));
    }
  }
  { /* 9 M terms, every one the largest: 2^40 quanta each, 9.9e18 in all, past a 64-bit integer (the total wrapped
       past 2^23 terms, 8.4 M crossings: the sum came out negative); the blocks are summed in 128 bits */
    const PetscInt n = (9000000 + size - 1) / size;
    PetscReal     *terms, sum;
    PetscCall(PetscMalloc1(n, &terms));
    for (PetscInt k = 0; k < n; k++) terms[k] = 1.0;
    PetscCall(GlobalPointSums(PETSC_COMM_WORLD, 1, terms, n, &sum));
    PetscCall(ExpectReal("GlobalPointSums of 9 M terms of 1 over the ranks (2^40 quanta each): their number", sum,
                         (PetscReal) n * size, 0));
    PetscCall(PetscFree(terms));
  }
  { /* CheckRankEntries: past 2^31 - 1 entries on rank 0 alone, every rank refuses (a rank alone would leave the
       others waiting); at 2^31 - 1 none does */
    for (int over = 0; over < 2; over++) {
      const double   most = over ? 2147483648.0 : 2147483647.0;
      PetscErrorCode ierr;
      char           what[128];
      PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
      ierr = CheckRankEntries(PETSC_COMM_WORLD, rank == 0 ? most : 1.0, 63, "the test's array");
      PetscCall(PetscPopErrorHandler());
      PetscCall(PetscSNPrintf(what, sizeof what, "CheckRankEntries of %.0f entries on rank 0: refused on every rank", most));
      PetscCall(ExpectReal(what, ierr == PETSC_ERR_USER_INPUT, over, 0));
    }
  }
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  char name[64] = "";

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-case", name, sizeof name, NULL));
  if (!strcmp(name, "graph_distance"))
    PetscCall(TestGraphDistance());
  else if (!strcmp(name, "front_box"))
    PetscCall(TestFrontBox());
  else if (!strcmp(name, "load_path"))
    PetscCall(TestLoadPath());
  else if (!strcmp(name, "curve_row"))
    PetscCall(TestCurveRow());
  else if (!strcmp(name, "option_values"))
    PetscCall(TestOptionValues());
  else if (!strcmp(name, "drape_defaults"))
    PetscCall(TestDrapeDefaults());
  else if (!strcmp(name, "predict_extrapolate"))
    PetscCall(TestPredictExtrapolate());
  else if (!strcmp(name, "break_strain"))
    PetscCall(TestBreakStrain());
  else if (!strcmp(name, "set_up"))
    PetscCall(TestSetUp());
  else if (!strcmp(name, "scene_units"))
    PetscCall(TestSceneUnits());
  else if (!strcmp(name, "yarn_csv_place"))
    PetscCall(TestYarnCsvPlace());
  else {
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "unknown -case '%s'\n", name));
    failures++;
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s: %d failure(s)\n", name, failures));
  free(help_text);
  PetscCall(PetscOptionsClear(NULL)); /* the cases' options are not the command line's: nothing left over */
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
