/* balance.c - the checks that end or stop the relaxation of a load step (MODEL.md 8, 15).
 *
 * The balance test per crossing. The test of every te step (integrate.c) compares the largest
 * free force with the largest yarn tension: it cannot see an imbalance where the forces are small,
 * a crossing governed by shear or bending (0.01 N) beside yarns at 1 N. Before a load step ends,
 * each free crossing's residual is compared with the sum of the magnitudes of its own force terms,
 * on every crossing (sleeping ones and those the front has not reached included).
 *
 * The energy watch. With nothing doing work on the fabric (the jaws and the sphere at rest, dead
 * loads, no friction), the damped schemes can only lose mechanical energy. Central differences
 * conserve H_n = Pi(x_n) + 1/2 sum m v(n-1/2).v(n+1/2) exactly on a linear system and let it fall
 * with damping; the paper's two leapfrog chains conserve Pi(u_n) + 1/2 sum m V(n-1).V(n+1). A
 * yarn law whose stiffness jumps breaks that conservation: a segment that crosses a kink within
 * a te step gains or loses energy, and at a low damping a ring can gain it step after step
 * (docs/stability.md). The watch measures H across one te step every ENERGY_WATCH_EVERY te steps
 * and stops the run when H has grown above its lowest by more than -energy_watch times the energy
 * the round released (its first H less its lowest) plus the largest kinetic energy seen: an
 * undamped run releases nothing, and H's kinetic part swings on a nonlinear chain. A ring the kink
 * feeds as fast as the damping drains it can hold its level, or rise slowly, below that bound: with
 * viscous damping, H falls whenever anything moves, so the watch also stops a run whose H has stayed
 * above its lowest (by more than rounding and ENERGY_WATCH_HELD_RISE of the energy in play) at
 * ENERGY_WATCH_HELD watched te steps in a row.
 * FIRE needs no watch: it stops all motion at the first te step whose power F.v is negative.
 */
#include "balance.h"
#include "bodies.h"
#include "comm.h"
#include "events.h"
#include "integrate.h"

#include <math.h>
#include <string.h>

#define ENERGY_WATCH_EVERY    256  /* te steps between two watched te steps */
#define ENERGY_WATCH_ROUNDING 1e-9 /* a rise of H below this times the magnitudes it sums is rounding */
#define ENERGY_WATCH_HELD      32   /* watched te steps in a row with H above its lowest: a ring the kink feeds */
#define ENERGY_WATCH_HELD_RISE 1e-5 /* ... by more than this times the energy released + the largest kinetic */

/* the global index j nx + i of owned point k (k = (j - ys) xm + (i - xs)), -1 for none */
static PetscInt GlobalIndexOf(const Patch *p, PetscInt k)
{
  return k < 0 ? -1 : (p->ys + k / p->xm) * p->nx + p->xs + k % p->xm;
}

PetscErrorCode RelaxInfo(Fabric fab, PetscInt round, PetscInt n, const StepStats *st)
{
  const Patch       *p = &fab->grid.patch;
  const PetscReal    tol2 = PetscSqr(fab->s.num.speed_tol);
  const PetscInt     nl   = fab->grid.nloc;
  const PetscScalar *v;
  PetscBool          info;
  PetscReal          fast = -1, sum[4], *terms; /* sums of v_x^2, v_y^2, v_z^2 and of the points faster than -speed_tol */
  PetscInt           kfast = -1, where;

  PetscFunctionBeginUser;
  if (n < 1024 || (n & (n - 1))) PetscFunctionReturn(0);
  PetscCall(PetscInfoEnabled(PETSC_SMALLEST_CLASSID, &info)); /* PetscInfo(NULL, ...)'s class */
  if (!info) PetscFunctionReturn(0);
  PetscCall(PetscMalloc1((size_t) 4 * nl, &terms)); /* size_t: 4 nl passes 2^31 above 537 M points a rank */
  PetscCall(VecGetArrayRead(fab->state.V, &v));
  for (PetscInt k = 0; k < nl; k++) {
    const PetscReal *u = v + 3 * k, s2 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2], w = fab->grid.inv_m[k] > 0 ? 1.0 : 0.0;
    for (int d = 0; d < 3; d++) terms[(size_t) d * nl + k] = w * u[d] * u[d];
    terms[(size_t) 3 * nl + k] = s2 > tol2 ? w : 0.0;
    if (w > 0 && s2 > fast) fast = s2, kfast = k;
  }
  PetscCall(VecRestoreArrayRead(fab->state.V, &v));
  PetscCall(GlobalSumsExact(fab->comm, 4, terms, nl, sum)); /* exact: the same shares on any number of ranks */
  PetscCall(PetscFree(terms));
  where = GlobalIndexOf(p, kfast);
  PetscCall(GlobalArgMax(fab->comm, &fast, &where));
  {
    const PetscReal all = PetscMax(sum[0] + sum[1] + sum[2], PETSC_MIN_REAL);
    PetscCall(PetscInfo(NULL,
                        "load step %" PetscInt_FMT ", round %" PetscInt_FMT " at load factor %.9g, te step %" PetscInt_FMT
                        " of the round: residual %.3g, speed %.3g m/s (-speed_tol %g), the fastest at crossing (%" PetscInt_FMT
                        ", %" PetscInt_FMT "); %.0f free crossings faster than -speed_tol; sum |v|^2 along x %.2f, y %.2f, z %.2f\n",
                        fab->load.load_step, round, (double) fab->load.load_factor, n, (double) st->residual,
                        (double) st->speed, (double) fab->s.num.speed_tol, where < 0 ? -1 : where % p->nx,
                        where < 0 ? -1 : where / p->nx, (double) sum[3], (double) (sum[0] / all), (double) (sum[1] / all),
                        (double) (sum[2] / all)));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode BalanceCrossings(Fabric fab, BalanceCheck *c)
{
  const Patch       *p = &fab->grid.patch;
  const PetscReal   *g = fab->load.gravity_now, tol = fab->s.num.balance_tol;
  const PetscScalar *f, *xl;
  PetscReal         *scale, *fint, tmax, best = 0, red[5];
  PetscInt           kbest = -1, where, lo = PETSC_MAX_INT, hi = -1, jlo = PETSC_MAX_INT, jhi = -1;
  PetscReal          r2max = 0;
  const PetscInt     all[4] = {p->xs, p->xs + p->xm, p->ys, p->ys + p->ym};

  PetscFunctionBeginUser;
  PetscCall(ComputeForces(fab, NULL, &tmax)); /* every crossing, at these positions; halo into Xl */
  PetscCall(PetscLogEventBegin(EV_Check, 0, 0, 0, 0));
  PetscCall(PetscMalloc2(fab->grid.nloc, &scale, 3 * fab->grid.nloc, &fint));
  PetscCall(VecGetArrayRead(fab->state.Xl, &xl));
  InternalForceMagnitudes(&fab->grid.patch, xl, all, fint, scale); /* the internal forces and their terms' magnitudes */
  PetscCall(VecRestoreArrayRead(fab->state.Xl, &xl));
  PetscCall(GlobalMax(fab->comm, &tmax, 1));
  {
    const PetscReal floor = PetscMax(fab->step.force_floor, fab->s.num.balance_floor * tmax);
    const PetscReal big2  = PetscSqr(tol * PetscMax(tmax, fab->step.force_floor)); /* fails the test of every te step */
    PetscCall(VecGetArrayRead(fab->state.F, &f));
    for (PetscInt k = 0; k < fab->grid.nloc; k++) {
      const PetscReal m = fab->grid.mass[k];
      PetscReal       load[3] = {0, 0, 0}, R2 = 0, C2 = 0, L2 = 0, W2 = 0, ratio;
      if (!(fab->grid.inv_m[k] > 0)) continue;
      if (k == fab->grid.load_index)
        for (int d = 0; d < 3; d++) load[d] = fab->load.load_factor * fab->s.load.point_load[d];
      for (int d = 0; d < 3; d++) {
        const PetscReal R = f[3 * k + d] + m * g[d], contact = f[3 * k + d] - fint[3 * k + d] - load[d];
        R2 += R * R, C2 += contact * contact, L2 += load[d] * load[d], W2 += m * g[d] * m * g[d];
      }
      ratio = PetscSqrtReal(R2) /
              PetscMax(scale[k] + PetscSqrtReal(C2) + PetscSqrtReal(L2) + PetscSqrtReal(W2), floor);
      if (ratio > best) best = ratio, kbest = k; /* the first in the patch's order on a tie */
      r2max = PetscMax(r2max, R2);
      if (ratio > tol || R2 > big2) {
        const PetscInt i = p->xs + k % p->xm, j = p->ys + k / p->xm;
        lo = PetscMin(lo, i), hi = PetscMax(hi, i + 1), jlo = PetscMin(jlo, j), jhi = PetscMax(jhi, j + 1);
      }
    }
    PetscCall(VecRestoreArrayRead(fab->state.F, &f));
  }
  PetscCall(PetscFree2(scale, fint));
  where = GlobalIndexOf(p, kbest);
  PetscCall(GlobalArgMax(fab->comm, &best, &where)); /* the lowest global index among the worst */
  red[0] = -(PetscReal) lo, red[1] = (PetscReal) hi, red[2] = -(PetscReal) jlo, red[3] = (PetscReal) jhi, red[4] = r2max;
  PetscCall(GlobalMax(fab->comm, red, 5));
  c->worst   = best;
  c->i       = where >= 0 ? where % p->nx : -1;
  c->j       = where >= 0 ? where / p->nx : -1;
  c->largest = PetscSqrtReal(red[4]) / PetscMax(tmax, fab->step.force_floor);
  c->box[0] = (PetscInt) -red[0], c->box[1] = (PetscInt) red[1], c->box[2] = (PetscInt) -red[2],
  c->box[3] = (PetscInt) red[3];
  PetscCall(PetscLogEventEnd(EV_Check, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode BallPassedCheck(Fabric fab)
{
  const Patch       *p = &fab->grid.patch;
  const PetscScalar *x, *x0;
  PetscReal          behind = 0, c[3], c0[3];
  PetscInt           where  = -1;
  const Body        *b      = NULL;

  PetscFunctionBeginUser;
  for (PetscInt q = 0; q < fab->bodies.n; q++)
    if (fab->bodies.body[q].kind == BODY_SPHERE) b = &fab->bodies.body[q];
  if (!b || fab->stats.broken_any) PetscFunctionReturn(0);
  BodyPosition(b, fab->load.travel_now, c);
  BodyPosition(b, 0, c0);
  PetscCall(VecGetArrayRead(fab->state.X, &x));
  PetscCall(VecGetArrayRead(fab->grid.X0, &x0));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) {
    PetscReal r[3], along = 0, along0 = 0, r2 = 0;
    if (!(fab->grid.inv_m[k] > 0)) continue;
    for (int d = 0; d < 3; d++) r[d] = x[3 * k + d] - c[d], along += r[d] * b->dir[d], r2 += r[d] * r[d];
    for (int d = 0; d < 3; d++) along0 += (x0[3 * k + d] - c0[d]) * b->dir[d];
    if (along0 > 0 && -along > behind && r2 - along * along < b->radius * b->radius) /* ahead at rest, now behind */
      behind = -along, where = GlobalIndexOf(p, k);
  }
  PetscCall(VecRestoreArrayRead(fab->grid.X0, &x0));
  PetscCall(VecRestoreArrayRead(fab->state.X, &x));
  PetscCall(GlobalArgMax(fab->comm, &behind, &where));
  {
    const PetscBool breaks = fab->s.yarns.warp.break_ey > 0 || fab->s.yarns.weft.break_ey > 0 ? PETSC_TRUE : PETSC_FALSE;
    PetscCheck(where < 0, fab->comm, PETSC_ERR_NOT_CONVERGED,
               "the ball has passed through the fabric at load step %" PetscInt_FMT " (travel %g mm): crossing (%" PetscInt_FMT
               ", %" PetscInt_FMT ") lies %g mm behind its centre, within its silhouette. Contact acts on the crossings "
               "alone, and yarns that %s (-warp_break_pct %g, -weft_break_pct %g) let the ball slip between them once "
               "strained far past a real yarn's strength: %sa shorter -sphere_travel_mm or a stiffer "
               "-contact_stiffness_N_m (now %g N/m)",
               fab->load.load_step, (double) (1e3 * fab->load.travel_now), where % p->nx, where / p->nx,
               (double) (1e3 * behind), breaks ? "have not broken" : "do not break",
               (double) (100 * fab->s.yarns.warp.break_ey), (double) (100 * fab->s.yarns.weft.break_ey),
               breaks ? "" : "give the yarns a breaking strain, ", (double) b->k);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode PointLoadHeldCheck(Fabric fab)
{
  const Scene     *s = &fab->s;
  const Patch     *p = &fab->grid.patch;
  const PetscReal *P = s->load.point_load;
  const PetscInt   i = s->load.load_at[0], j = s->load.load_at[1];
  PetscReal        loose[2] = {0, 0}; /* every segment at it broken; its distance from its place at rest, m */
  char             why[160];

  PetscFunctionBeginUser;
  if (!fab->stats.broken_any || (P[0] == 0 && P[1] == 0 && P[2] == 0)) PetscFunctionReturn(0);
  if (fab->grid.load_index >= 0) { /* this rank owns the loaded crossing: its four segments are in its patch */
    const PetscInt     k = (j - p->gys) * p->gxm + (i - p->gxs), w = p->gxm, q = fab->grid.load_index; /* ghosted, owned */
    const PetscScalar *x, *x0;
    PetscBool          held = PETSC_FALSE;
    if (i > p->gxs && p->exists[k - 1] && !p->broken_x[k - 1]) held = PETSC_TRUE;
    if (i + 1 < p->gxs + p->gxm && p->exists[k + 1] && !p->broken_x[k]) held = PETSC_TRUE;
    if (j > p->gys && p->exists[k - w] && !p->broken_y[k - w]) held = PETSC_TRUE;
    if (j + 1 < p->gys + p->gym && p->exists[k + w] && !p->broken_y[k]) held = PETSC_TRUE;
    PetscCall(VecGetArrayRead(fab->state.X, &x));
    /* a plane or a pedestal the load presses it onto may hold it (a tear's te steps end before the crossing lands
       on one below it): a plane facing the load, a pedestal's top under the crossing with the load downwards. The
       square net's distance check below stays. */
    for (PetscInt b = 0; b < fab->bodies.n; b++) {
      const Body *body = &fab->bodies.body[b];
      if (body->kind == BODY_PLANE && P[0] * body->dir[0] + P[1] * body->dir[1] + P[2] * body->dir[2] < 0) held = PETSC_TRUE;
      if (body->kind == BODY_PEDESTAL && P[2] < 0 &&
          PetscSqr(x[3 * q] - body->ref[0]) + PetscSqr(x[3 * q + 1] - body->ref[1]) <= PetscSqr(body->radius + body->reach))
        held = PETSC_TRUE;
    }
    loose[0] = held ? 0.0 : 1.0;
    PetscCall(VecGetArrayRead(fab->grid.X0, &x0));
    loose[1] = PetscSqrtReal(PetscSqr(x[3 * q] - x0[3 * q]) + PetscSqr(x[3 * q + 1] - x0[3 * q + 1]) +
                             PetscSqr(x[3 * q + 2] - x0[3 * q + 2]));
    PetscCall(VecRestoreArrayRead(fab->grid.X0, &x0));
    PetscCall(VecRestoreArrayRead(fab->state.X, &x));
  }
  PetscCall(GlobalMax(fab->comm, loose, 2));
  if (s->test != TEST_SQUARE) loose[1] = 0; /* the square net measures that crossing's travel (a strip's pieces may fly) */
  if (loose[0] == 0 && loose[1] <= fab->grid.extent) PetscFunctionReturn(0);
  if (loose[1] > fab->grid.extent) /* a piece torn out with it: the crossing may still have segments, holding nothing */
    PetscCall(PetscSNPrintf(why, sizeof why, " and it has moved %g mm, farther than the fabric's size %g mm",
                            (double) (1e3 * loose[1]), (double) (1e3 * fab->grid.extent)));
  else why[0] = 0;
  SETERRQ(fab->comm, PETSC_ERR_NOT_CONVERGED,
          "the point load (-point_load_N %g,%g,%g) has torn its crossing (%" PetscInt_FMT ", %" PetscInt_FMT
          ") loose at load step %" PetscInt_FMT ": %s (-warp_break_pct %g, -weft_break_pct %g)%s; nothing holds it "
          "against the load: a smaller -point_load_N or stronger yarns",
          (double) P[0], (double) P[1], (double) P[2], i, j, fab->load.load_step,
          loose[0] != 0 ? "every yarn segment at it has broken" : "yarns that held it have broken",
          (double) (100 * s->yarns.warp.break_ey), (double) (100 * s->yarns.weft.break_ey), why);
}

/* ------------------------------------------------------------------ the energy watch */

/* the watch applies: a damped scheme, not a tear, nothing doing work on the fabric */
static PetscBool WatchApplies(const Fabric fab)
{
  const Scene *s = &fab->s;
  return s->num.energy_watch > 0 && s->num.integrator != INTEGRATOR_FIRE && !fab->step.tear &&
                 fab->load.ramp_done >= fab->load.ramp_steps && !(s->bodies.friction_mu > 0)
             ? PETSC_TRUE
             : PETSC_FALSE;
}

void EnergyWatchReset(Fabric fab)
{
  fab->step.watch_checks = 0;
}

PetscErrorCode EnergyWatchBefore(Fabric fab, PetscInt n, PetscBool *due)
{
  PetscFunctionBeginUser;
  *due = WatchApplies(fab) && (n - 1) % ENERGY_WATCH_EVERY == 0 ? PETSC_TRUE : PETSC_FALSE;
  if (!*due) PetscFunctionReturn(0);
  if (!fab->state.watch_x) {
    PetscCall(VecDuplicate(fab->state.X, &fab->state.watch_x));
    PetscCall(VecDuplicate(fab->state.X, &fab->state.watch_v));
  }
  PetscCall(VecCopy(fab->state.X, fab->state.watch_x)); /* x_n (paper: u_n) */
  PetscCall(VecCopy(PaperSteps(fab) ? fab->state.Vold : fab->state.V,
                    fab->state.watch_v)); /* v(n-1/2) (paper: V(n-1)) */
  PetscFunctionReturn(0);
}

/* each owned crossing's part of Pi at positions X (up to a constant) into E[k]: the internal terms
   it owns, the bodies' penalty, minus the work of gravity; A[k]: the sum of those parts' magnitudes
   (the scale of Pi's rounding). Per crossing, in a fixed order: summed exactly over the ranks
   (GlobalPointSums), the watch is the same on any number of ranks. The point load's work, on one
   crossing and often the largest part, apart in load[0] (its magnitude load[1]): the exact sum
   quantises every part on the largest. */
static PetscErrorCode PotentialEnergy(Fabric fab, Vec X, PetscReal *E, PetscReal *A, PetscReal load[2])
{
  const Patch       *p = &fab->grid.patch;
  const PetscReal   *g = fab->load.gravity_now;
  const PetscScalar *xl, *x;
  PetscReal          c[BODY_KINDS][3];

  PetscFunctionBeginUser;
  PetscCall(HaloExchange(fab->grid.da, X, fab->state.Xl));
  PetscCall(VecGetArrayRead(fab->state.Xl, &xl));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) {
    const PetscInt i = p->xs + k % p->xm, j = p->ys + k / p->xm, own[4] = {i, i + 1, j, j + 1};
    E[k] = InternalEnergy(p, xl, own);
    A[k] = PetscAbsReal(E[k]);
  }
  PetscCall(VecRestoreArrayRead(fab->state.Xl, &xl));
  for (PetscInt q = 0; q < fab->bodies.n; q++) BodyPosition(&fab->bodies.body[q], fab->load.travel_now, c[q]);
  PetscCall(VecGetArrayRead(X, &x));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) {
    if (!(fab->grid.inv_m[k] > 0)) continue;
    for (int d = 0; d < 3; d++) E[k] -= fab->grid.mass[k] * g[d] * x[3 * k + d], A[k] += PetscAbsReal(fab->grid.mass[k] * g[d] * x[3 * k + d]);
    for (PetscInt q = 0; q < fab->bodies.n; q++) {
      PetscReal gb[3], Kb[9], eb = BodyEnergy(&fab->bodies.body[q], c[q], x + 3 * k, gb, Kb);
      E[k] += eb, A[k] += PetscAbsReal(eb);
    }
  }
  load[0] = load[1] = 0;
  if (fab->grid.load_index >= 0)
    for (int d = 0; d < 3; d++) {
      const PetscReal w = fab->load.load_factor * fab->s.load.point_load[d] * x[3 * fab->grid.load_index + d];
      load[0] -= w, load[1] += PetscAbsReal(w);
    }
  PetscCall(VecRestoreArrayRead(X, &x));
  PetscFunctionReturn(0);
}

/* The watch found the energy growing: name the crossing with the largest kinetic energy, its
   yarn segments' chord strains and the nearest kink of their yarn law, and stop. */
static PetscErrorCode StopPumping(Fabric fab, PetscInt n, PetscReal h0, PetscReal hmin, PetscReal h, PetscInt held)
{
  const Patch       *p = &fab->grid.patch;
  const PetscScalar *v, *xl;
  PetscReal          best = -1, info[4] = {-PETSC_MAX_REAL, -PETSC_MAX_REAL, -PETSC_MAX_REAL, -PETSC_MAX_REAL};
  PetscInt           kb = -1, where;
  const char        *seg[4] = {"warp to (i-1,j)", "warp to (i+1,j)", "weft to (i,j-1)", "weft to (i,j+1)"};
  char               strains[256] = "", kink[128] = "", how[96] = "", advice[320] = "";

  PetscFunctionBeginUser;
  if (held)
    PetscCall(PetscSNPrintf(how, sizeof how, " and has stayed above it for the last %d te steps",
                            ENERGY_WATCH_HELD * ENERGY_WATCH_EVERY));
  PetscCall(VecGetArrayRead(fab->state.V, &v));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) {
    const PetscReal ke = fab->grid.inv_m[k] > 0 ? fab->grid.mass[k] * (v[3 * k] * v[3 * k] + v[3 * k + 1] * v[3 * k + 1] + v[3 * k + 2] * v[3 * k + 2]) : -1;
    if (ke > best) best = ke, kb = k;
  }
  PetscCall(VecRestoreArrayRead(fab->state.V, &v));
  where = GlobalIndexOf(p, kb);
  PetscCall(GlobalArgMax(fab->comm, &best, &where));
  {
    const PetscInt gi = where % p->nx, gj = where / p->nx;
    PetscCall(HaloExchange(fab->grid.da, fab->state.X, fab->state.Xl)); /* collective */
    if (gi >= p->xs && gi < p->xs + p->xm && gj >= p->ys && gj < p->ys + p->ym) { /* its owner: the strains */
      PetscCall(VecGetArrayRead(fab->state.Xl, &xl));
      for (int q = 0; q < 4; q++) {
        const PetscInt ni = gi + (q == 0 ? -1 : q == 1 ? 1 : 0), nj = gj + (q == 2 ? -1 : q == 3 ? 1 : 0);
        const PetscInt a = (gj - p->gys) * p->gxm + (gi - p->gxs), b = (nj - p->gys) * p->gxm + (ni - p->gxs);
        if (ni < 0 || ni >= p->nx || nj < 0 || nj >= p->ny || !p->exists[a] || !p->exists[b]) continue;
        if (q == 0 ? p->broken_x[b] : q == 1 ? p->broken_x[a] : q == 2 ? p->broken_y[b] : p->broken_y[a]) continue;
        const PetscReal L0 = q < 2 ? p->ax : p->ay;
        info[q] = PetscSqrtReal(PetscSqr(xl[3 * b] - xl[3 * a]) + PetscSqr(xl[3 * b + 1] - xl[3 * a + 1]) +
                                PetscSqr(xl[3 * b + 2] - xl[3 * a + 2])) / L0 - 1.0;
      }
      PetscCall(VecRestoreArrayRead(fab->state.Xl, &xl));
    }
    PetscCall(GlobalMax(fab->comm, info, 4));
    { /* the kink of the yarn law nearest to one of its segments' strains */
      PetscReal dist = PETSC_MAX_REAL;
      for (int q = 0; q < 4; q++) {
        const YarnLaw  *y = q < 2 ? p->warp : p->weft;
        const PetscReal at[3] = {y->e_contact, 0.0, y->crimp};
        const char     *nm[3] = {"yarn contact", "buckling", "the crimp knee"};
        if (info[q] == -PETSC_MAX_REAL) continue;
        PetscCall(PetscSNPrintf(strains + strlen(strains), sizeof(strains) - strlen(strains), "%s%s %.4g %%",
                                strains[0] ? ", " : "", seg[q], (double) (100 * info[q])));
        for (int c = 0; c < 3; c++)
          if (PetscAbsReal(info[q] - at[c]) < dist) {
            dist = PetscAbsReal(info[q] - at[c]);
            PetscCall(PetscSNPrintf(kink, sizeof(kink), "the %s yarn law's kink at %.4g %% (%s)", y->name,
                                    (double) (100 * at[c]), nm[c]));
          }
      }
    }
    if (fab->s.num.integrator != INTEGRATOR_PAPER)
      PetscCall(PetscSNPrintf(advice, sizeof advice, "Use -integrator fire, a larger -damping_ratio (now %g) or a smaller -te_safety (now %g)",
                              (double) fab->s.num.damping_ratio, (double) fab->s.num.te_safety));
    else /* its parasitic mode grows with any damping, and no te safety measured stops it (docs/stability.md) */
      PetscCall(PetscSNPrintf(advice, sizeof advice,
                              "%s the paper integrator does not relax at any damping or te safety measured (its "
                              "parasitic mode grows with damping: docs/stability.md); use -integrator fire or damped",
                              fab->stats.broken_any ? "Yarns have broken: their loose ends cross the kinks over and over, and"
                                                    : "A relaxation to balance is beyond it:"));
    SETERRQ(fab->comm, PETSC_ERR_NOT_CONVERGED,
            "energy watch: at load step %" PetscInt_FMT ", te step %" PetscInt_FMT
            " of its relaxation, the mechanical energy has grown by %g J since its lowest %g J (the relaxation had "
            "released %g J)%s while nothing did work on the fabric: the %s integrator pumps energy. It moves most at "
            "crossing (%" PetscInt_FMT ", %" PetscInt_FMT "), chord strains %s, nearest to %s: a segment crossing a kink "
            "of the yarn law within a te step gains energy that a low damping does not take out. %s; -energy_watch 0 "
            "switches the watch off",
            fab->load.load_step, n, (double) (h - hmin), (double) hmin, (double) (h0 - hmin),
            how, IntegratorNames[fab->s.num.integrator], gi, gj, strains[0] ? strains : "(none)",
            kink[0] ? kink : "(no segment)", advice);
  }
}

PetscErrorCode EnergyWatchAfter(Fabric fab, PetscInt n)
{
  const PetscScalar *v0, *v1;
  const PetscInt     n_ = fab->grid.nloc;
  PetscReal          e[3]; /* H, the kinetic energy 1/2 sum m v(n+1/2)^2, and the magnitudes H sums */
  PetscReal         *t;    /* their parts per crossing: t[0..n_) H, t[n_..2n_) kinetic, t[2n_..3n_) magnitudes */
  PetscReal          load[2]; /* the point load's part of H and its magnitude: on one rank, summed exactly */
  StepControl       *c = &fab->step;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(EV_Check, 0, 0, 0, 0));
  PetscCall(PetscMalloc1(3 * n_ + 1, &t));
  PetscCall(PotentialEnergy(fab, fab->state.watch_x, t, t + 2 * n_, load));
  PetscCall(VecGetArrayRead(fab->state.watch_v, &v0));
  PetscCall(VecGetArrayRead(fab->state.V, &v1));
  for (PetscInt k = 0; k < n_; k++) {
    t[n_ + k] = 0;
    if (fab->grid.inv_m[k] > 0) {
      const PetscReal m = fab->grid.mass[k];
      const PetscReal kin = 0.5 * m * (v0[3 * k] * v1[3 * k] + v0[3 * k + 1] * v1[3 * k + 1] + v0[3 * k + 2] * v1[3 * k + 2]);
      t[k] += kin, t[2 * n_ + k] += PetscAbsReal(kin);
      t[n_ + k] = 0.5 * m * (v1[3 * k] * v1[3 * k] + v1[3 * k + 1] * v1[3 * k + 1] + v1[3 * k + 2] * v1[3 * k + 2]);
    }
  }
  PetscCall(VecRestoreArrayRead(fab->state.V, &v1));
  PetscCall(VecRestoreArrayRead(fab->state.watch_v, &v0));
  PetscCall(GlobalPointSums(fab->comm, 3, t, n_, e));
  PetscCall(PetscFree(t));
  PetscCall(GlobalSum(fab->comm, load, 2)); /* one rank's value and zeros: exact */
  e[0] += load[0], e[2] += load[1];
  PetscCall(PetscLogEventEnd(EV_Check, 0, 0, 0, 0));
  if (!c->watch_checks++) c->watch_h0 = c->watch_hmin = e[0], c->watch_kmax = 0, c->watch_held = 0;
  c->watch_kmax = PetscMax(c->watch_kmax, e[1]);
  PetscCall(PetscInfo(NULL, "energy watch: load step %" PetscInt_FMT ", te step %" PetscInt_FMT ": H %.10e J (first %.10e, lowest %.10e), kinetic %.4e J (largest %.4e)\n",
                      fab->load.load_step, n, (double) e[0], (double) c->watch_h0, (double) c->watch_hmin, (double) e[1], (double) c->watch_kmax));
  /* grown by more than the fraction of what the round released and of the largest kinetic energy
     (the scale of what H's kinetic part can swing by on a nonlinear chain), and by more than
     H's rounding: H is a sum of parts of magnitude e[2], each part rounded and the sum quantised on
     the largest (near balance the round releases almost nothing and a rise of 1e-17 J is rounding) */
  if (e[0] - c->watch_hmin > fab->s.num.energy_watch * (c->watch_h0 - c->watch_hmin + c->watch_kmax) &&
      e[0] - c->watch_hmin > ENERGY_WATCH_ROUNDING * e[2])
    PetscCall(StopPumping(fab, n, c->watch_h0, c->watch_hmin, e[0], 0));
  /* held above the lowest: with viscous damping, H falls while anything moves. Not counted: a
     run without it (nothing lowers H), and a rise within rounding or below ENERGY_WATCH_HELD_RISE
     of what the round has set in motion (near rest, H's last digits) */
  c->watch_held = (fab->step.damp_c > 0 || fab->s.num.nu > 0) &&
                          e[0] - c->watch_hmin > PetscMax(ENERGY_WATCH_ROUNDING * e[2],
                                                          ENERGY_WATCH_HELD_RISE * (c->watch_h0 - c->watch_hmin + c->watch_kmax))
                      ? c->watch_held + 1
                      : 0;
  if (c->watch_held >= ENERGY_WATCH_HELD) PetscCall(StopPumping(fab, n, c->watch_h0, c->watch_hmin, e[0], 1));
  c->watch_hmin = PetscMin(c->watch_hmin, e[0]);
  PetscFunctionReturn(0);
}
