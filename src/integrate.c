/* integrate.c - explicit time integration (MODEL.md 7) and the stable step.
 *
 * fire (default): FIRE, velocities steered along the force and stopped when the power F.v turns
 *   negative (IntegrateFire below; MODEL.md 15).
 * damped, central differences with mass-proportional damping c = nu/m:
 *   v(n+1/2) = ((2 - c te) v(n-1/2) + 2 te F_n / m) / (2 + c te),  x(n+1) = x(n) + te v(n+1/2)
 *   stable for omega_max te <= 2 at any damping.
 * paper, eq. (10), a leapfrog over two interleaved chains:
 *   V(n+1) = (2 te / m)(R_n - nu V(n)) + V(n-1),  u(n+1) = 2 te V(n) + u(n-1)
 *   stable only for omega_max te <= 1, and with nu > 0 it has a growing parasitic mode.
 * te = safety * bound, bound = 2/omega_max (damped, FIRE) or 1/omega_max (paper), with
 * omega_max^2 bounded over a window of states around the current one (StableOmega2, kernels.c);
 * a te step that leaves the window (the force sweep checks it) takes the bound again.
 */
#include "integrate.h"
#include "bodies.h"
#include "comm.h"
#include "events.h"
#include "front.h"
#include "spectrum.h"

#include <math.h>

/* FIRE's constants (Bitzek et al. 2006; Guenole et al. 2020): after more than FIRE_NMIN te steps
   with power P = F.v > 0 the step grows by FIRE_FINC up to te and alpha shrinks by FIRE_FALPHA; at
   P <= 0 the points step back half a step, stop, the step shrinks by FIRE_FDEC (not below
   FIRE_DTMIN te) and alpha restarts at FIRE_ALPHA0. */
#define FIRE_NMIN   5
#define FIRE_FINC   1.1
#define FIRE_FDEC   0.5
#define FIRE_ALPHA0 0.1
#define FIRE_FALPHA 0.99
#define FIRE_DTMIN  0.02

/* the rigid bodies' contact and friction on the owned points of box, row by row (their reactions are measured
   apart, as exact sums: measure.c) */
static PetscErrorCode BodyForces(Fabric fab, Vec X, const PetscInt box[4], PetscScalar *f)
{
  const Patch       *p = &fab->grid.patch;
  const PetscScalar *x;
  PetscScalar       *anchor[BODY_KINDS] = {NULL};
  PetscReal          c[BODY_KINDS][3];

  PetscFunctionBeginUser;
  if (!fab->bodies.n) PetscFunctionReturn(0);
  for (PetscInt q = 0; q < fab->bodies.n; q++) BodyPosition(&fab->bodies.body[q], fab->load.travel_now, c[q]);
  PetscCall(VecGetArrayRead(X, &x));
  for (PetscInt q = 0; q < fab->bodies.n; q++) {
    const Vec a = fab->state.anchor[fab->bodies.body[q].kind];
    if (a) PetscCall(VecGetArray(a, &anchor[q]));
  }
  for (PetscInt j = box[2]; j < box[3]; j++) {
    const PetscInt k0 = (j - p->ys) * p->xm + (box[0] - p->xs), n = box[1] - box[0];
    for (PetscInt q = 0; q < fab->bodies.n; q++) {
      const Body *b = &fab->bodies.body[q];
      BodyContact(b, c[q], n, x + 3 * k0, fab->grid.inv_m + k0, anchor[q] ? anchor[q] + 3 * k0 : NULL, f + 3 * k0);
    }
  }
  for (PetscInt q = 0; q < fab->bodies.n; q++)
    if (anchor[q]) PetscCall(VecRestoreArray(fab->state.anchor[fab->bodies.body[q].kind], &anchor[q]));
  PetscCall(VecRestoreArrayRead(X, &x));
  PetscFunctionReturn(0);
}

/* internal forces at positions X on the owned points of box (NULL: all), plus the point load
   and the rigid bodies' contact, into F */
PetscErrorCode ComputeForcesAt(Fabric fab, Vec X, Vec F, const PetscInt box[4], PetscReal *tension_max)
{
  const Patch       *p      = &fab->grid.patch;
  const PetscInt     all[4] = {p->xs, p->xs + p->xm, p->ys, p->ys + p->ym};
  const PetscScalar *xl;
  PetscScalar       *f;

  PetscFunctionBeginUser;
  if (!box) box = all;
  PetscCall(HaloExchange(fab->grid.da, X, fab->state.Xl));
  PetscCall(PetscLogEventBegin(EV_Force, 0, 0, 0, 0));
  PetscCall(VecGetArrayRead(fab->state.Xl, &xl));
  PetscCall(VecGetArray(F, &f));
  ComputeInternalForces(&fab->grid.patch, xl, box, f, tension_max);
  if (fab->grid.load_index >= 0) {
    const PetscInt i = p->xs + fab->grid.load_index % p->xm, j = p->ys + fab->grid.load_index / p->xm;
    if (i >= box[0] && i < box[1] && j >= box[2] && j < box[3])
      for (int d = 0; d < 3; d++) f[3 * fab->grid.load_index + d] += fab->load.load_factor * fab->s.load.point_load[d];
  }
  PetscCall(BodyForces(fab, X, box, f));
  PetscCall(VecRestoreArray(F, &f));
  PetscCall(VecRestoreArrayRead(fab->state.Xl, &xl));
  PetscCall(PetscLogEventEnd(EV_Force, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* the same at the current positions, into the state's forces */
PetscErrorCode ComputeForces(Fabric fab, const PetscInt box[4], PetscReal *tension_max)
{
  PetscFunctionBeginUser;
  PetscCall(ComputeForcesAt(fab, fab->state.X, fab->state.F, box, tension_max));
  PetscFunctionReturn(0);
}

/* -info: where the bound is set (the lowest crossing index among the rows that set it), its
   terms' parts there, and the window it holds for */
static PetscErrorCode BoundInfo(Fabric fab, const BoundRow *at)
{
  const Patch *p = &fab->grid.patch;
  PetscBool    info;
  PetscReal    v     = at->omega2, part[4] = {0, 0, 0, 0};
  PetscInt     index = at->i >= 0 ? at->j * fab->s.spec.nx + at->i : -1;

  PetscFunctionBeginUser;
  PetscCall(PetscInfoEnabled(PETSC_SMALLEST_CLASSID, &info)); /* PetscInfo(NULL, ...)'s class */
  if (!info) PetscFunctionReturn(0);
  PetscCall(GlobalArgMax(fab->comm, &v, &index));
  if (index < 0) PetscFunctionReturn(0);
  if (at->i >= 0 && at->omega2 == v && at->j * fab->s.spec.nx + at->i == index)
    for (int q = 0; q < 4; q++) part[q] = at->part[q];
  PetscCall(GlobalMax(fab->comm, part, 4)); /* the parts of the rank that holds the row (all >= 0) */
  PetscCall(PetscInfo(NULL,
                      "load step %" PetscInt_FMT ", te step %" PetscInt64_FMT
                      ": omega_max^2 <= %.6g rad^2/s^2, set at crossing (%" PetscInt_FMT ", %" PetscInt_FMT
                      "): traction %.4g, bending %.4g, shear %.4g, contact %.4g; for warp strains in [%.4g, %.4g], "
                      "weft in [%.4g, %.4g] (yarn stiffness up to %.6g and %.6g N/m a segment), |cos| of the "
                      "yarns' angle up to %.4g\n",
                      fab->load.load_step, fab->stats.te_steps, (double) v, index % fab->s.spec.nx,
                      index / fab->s.spec.nx, (double) part[0], (double) part[1], (double) part[2], (double) part[3],
                      (double) p->win_lo[0], (double) p->win_hi[0], (double) p->win_lo[1], (double) p->win_hi[1],
                      (double) p->win_k[0], (double) p->win_k[1], (double) p->win_s));
  PetscFunctionReturn(0);
}

/* the window of the state (WindowRange, reduced, widened by -te_strain_window) and the bound on
   omega_max^2 for every state within it; te from it, or the user's -te checked against it */
static PetscErrorCode StableBound(Fabric fab, PetscReal omega2[2])
{
  const Scene       *s = &fab->s;
  Patch             *p = &fab->grid.patch;
  const PetscScalar *xl;
  PetscReal          r[5];
  BoundRow           at;

  PetscFunctionBeginUser;
  PetscCall(HaloExchange(fab->grid.da, fab->state.X, fab->state.Xl));
  PetscCall(PetscLogEventBegin(EV_Bound, 0, 0, 0, 0));
  PetscCall(VecGetArrayRead(fab->state.Xl, &xl));
  WindowRange(p, xl, r);
  PetscCall(GlobalMax(fab->comm, r, 5));
  WindowSet(p, r, (fab->step.tear ? s->num.te_window_tear : s->num.te_window) * (PetscReal) (1 << fab->step.window_grow));
  fab->step.window_bound_at = fab->stats.te_steps;
  for (int q = 0; q < p->ncb; q++) /* the sphere where it is now, and how far it moves within the load step */
    if (p->cb[q].sphere) {
      BodyPosition(&fab->bodies.body[p->cb[q].body], fab->load.travel_now, p->cb[q].c);
      p->cb[q].span = PetscAbsReal(fab->load.travel - fab->load.travel_now);
    }
  omega2[0] = StableOmega2(p, xl, fab->grid.inv_m, s->spec.pull == PULL_WARP ? 0 : 1, &omega2[1], &at);
  PetscCall(VecRestoreArrayRead(fab->state.Xl, &xl));
  PetscCall(PetscLogEventEnd(EV_Bound, 0, 0, 0, 0));
  PetscCall(GlobalMax(fab->comm, omega2, 2));
  PetscCall(BoundInfo(fab, &at));
  if (omega2[0] == 0 && fab->stats.rupture.segments > 0 && fab->step.omega_max > 0) {
    /* every segment that held a free crossing has broken (a strip one yarn wide): its pieces move free of any
       spring, and any te is stable for them; the te of the bound before goes on */
    PetscCall(PetscInfo(NULL, "load step %" PetscInt_FMT ": no stiffness left after %" PetscInt64_FMT
                              " segments broke: te %g s kept\n",
                        fab->load.load_step, (PetscInt64) fab->stats.rupture.segments, (double) fab->step.te));
    PetscFunctionReturn(0);
  }
  PetscCheck(omega2[0] > 0, fab->comm, PETSC_ERR_USER_INPUT,
             "no free crossing point has any stiffness: nothing to integrate (check -traction, -bending, -shear and "
             "the clamps)");
  fab->step.omega_max = PetscSqrtReal(omega2[0]);
  fab->step.te_bound  = (PaperSteps(fab) ? 1.0 : 2.0) / fab->step.omega_max;
  if (s->num.te_user > 0) {
    char scheme[64] = "a tear's damped scheme over the whole yarn law"; /* a tear's te: -te too */
    if (!fab->step.tear) PetscCall(PetscSNPrintf(scheme, sizeof scheme, "%s integrator", IntegratorNames[s->num.integrator]));
    PetscReal te_whole = 0; /* the bound over the whole yarn law, where it is below this state's */
    if (s->num.te_check && s->num.te_user > fab->step.te_bound) {
      /* refused: the message gives the bound over the whole yarn law at this shape of the fabric, which the yarns'
         straightening does not lower (this state's window does). The run stops: the window is not set back. */
      PetscReal whole[2];
      BoundRow  w;
      PetscCall(VecGetArrayRead(fab->state.Xl, &xl));
      WindowSet(p, r, 1);
      whole[0] = StableOmega2(p, xl, fab->grid.inv_m, s->spec.pull == PULL_WARP ? 0 : 1, &whole[1], &w);
      PetscCall(VecRestoreArrayRead(fab->state.Xl, &xl));
      PetscCall(GlobalMax(fab->comm, whole, 2));
      if (whole[0] > omega2[0]) te_whole = (PaperSteps(fab) ? 1.0 : 2.0) / PetscSqrtReal(whole[0]);
    }
    PetscCheck(!s->num.te_check || s->num.te_user <= fab->step.te_bound, fab->comm, PETSC_ERR_USER_INPUT,
               "-te %g s is above the stable bound %g s at load step %" PetscInt_FMT
               " (%s, omega_max = %g rad/s): use -te %g or less%s, or leave -te unset",
               (double) s->num.te_user, (double) fab->step.te_bound, fab->load.load_step, scheme,
               (double) fab->step.omega_max,
               (double) ((te_whole > 0 ? te_whole : fab->step.te_bound) * (1 - 1e-5)), /* printed, not above it */
               te_whole > 0 ? " (the bound over the whole yarn law at this shape of the fabric: this state's falls as the "
                       "yarns straighten; it may fall further as the fabric deforms, and a -te above it then stops the "
                       "run there)"
                     : "");
    fab->step.te = s->num.te_user;
  } else
    fab->step.te = (fab->step.tear ? s->num.te_safety_tear : s->num.te_safety) * fab->step.te_bound;
  PetscFunctionReturn(0);
}

/* damping: the paper's nu per point, plus a mass-proportional part c = 2 zeta omega_1 with
   omega_1 ~ pi omega_pull / (2 n) the slowest mode of the chain of n segments along the
   pull, omega_pull = 2 sqrt(k/m) its highest (from the pull-direction springs alone) */
static void SetDamping(Fabric fab, PetscReal omega2_pull)
{
  const Scene   *s = &fab->s;
  const PetscInt n = (s->spec.pull == PULL_WARP ? s->spec.nx : s->spec.ny) - 1;

  fab->step.omega1 = PETSC_PI * PetscSqrtReal(omega2_pull) / (2.0 * n);
  fab->step.damp_c = 2.0 * s->num.damping_ratio * fab->step.omega1;
}

PetscErrorCode StableStep(Fabric fab)
{
  const Scene    *s       = &fab->s;
  const PetscReal te_prev = fab->step.te; /* in use up to this state */
  PetscReal       omega2[2];

  PetscFunctionBeginUser;
  fab->step.window_grow = 0; /* each load step starts from the window's margin as set */
  PetscCall(StableBound(fab, omega2));
  fab->step.fire_dt    = fab->step.te; /* FIRE starts again at each stable step (each load step) */
  fab->step.fire_alpha = FIRE_ALPHA0;
  fab->step.fire_npos  = 0;
  SetDamping(fab, omega2[1]);
  if (s->num.te_measure) PetscCall(StableStepMeasure(fab, te_prev)); /* the true limit here (spectrum.c) */
  PetscFunctionReturn(0);
}

PetscErrorCode StableDamping(Fabric fab)
{
  const PetscScalar *xl;
  PetscReal          pull2;

  PetscFunctionBeginUser;
  PetscCall(HaloExchange(fab->grid.da, fab->state.X, fab->state.Xl));
  PetscCall(PetscLogEventBegin(EV_Bound, 0, 0, 0, 0));
  PetscCall(VecGetArrayRead(fab->state.Xl, &xl));
  pull2 = PullOmega2(&fab->grid.patch, xl, fab->grid.inv_m, fab->s.spec.pull == PULL_WARP ? 0 : 1);
  PetscCall(VecRestoreArrayRead(fab->state.Xl, &xl));
  PetscCall(PetscLogEventEnd(EV_Bound, 0, 0, 0, 0));
  PetscCall(GlobalMax(fab->comm, &pull2, 1));
  SetDamping(fab, pull2);
  if (fab->s.num.te_measure) { /* the bound and the true limit here, te kept (spectrum.c) */
    const PetscReal te = fab->step.te;
    PetscReal       omega2[2];
    PetscCall(StableBound(fab, omega2));
    fab->step.te = te;
    PetscCall(StableStepMeasure(fab, te));
  }
  PetscFunctionReturn(0);
}

/* A te step found a segment or crossing outside the window its bound covers: the bound again
   from this state, within the load step (the damping, the ramp and FIRE's state go on; FIRE's
   step never exceeds te) */
PetscErrorCode StableStepAgain(Fabric fab)
{
  PetscReal omega2[2];

  PetscFunctionBeginUser;
  PetscCall(StableBound(fab, omega2));
  fab->step.fire_dt = PetscMin(fab->step.fire_dt, fab->step.te);
  PetscFunctionReturn(0);
}

/* A state left the window within the load step. A bound costs about 8 te steps (a Gershgorin
   sweep with the law's tangent over the window); strains that leave the window again within
   WINDOW_GROW_BEFORE te steps double its margin (up to WINDOW_GROW_MAX times), so that a state
   whose strains move fast takes the bound a few times, not at every margin's worth of strain; a
   slower one keeps the margin as set (a wider window takes in stiffer parts of the law: a
   smaller te). A te the user set (-te) is only checked against the bound: its window never grows. */
#define WINDOW_GROW_BEFORE 64
static PetscErrorCode StableStepRebound(Fabric fab)
{
  PetscFunctionBeginUser;
  fab->step.window_grow = fab->s.num.te_user <= 0 && fab->stats.te_steps - fab->step.window_bound_at < WINDOW_GROW_BEFORE
                              ? PetscMin(fab->step.window_grow + 1, WINDOW_GROW_MAX)
                              : 0;
  PetscCall(StableStepAgain(fab));
  fab->stats.te_rebounds++;
  PetscFunctionReturn(0);
}

/* the statistics of one sweep: max |F|^2 and |v|^2 over free points, whether some |v|^2 is not
   finite, and the awake points' bounding box in the sweep's index (sleeping: a free point whose
   |F|^2 exceeds f2 or whose new |v|^2 exceeds v2max) */
typedef struct {
  PetscReal res2, v2;
  int       bad;                /* some |v|^2 is inf or NaN */
  PetscInt  awake_lo, awake_hi; /* first and one past the last awake index, or lo >= hi */
} SweepStats;

/* a row's statistics from its points' r2 (residual |F|^2, 0 at a fixed point) and w2 (new |v|^2),
   which the update loops store so that they vectorise: the maxima in four lanes (max is exact in
   any order: the values of one running max), the awake range only when sleeping */
FABRIC_WIDE static void RowTally(PetscInt n, const PetscReal *restrict r2, const PetscReal *restrict w2,
                     const PetscReal *restrict inv_m, PetscBool sleep, PetscReal f2, PetscReal v2max, SweepStats *st)
{
  PetscReal r[4] = {0, 0, 0, 0}, w[4] = {0, 0, 0, 0};
  int       bad[4] = {0, 0, 0, 0};
  PetscInt  k      = 0;

  for (; k + 4 <= n; k += 4)
    for (int l = 0; l < 4; l++) {
      r[l] = PetscMax(r[l], r2[k + l]);
      w[l] = PetscMax(w[l], w2[k + l]);
      bad[l] |= !(w2[k + l] <= PETSC_MAX_REAL);
    }
  for (; k < n; k++) {
    r[0] = PetscMax(r[0], r2[k]);
    w[0] = PetscMax(w[0], w2[k]);
    bad[0] |= !(w2[k] <= PETSC_MAX_REAL);
  }
  *st = (SweepStats){PetscMax(PetscMax(r[0], r[1]), PetscMax(r[2], r[3])),
                     PetscMax(PetscMax(w[0], w[1]), PetscMax(w[2], w[3])), bad[0] | bad[1] | bad[2] | bad[3], n, 0};
  if (sleep)
    for (k = 0; k < n; k++)
      if (inv_m[k] > 0 && (r2[k] > f2 || w2[k] > v2max)) {
        st->awake_lo = PetscMin(st->awake_lo, k);
        st->awake_hi = k + 1;
      }
}

/* the update loops: point k's new velocity and position, its r2 and w2 for RowTally */
FABRIC_WIDE static void IntegrateDamped(PetscInt n, PetscReal te, PetscReal c0, PetscReal nu, const PetscReal g[3],
                            const PetscReal *restrict mass, const PetscReal *restrict inv_m,
                            const PetscReal *restrict f, PetscReal *restrict x, PetscReal *restrict v,
                            PetscReal *restrict r2, PetscReal *restrict w2)
{
  for (PetscInt k = 0; k < n; k++) {
    const PetscReal im = inv_m[k], m = mass[k], c = c0 + nu * im;
    const PetscReal den = 1.0 / (2.0 + c * te), a = (2.0 - c * te) * den, b = 2.0 * te * im * den;
    const PetscReal Fx = f[3 * k] + m * g[0], Fy = f[3 * k + 1] + m * g[1], Fz = f[3 * k + 2] + m * g[2];
    const PetscReal vx = a * v[3 * k] + b * Fx, vy = a * v[3 * k + 1] + b * Fy, vz = a * v[3 * k + 2] + b * Fz;
    v[3 * k]     = vx;
    v[3 * k + 1] = vy;
    v[3 * k + 2] = vz;
    x[3 * k] += te * vx;
    x[3 * k + 1] += te * vy;
    x[3 * k + 2] += te * vz;
    w2[k] = vx * vx + vy * vy + vz * vz;
    r2[k] = im > 0 ? Fx * Fx + Fy * Fy + Fz * Fz : 0.0;
  }
}

FABRIC_WIDE static void IntegratePaper(PetscInt n, PetscReal te, PetscReal c0, PetscReal nu, const PetscReal g[3],
                           const PetscReal *restrict mass, const PetscReal *restrict inv_m,
                           const PetscReal *restrict f, PetscReal *restrict x, PetscReal *restrict v,
                           PetscReal *restrict xold, PetscReal *restrict vold, PetscReal *restrict r2s,
                           PetscReal *restrict w2s)
{
  for (PetscInt k = 0; k < n; k++) {
    const PetscReal im = inv_m[k], m = mass[k], c = c0 + nu * im;
    PetscReal       r2 = 0, w2 = 0;
    for (int d = 0; d < 3; d++) {
      const PetscReal F = f[3 * k + d] + m * g[d], Vn = v[3 * k + d], xn = x[3 * k + d];
      const PetscReal Vnew = vold[3 * k + d] + 2.0 * te * (F * im - c * Vn);
      vold[3 * k + d]      = Vn;
      v[3 * k + d]         = Vnew;
      x[3 * k + d]         = xold[3 * k + d] + 2.0 * te * Vn;
      xold[3 * k + d]      = xn;
      r2 += F * F;
      w2 += Vnew * Vnew;
    }
    r2s[k] = im > 0 ? r2 : 0.0;
    w2s[k] = w2;
  }
}

/* FIRE (Bitzek et al. 2006) with semi-implicit Euler, as FIRE 2.0 (Guenole et al. 2020): the
   velocities are first mixed towards the force, v <- cv v + cf F (cv = 1 - alpha,
   cf = alpha |v|/|F|, global norms), then v <- v + dt F/m, x <- x + dt v. */
FABRIC_WIDE static void IntegrateFire(PetscInt n, PetscReal dt, PetscReal cv, PetscReal cf, const PetscReal g[3],
                          const PetscReal *restrict mass, const PetscReal *restrict inv_m,
                          const PetscReal *restrict f, PetscReal *restrict x, PetscReal *restrict v,
                          PetscReal *restrict r2, PetscReal *restrict w2)
{
  for (PetscInt k = 0; k < n; k++) {
    const PetscReal im = inv_m[k], m = mass[k], b = dt * im;
    const PetscReal Fx = f[3 * k] + m * g[0], Fy = f[3 * k + 1] + m * g[1], Fz = f[3 * k + 2] + m * g[2];
    const PetscReal ex = im > 0 ? cf : 0.0; /* a fixed point keeps v = 0 */
    const PetscReal vx = cv * v[3 * k] + ex * Fx + b * Fx, vy = cv * v[3 * k + 1] + ex * Fy + b * Fy,
                    vz = cv * v[3 * k + 2] + ex * Fz + b * Fz;
    v[3 * k]     = vx;
    v[3 * k + 1] = vy;
    v[3 * k + 2] = vz;
    x[3 * k] += dt * vx;
    x[3 * k + 1] += dt * vy;
    x[3 * k + 2] += dt * vz;
    w2[k] = vx * vx + vy * vy + vz * vz;
    r2[k] = im > 0 ? Fx * Fx + Fy * Fy + Fz * Fz : 0.0;
  }
}


/* FIRE's sums on one row of n points, in one pass: the power F.v, |F|^2 and |v|^2 of each free
   point (times 0 at a fixed one, whose forces are finite), F = f + m g, quantised on the scales
   2^EXACT_LAG_BITS / inv_q[c] (comm.h) and summed, and their largest magnitudes, into part
   (products and integer operations: the loop vectorises). */
FABRIC_WIDE static void FireTerms(PetscInt n, const PetscReal g[3], const PetscReal *restrict mass,
                                  const PetscReal *restrict inv_m, const PetscReal *restrict f,
                                  const PetscReal *restrict v, const PetscReal inv_q[3], ExactPart *part)
{
  const PetscReal gx = g[0], gy = g[1], gz = g[2], qP = inv_q[0], qF = inv_q[1], qV = inv_q[2];
  int64_t         tP = part->top[0], tF = part->top[1], tV = part->top[2];

  for (PetscInt k0 = 0; k0 < n; k0 += EXACT_LAG_BLOCK) {
    const PetscInt k1 = PetscMin(n, k0 + EXACT_LAG_BLOCK);
    uint64_t       sP = 0, sF = 0, sV = 0;
    for (PetscInt k = k0; k < k1; k++) {
      const PetscReal m = mass[k];
      const PetscReal Fx = f[3 * k] + m * gx, Fy = f[3 * k + 1] + m * gy, Fz = f[3 * k + 2] + m * gz;
      const PetscReal vx = v[3 * k], vy = v[3 * k + 1], vz = v[3 * k + 2];
      const PetscReal w = inv_m[k] > 0 ? 1.0 : 0.0; /* a product, not a select per term: GCC vectorises it */
      const PetscReal P = (Fx * vx + Fy * vy + Fz * vz) * w, F2 = (Fx * Fx + Fy * Fy + Fz * Fz) * w;
      const PetscReal V2 = (vx * vx + vy * vy + vz * vz) * w;
      const int64_t   bP = AbsBits(P), bF = AbsBits(F2), bV = AbsBits(V2);
      sP += ExactLagTerm(P * qP);
      sF += ExactLagTerm(F2 * qF);
      sV += ExactLagTerm(V2 * qV);
      tP = bP > tP ? bP : tP;
      tF = bF > tF ? bF : tF;
      tV = bV > tV ? bV : tV;
    }
    part->sum[0] += (int64_t) sP;
    part->sum[1] += (int64_t) sF;
    part->sum[2] += (int64_t) sV;
  }
  part->top[0] = tP, part->top[1] = tF, part->top[2] = tV;
}

/* the smallest power of 2 >= x > 0 (x finite) */
static PetscReal PowerOfTwoAbove(PetscReal x)
{
  int             e;
  const PetscReal m = frexp(x, &e);
  return ldexp(1.0, m == 0.5 ? e - 1 : e);
}

/* FIRE's sums over the owned points of box on the scales c->fire_scale, into part (global) */
static PetscErrorCode FireSums(Fabric fab, const PetscInt box[4], const PetscScalar *v, const PetscScalar *f,
                               ExactPart *part)
{
  const Patch     *p = &fab->grid.patch;
  const PetscReal *g = fab->load.gravity_now, *scale = fab->step.fire_scale;
  PetscReal        inv_q[3];
  ExactPart        local;

  PetscFunctionBeginUser;
  memset(&local, 0, sizeof local);
  for (int c = 0; c < 3; c++) inv_q[c] = scale[c] > 0 ? ldexp(1.0, EXACT_LAG_BITS) / scale[c] : 0.0;
  for (PetscInt j = box[2]; j < box[3]; j++) {
    const PetscInt k0 = (j - p->ys) * p->xm + (box[0] - p->xs);
    FireTerms(box[1] - box[0], g, fab->grid.mass + k0, fab->grid.inv_m + k0, f + 3 * k0, v + 3 * k0, inv_q, &local);
  }
  PetscCall(GlobalExactParts(fab->comm, 3, &local, part));
  PetscFunctionReturn(0);
}

/* FIRE's decision for this te step, from the forces just computed on box (F) and the velocities:
   the global power P = sum F.v and the norms |F|, |v| over free points, exact sums (the same on
   any number of ranks). Sets the step and the mixing (cv, cf) the sweep applies.
   The sums take one pass on the scales the last te step's maxima set (4 times the largest term,
   up to a power of 2); where the largest term came out above its scale or below 2^-FIRE_SCALE_SLACK
   of it (the terms' resolution 2^(FIRE_SCALE_SLACK - EXACT_LAG_BITS) of it at worst), or at the
   first te step, a second pass on the scale of this step's largest. The scales are in the
   checkpoint, so a restart sums as the run it continues. */
#define FIRE_SCALE_SLACK 12
#define FIRE_SCALE_TINY  ldexp(1.0, -900) /* a largest term below: the sum is taken as 0 */
#define FIRE_SCALE_HUGE  ldexp(1.0, 1000) /* above: no scale (the run is blowing up; its watch stops it) */
static PetscErrorCode FirePower(Fabric fab, const PetscInt box[4], PetscScalar *x, PetscScalar *v, const PetscScalar *f,
                                PetscReal *cv, PetscReal *cf)
{
  const Patch *p = &fab->grid.patch;
  StepControl *c = &fab->step;
  PetscReal    sum[3], top[3];
  ExactPart    part;
  PetscBool    again = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(FireSums(fab, box, v, f, &part));
  for (int q = 0; q < 3; q++) {
    memcpy(&top[q], &part.top[q], sizeof top[q]);
    if (top[q] >= FIRE_SCALE_TINY && top[q] <= FIRE_SCALE_HUGE &&
        !(top[q] <= c->fire_scale[q] && top[q] >= ldexp(c->fire_scale[q], -FIRE_SCALE_SLACK))) {
      c->fire_scale[q] = PowerOfTwoAbove(top[q]);
      again            = PETSC_TRUE;
    }
  }
  if (again) {
    ExactPart redo;
    PetscCall(FireSums(fab, box, v, f, &redo));
    for (int q = 0; q < 3; q++) part.sum[q] = redo.sum[q];
  }
  for (int q = 0; q < 3; q++) {
    if (!(top[q] <= FIRE_SCALE_HUGE)) sum[q] = top[q]; /* NaN, Inf or huge: the te step's watch stops the run */
    else if (top[q] < FIRE_SCALE_TINY) sum[q] = 0.0;
    else {
      sum[q]           = (PetscReal) part.sum[q] * ldexp(c->fire_scale[q], -EXACT_LAG_BITS);
      c->fire_scale[q] = PowerOfTwoAbove(4.0 * top[q]); /* the next te step's */
    }
  }
  if (!(sum[2] > 0)) /* at rest: nothing to mix, nothing to judge */
    *cv = 1.0, *cf = 0.0;
  else if (sum[0] > 0) {
    if (++c->fire_npos > FIRE_NMIN) {
      c->fire_dt = PetscMin(FIRE_FINC * c->fire_dt, c->te);
      c->fire_alpha *= FIRE_FALPHA;
    }
    *cv = 1.0 - c->fire_alpha;
    *cf = sum[1] > 0 ? c->fire_alpha * PetscSqrtReal(sum[2] / sum[1]) : 0.0;
  } else { /* uphill: half a step back, stop, a smaller step */
    for (PetscInt j = box[2]; j < box[3]; j++)
        for (PetscInt i = box[0]; i < box[1]; i++) {
          const PetscInt k = (j - p->ys) * p->xm + (i - p->xs);
          for (int d = 0; d < 3; d++) x[3 * k + d] -= 0.5 * c->fire_dt * v[3 * k + d], v[3 * k + d] = 0;
        }
    c->fire_npos  = 0;
    c->fire_dt    = PetscMax(FIRE_FDEC * c->fire_dt, FIRE_DTMIN * c->te);
    c->fire_alpha = FIRE_ALPHA0;
    c->fire_stops++;
    *cv = 1.0, *cf = 0.0;
  }
  PetscFunctionReturn(0);
}

/* The kinetic energy peaked between the last two te steps: the quadratic fit through the last
   three states puts the peak at x - 1.5 te v + 0.5 te^2 F/m (Barnes). Resetting the velocities
   where the points are instead, half a step past the peak, feeds the chain energy at every reset;
   near the stable step that runs away (docs/stability.md). */
static PetscErrorCode StepBackToPeak(Fabric fab, const PetscInt box[4], const PetscScalar *v)
{
  const PetscReal    te = fab->step.te, *g = fab->load.gravity_now;
  const Patch       *p  = &fab->grid.patch;
  const PetscScalar *f;
  PetscScalar       *x;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(fab->state.X, &x));
  PetscCall(VecGetArrayRead(fab->state.F, &f));
  for (PetscInt j = box[2]; j < box[3]; j++) /* the points this te step moved: the front's and sleeping's box */
    for (PetscInt i = box[0]; i < box[1]; i++) {
      const PetscInt  k  = (j - p->ys) * p->xm + (i - p->xs);
      const PetscReal im = fab->grid.inv_m[k], m = fab->grid.mass[k];
      if (!(im > 0)) continue;
      for (int d = 0; d < 3; d++)
        x[3 * k + d] -= 1.5 * te * v[3 * k + d] - 0.5 * te * te * (f[3 * k + d] + m * g[d]) * im;
    }
  PetscCall(VecRestoreArrayRead(fab->state.F, &f));
  PetscCall(VecRestoreArray(fab->state.X, &x));
  PetscFunctionReturn(0);
}

/* Kinetic damping (Cundall; Barnes' dynamic relaxation): the total kinetic energy
   K = sum m |v|^2 / 2 grows while the structure falls towards its balance and drops once it
   has passed it; at that peak all velocities are set to zero, and the motion starts again
   from there, nearer to rest. It needs no tuning to the spectrum (viscous damping that is
   critical for the fastest of the slow modes overdamps the slowest ones). K feeds back into
   the positions, so it is an exact sum (GlobalSumsExact): the same on any number of ranks.
   KineticTerms puts each point's energy in ke_terms and their local max in *scale, which the te
   step's max-reduction makes global; KineticDamping then takes the sum (one reduction). */
static void KineticTerms(Fabric fab, const PetscScalar *v, PetscReal *scale)
{
  for (PetscInt k = 0; k < fab->grid.nloc; k++)
    fab->step.ke_terms[k] = fab->grid.inv_m[k] > 0
                                ? 0.5 * fab->grid.mass[k] *
                                      (v[3 * k] * v[3 * k] + v[3 * k + 1] * v[3 * k + 1] + v[3 * k + 2] * v[3 * k + 2])
                                : 0.0;
  ExactSumScales(1, fab->step.ke_terms, fab->grid.nloc, scale);
}

static PetscErrorCode KineticDamping(Fabric fab, const PetscInt box[4], PetscReal scale)
{
  PetscScalar *v;
  PetscReal    ke;

  PetscFunctionBeginUser;
  PetscCall(GlobalSumsExactScaled(fab->comm, 1, fab->step.ke_terms, fab->grid.nloc, &scale, &ke));
  PetscCall(VecGetArray(fab->state.V, &v));
  if (ke < fab->step.ke_prev) { /* past the peak: back to it (MODEL.md 15), and start again from rest there */
    PetscCall(StepBackToPeak(fab, box, v));
    for (PetscInt k = 0; k < 3 * fab->grid.nloc; k++) v[k] = 0;
    fab->step.ke_prev = 0;
    fab->step.ke_resets++;
  } else
    fab->step.ke_prev = ke;
  PetscCall(VecRestoreArray(fab->state.V, &v));
  PetscFunctionReturn(0);
}

/* An instability's likely cause, for its message (collective; "" if none is known): a point load that by
   itself moves its crossing farther than the fabric's size in one te step (no yarn holds that); yarns
   too soft to carry the fabric's weight, at a stable te with no body to rest on; or the
   paper's scheme (MODEL.md eq. 10), which steps the damping c = 2 zeta omega_1 + nu/m by a central
   difference over 2 te, whose spurious root grows by a factor of about 1 + c te per te step (c te > 1:
   a runaway within te steps) */
static PetscErrorCode InstabilityCause(Fabric fab, char *cause, size_t len)
{
  PetscReal inv_m = 0, inv_m_load = fab->grid.load_index >= 0 ? fab->grid.inv_m[fab->grid.load_index] : 0;

  PetscFunctionBeginUser;
  cause[0] = 0;
  for (PetscInt k = 0; k < fab->grid.nloc; k++) inv_m = PetscMax(inv_m, fab->grid.inv_m[k]);
  PetscCall(GlobalMax(fab->comm, &inv_m, 1));
  PetscCall(GlobalMax(fab->comm, &inv_m_load, 1)); /* the rank that holds the loaded crossing's */
  {
    const PetscReal *P = fab->s.load.point_load, te2 = fab->step.te * fab->step.te,
                    load = fab->load.load_factor * PetscSqrtReal(P[0] * P[0] + P[1] * P[1] + P[2] * P[2]);
    if (load * inv_m_load * te2 > fab->grid.extent) {
      PetscCall(PetscSNPrintf(cause, len,
                              "; the point load (-point_load_N, %g N at this load step) alone moves its crossing %g m "
                              "in one te step, more than the fabric's size: lower -point_load_N",
                              (double) load, (double) (load * inv_m_load * te2)));
      PetscFunctionReturn(0);
    }
    if (load * inv_m_load * te2 > PetscMin(fab->grid.patch.ax, fab->grid.patch.ay)) { /* a soft de-crimping branch
                                                                                          sets te, the load's jump
                                                                                          lands on the stiff one */
      PetscCall(PetscSNPrintf(cause, len,
                              "; the point load (-point_load_N, %g N at this load step) moves its crossing %g m in one "
                              "te step, more than a yarn spacing (%g m): past the yarn law's soft part (de-crimping) "
                              "onto its stiff one, whose stable step is shorter; %sa smaller -te_safety, or -solver "
                              "static",
                              (double) load, (double) (load * inv_m_load * te2),
                              (double) PetscMin(fab->grid.patch.ax, fab->grid.patch.ay),
                              fab->s.load.load_steps < MAX_LOAD_STEPS ? "more load steps (-load_steps), " : ""));
      PetscFunctionReturn(0);
    }
  }
  if (fab->step.te <= fab->step.te_bound && !fab->s.bodies.plane && fab->s.bodies.pedestal_radius == 0 &&
      fab->s.bodies.sphere_radius == 0) { /* yarns that cannot carry the fabric's own weight (no body does): a yarn
                                             as long as the fabric, hung by its end, stretched by 100 % or more */
    const PetscReal *g = fab->load.gravity_now, gmag = PetscSqrtReal(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    const YarnLaw   *y[2] = {&fab->s.yarns.warp, &fab->s.yarns.weft};
    for (int f = 0; f < 2; f++) {
      const PetscReal w = y[f]->mu * (1.0 + y[f]->crimp) * gmag * fab->grid.extent; /* N */
      if (w > y[f]->EA) {
        PetscCall(PetscSNPrintf(cause, len,
                                "; the %s yarns cannot carry the fabric's own weight: one as long as the fabric (%g m) "
                                "weighs %g N under -gravity (%g m/s^2 at this load step), %g times their stiffness EA "
                                "(%g N); lower -gravity or give stiffer yarns",
                                y[f]->name, (double) fab->grid.extent, (double) w, (double) gmag, (double) (w / y[f]->EA),
                                (double) y[f]->EA));
        PetscFunctionReturn(0);
      }
    }
  }
  if (!PaperSteps(fab) || (fab->s.num.nu == 0 && fab->step.damp_c == 0)) PetscFunctionReturn(0);
  PetscCall(PetscSNPrintf(cause, len,
                          "; -integrator paper steps the damping by a central difference whose spurious mode grows by a "
                          "factor of about 1 + c te per te step: with -damping_ratio %g and -nu %g N s/m, c te = %g at the "
                          "lightest crossing; use -integrator fire or damped (more damping makes it grow faster)",
                          (double) fab->s.num.damping_ratio, (double) fab->s.num.nu,
                          (double) ((fab->step.damp_c + fab->s.num.nu * inv_m) * fab->step.te)));
  PetscFunctionReturn(0);
}

/* The velocities became NaN or Inf (or their |v|^2 overflowed): name the first crossing (in the
   grid's natural order) where they did, and stop. */
static PetscErrorCode StopNonFinite(Fabric fab)
{
  const Patch       *p = &fab->grid.patch;
  const PetscScalar *v;
  PetscReal          first = -(PetscReal) PETSC_MAX_INT; /* minus the first global index: a max-reduction */
  char               cause[320];

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(fab->state.V, &v));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) /* RowTally's test: |v|^2 not finite (a finite v can overflow it) */
    if (!(v[3 * k] * v[3 * k] + v[3 * k + 1] * v[3 * k + 1] + v[3 * k + 2] * v[3 * k + 2] <= PETSC_MAX_REAL)) {
      const PetscInt i = p->xs + k % p->xm, j = p->ys + k / p->xm;
      first = PetscMax(first, -(PetscReal) (j * p->nx + i));
      break;
    }
  PetscCall(VecRestoreArrayRead(fab->state.V, &v));
  PetscCall(GlobalMax(fab->comm, &first, 1));
  PetscCall(InstabilityCause(fab, cause, sizeof cause));
  SETERRQ(fab->comm, PETSC_ERR_FP,
          "numerical instability at load step %" PetscInt_FMT ", te step %" PetscInt64_FMT
          " of the run: velocities became NaN, Inf or too large to square, first at crossing (%" PetscInt_FMT ", %" PetscInt_FMT
          ") (te = %g s, stable bound %g s)%s",
          fab->load.load_step, fab->stats.te_steps, (PetscInt) (-first) % p->nx, (PetscInt) (-first) / p->nx,
          (double) fab->step.te, (double) fab->step.te_bound, cause);
}

/* One te step: halo exchange, forces and integration on the points the front and sleeping
   leave to compute, then the global balance test and the stability watch (one max-reduction,
   which also carries the awake box and, with kinetic damping, the scale of its exact sum). Stops
   with an error on NaN, Inf or runaway motion. */
PetscErrorCode TimeStep(Fabric fab, StepStats *out)
{
  const Scene    *s = &fab->s;
  const Patch    *p = &fab->grid.patch;
  PetscReal       tension_max, red[9];
  PetscInt        gbox[4], box[4];
  SweepStats      all = {0, 0, 0, 0, 0};
  PetscScalar    *x, *v, *f, *xold = NULL, *vold = NULL;
  const PetscBool sleep    = s->num.sleep_tol > 0;
  const PetscReal scale    = PetscMax(fab->step.last.tension_max, fab->step.force_floor);
  const PetscReal sleep_f2 = sleep ? PetscSqr(s->num.sleep_tol * scale) : PETSC_MAX_REAL,
                  sleep_v2 =
                      sleep ? PetscSqr(s->num.speed_tol * s->num.sleep_tol / s->num.balance_tol) : PETSC_MAX_REAL;
  PetscInt alo = PETSC_MAX_INT, ahi = -1, ajlo = PETSC_MAX_INT, ajhi = -1;
  /* a tear is dynamics: the damped scheme, whatever relaxes the load steps */
  const PetscBool fire  = s->num.integrator == INTEGRATOR_FIRE && !fab->step.tear;
  const PetscBool paper = PaperSteps(fab);
  PetscReal       cv = 1, cf = 0, ke_scale = 0;
  const PetscBool kinetic = s->num.kinetic_damping && !fab->step.tear;
  PetscInt        nred    = sleep ? 8 : 4;

  PetscFunctionBeginUser;
  fab->stats.point_updates += FrontStepBox(fab, gbox, box);
  PetscCall(ComputeForces(fab, box, &tension_max));
  PetscCall(PetscLogEventBegin(EV_Integrate, 0, 0, 0, 0));
  PetscCall(VecGetArray(fab->state.X, &x));
  PetscCall(VecGetArray(fab->state.V, &v));
  PetscCall(VecGetArray(fab->state.F, &f));
  if (paper) {
    PetscCall(VecGetArray(fab->state.Xold, &xold));
    PetscCall(VecGetArray(fab->state.Vold, &vold));
  }
  if (fire) PetscCall(FirePower(fab, box, x, v, f, &cv, &cf));
  for (PetscInt j = box[2]; j < box[3]; j++) {
    const PetscInt k0 = (j - p->ys) * p->xm + (box[0] - p->xs), n = box[1] - box[0];
    PetscReal     *r2 = fab->step.tally_rows, *w2 = r2 + p->xm;
    SweepStats     st;
    if (fire)
      IntegrateFire(n, fab->step.fire_dt, cv, cf, fab->load.gravity_now, fab->grid.mass + k0, fab->grid.inv_m + k0,
                    f + 3 * k0, x + 3 * k0, v + 3 * k0, r2, w2);
    else if (paper)
      IntegratePaper(n, fab->step.te, fab->step.damp_c, s->num.nu, fab->load.gravity_now, fab->grid.mass + k0,
                     fab->grid.inv_m + k0, f + 3 * k0, x + 3 * k0, v + 3 * k0, xold + 3 * k0, vold + 3 * k0, r2, w2);
    else
      IntegrateDamped(n, fab->step.te, fab->step.damp_c, s->num.nu, fab->load.gravity_now, fab->grid.mass + k0,
                      fab->grid.inv_m + k0, f + 3 * k0, x + 3 * k0, v + 3 * k0, r2, w2);
    RowTally(n, r2, w2, fab->grid.inv_m + k0, sleep, sleep_f2, sleep_v2, &st);
    all.res2 = PetscMax(all.res2, st.res2);
    all.v2   = PetscMax(all.v2, st.v2);
    all.bad |= st.bad;
    if (sleep) {
      if (st.awake_lo < st.awake_hi) {
        alo = PetscMin(alo, box[0] + st.awake_lo), ahi = PetscMax(ahi, box[0] + st.awake_hi);
        ajlo = PetscMin(ajlo, j), ajhi = j + 1;
      }
    }
  }
  if (kinetic) KineticTerms(fab, v, &ke_scale);
  if (xold) {
    PetscCall(VecRestoreArray(fab->state.Xold, &xold));
    PetscCall(VecRestoreArray(fab->state.Vold, &vold));
  }
  PetscCall(VecRestoreArray(fab->state.F, &f));
  PetscCall(VecRestoreArray(fab->state.V, &v));
  PetscCall(VecRestoreArray(fab->state.X, &x));
  PetscCall(PetscLogEventEnd(EV_Integrate, 0, 0, 0, 0));

  red[0] = all.res2;
  red[1] = all.v2;
  red[2] = tension_max;
  red[3] = all.bad ? 2.0 : p->left_window ? 1.0 : 0.0; /* not finite; out of te's window */
  red[4] = -(PetscReal) alo, red[5] = (PetscReal) ahi, red[6] = -(PetscReal) ajlo,
  red[7] = (PetscReal) ajhi; /* awake box */
  if (kinetic) red[nred++] = ke_scale;
  PetscCall(GlobalMax(fab->comm, red, nred));
  if (sleep) {
    fab->front.awake_box[0] = (PetscInt) -red[4], fab->front.awake_box[1] = (PetscInt) red[5];
    fab->front.awake_box[2] = (PetscInt) -red[6], fab->front.awake_box[3] = (PetscInt) red[7];
  }
  fab->stats.te_steps++;
  fab->load.elapsed += fab->step.te; /* the te of this step (a rebound below sets the next one's) */
  if (red[3] == 2.0) PetscCall(StopNonFinite(fab));
  out->speed       = PetscSqrtReal(red[1]);
  out->tension_max = red[2];
  out->residual    = PetscSqrtReal(red[0]) / PetscMax(red[2], fab->step.force_floor);
  if (!(out->speed * fab->step.te <= fab->grid.extent)) { /* every rank: the speed is reduced */
    char cause[512];
    PetscCall(InstabilityCause(fab, cause, sizeof cause));
    SETERRQ(fab->comm, PETSC_ERR_FP,
            "numerical instability at load step %" PetscInt_FMT ", te step %" PetscInt64_FMT
            " of the run: runaway motion, a point moved %g m in one step, more than the fabric's size %g m (te = %g s, stable "
            "bound %g s)%s",
            fab->load.load_step, fab->stats.te_steps, (double) (out->speed * fab->step.te), (double) fab->grid.extent,
            (double) fab->step.te, (double) fab->step.te_bound, cause);
  }
  if (kinetic) PetscCall(KineticDamping(fab, box, red[nred - 1]));
  out->balanced  = (out->residual <= s->num.balance_tol && out->speed <= s->num.speed_tol &&
                   fab->load.ramp_done >= fab->load.ramp_steps)
                       ? PETSC_TRUE
                       : PETSC_FALSE;
  fab->step.last = *out;
  if (red[3] == 1.0) PetscCall(StableStepRebound(fab));
  PetscFunctionReturn(0);
}
