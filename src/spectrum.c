/* spectrum.c - the measured stable limit: the largest eigenvalue omega_max^2 of M^-1 K.
 *
 * Central differences are stable while te <= 2/omega_max (the paper's scheme: 1/omega_max),
 * omega_max^2 the largest eigenvalue of M^-1 K with K the tangent stiffness of the free crossings
 * (MODEL.md 7.3). The stable step takes omega_max^2 from a bound (StableOmega2, kernels.c); this
 * module measures it, to check the bound and say how loose it is (-te_measure, summary.json).
 *
 * K: the exact Hessians of the force terms' instances (TermInstance, as the quasi-static path
 * assembles them) plus the bodies' penalty Hessians, between free crossings only (a held crossing
 * does not move: its rows and columns are left out). Each owned free crossing keeps its block row,
 * the 3x3 blocks to the 13 crossings within grid distance 2 (the reach of a shear crossing), summed
 * over the instances that contain it in a fixed order; so K v and every step below give the same
 * bits on any number of ranks, with the dot products as exact sums (GlobalSumsExact).
 *
 * Lanczos on the symmetric A = M^-1/2 K M^-1/2 (same eigenvalues as M^-1 K), from a start vector
 * hashed from the global indices, without reorthogonalisation (the largest Ritz value converges
 * first; lost orthogonality only adds copies of converged values). The largest eigenvalue of the
 * tridiagonal matrix by bisection on its Sturm sequence. A Ritz value is never above the largest
 * eigenvalue: the measured limit 2/sqrt(theta) errs, by the relative change of the last 10 steps
 * (below 1e-6), towards a larger te.
 */
#include "spectrum.h"
#include "comm.h"
#include "hash.h"

#include <math.h>

#define REACH       13   /* crossings within grid distance 2: the coupling of a block row */
#define LANCZOS_MAX 500  /* Lanczos steps at most */
#define LANCZOS_TOL 1e-6 /* converged: theta changed by less than this (relative) over 10 steps */

/* the index in a block row of the crossing (di, dj) from its owner, |di| + |dj| <= 2; -1 beyond */
static int ReachIndex(PetscInt di, PetscInt dj)
{
  static const int idx[5][5] = {
      {-1, -1, 0, -1, -1}, {-1, 1, 2, 3, -1}, {4, 5, 6, 7, 8}, {-1, 9, 10, 11, -1}, {-1, -1, 12, -1, -1}};
  if (di < -2 || di > 2 || dj < -2 || dj > 2) return -1;
  return idx[dj + 2][di + 2];
}

typedef struct {
  Fabric         fab;
  PetscReal     *rows;   /* nloc x REACH x 9: the owned crossings' block rows of K */
  PetscReal     *sinv;   /* nloc: 1/sqrt(m) of a free crossing, 0 of a held or absent one */
  unsigned char *free_g; /* ghosted: the crossing is free */
  Vec            z, zl;  /* M^-1/2 v, and ghosted */
  PetscReal     *terms;  /* nloc: per-crossing terms of an exact sum */
} Tangent;

/* which crossings of the ghosted patch are free (inv_m > 0) */
static PetscErrorCode FreeGhosted(Fabric fab, unsigned char *free_g)
{
  const Patch *p = &fab->grid.patch;
  Vec          flag, flagl;
  PetscScalar *a;

  PetscFunctionBeginUser;
  PetscCall(DMGetGlobalVector(fab->grid.da, &flag));
  PetscCall(DMGetLocalVector(fab->grid.da, &flagl));
  PetscCall(VecGetArray(flag, &a));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) a[3 * k] = a[3 * k + 1] = a[3 * k + 2] = fab->grid.inv_m[k] > 0 ? 1 : 0;
  PetscCall(VecRestoreArray(flag, &a));
  PetscCall(HaloExchange(fab->grid.da, flag, flagl));
  PetscCall(VecGetArray(flagl, &a));
  for (PetscInt g = 0; g < p->gxm * p->gym; g++) free_g[g] = a[3 * g] > 0.5 ? 1 : 0;
  PetscCall(VecRestoreArray(flagl, &a));
  PetscCall(DMRestoreLocalVector(fab->grid.da, &flagl));
  PetscCall(DMRestoreGlobalVector(fab->grid.da, &flag));
  PetscFunctionReturn(0);
}

/* the block rows of the owned free crossings: for each, the instances of every term owned by a
   crossing within 1 of it (all that can contain it), in a fixed order; then the bodies */
static PetscErrorCode AssembleRows(Tangent *t)
{
  Fabric             fab = t->fab;
  const Patch       *p   = &fab->grid.patch;
  const PetscScalar *xl, *x;
  PetscReal          c[BODY_KINDS][3];
  TermInstance       inst;

  PetscFunctionBeginUser;
  PetscCall(HaloExchange(fab->grid.da, fab->state.X, fab->state.Xl));
  PetscCall(VecGetArrayRead(fab->state.Xl, &xl));
  PetscCall(VecGetArrayRead(fab->state.X, &x));
  for (PetscInt q = 0; q < fab->bodies.n; q++) BodyPosition(&fab->bodies.body[q], fab->load.travel_now, c[q]);
  for (PetscInt k = 0; k < fab->grid.nloc; k++) {
    const PetscInt i = p->xs + k % p->xm, j = p->ys + k / p->xm;
    PetscReal     *row = t->rows + (size_t) k * REACH * 9;
    for (int e = 0; e < REACH * 9; e++) row[e] = 0;
    if (!(fab->grid.inv_m[k] > 0)) continue;
    for (PetscInt oj = j - 1; oj <= j + 1; oj++)
      for (PetscInt oi = i - 1; oi <= i + 1; oi++)
        for (int tt = 0; tt < INTERNAL_TERMS; tt++) {
          const ForceTerm *term = InternalTerms[tt];
          if (!term->enabled(p)) continue;
          for (int q = 0; q < term->per_point; q++) {
            PetscInt self = -1;
            if (!term->instance(p, xl, oi, oj, q, 0, &inst)) continue;
            for (PetscInt a = 0; a < inst.n; a++)
              if (inst.i[a] == i && inst.j[a] == j) self = a;
            if (self < 0) continue;
            term->instance(p, xl, oi, oj, q, TERM_HESSIAN, &inst);
            for (PetscInt b = 0; b < inst.n; b++) {
              const PetscInt g = (inst.j[b] - p->gys) * p->gxm + (inst.i[b] - p->gxs);
              const int      r = ReachIndex(inst.i[b] - i, inst.j[b] - j);
              if (r < 0 || !t->free_g[g]) continue;
              for (int d = 0; d < 3; d++)
                for (int e = 0; e < 3; e++) {
                  const PetscReal v = inst.K[(3 * self + d) * 3 * inst.n + 3 * b + e];
                  if (isfinite(v)) row[9 * r + 3 * d + e] += v; /* a zero-length chord has no tangent */
                }
            }
          }
        }
    for (PetscInt q = 0; q < fab->bodies.n; q++) {
      PetscReal gb[3], Kb[9];
      if (BodyEnergy(&fab->bodies.body[q], c[q], x + 3 * k, gb, Kb) > 0)
        for (int e = 0; e < 9; e++) row[9 * ReachIndex(0, 0) + e] += Kb[e];
    }
  }
  PetscCall(VecRestoreArrayRead(fab->state.X, &x));
  PetscCall(VecRestoreArrayRead(fab->state.Xl, &xl));
  PetscFunctionReturn(0);
}

/* y = M^-1/2 K M^-1/2 v on the owned crossings */
static PetscErrorCode Apply(Tangent *t, Vec v, Vec y)
{
  Fabric             fab = t->fab;
  const Patch       *p   = &fab->grid.patch;
  const PetscScalar *va, *zl;
  PetscScalar       *za, *ya;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(v, &va));
  PetscCall(VecGetArray(t->z, &za));
  for (PetscInt k = 0; k < fab->grid.nloc; k++)
    for (int d = 0; d < 3; d++) za[3 * k + d] = t->sinv[k] * va[3 * k + d];
  PetscCall(VecRestoreArray(t->z, &za));
  PetscCall(VecRestoreArrayRead(v, &va));
  PetscCall(HaloExchange(fab->grid.da, t->z, t->zl));
  PetscCall(VecGetArrayRead(t->zl, &zl));
  PetscCall(VecGetArray(y, &ya));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) {
    const PetscInt   i = p->xs + k % p->xm, j = p->ys + k / p->xm;
    const PetscReal *row  = t->rows + (size_t) k * REACH * 9;
    PetscReal        s[3] = {0, 0, 0};
    if (t->sinv[k] > 0)
      for (PetscInt dj = -2; dj <= 2; dj++)
        for (PetscInt di = -2; di <= 2; di++) {
          const int      r  = ReachIndex(di, dj);
          const PetscInt li = i + di - p->gxs, lj = j + dj - p->gys;
          if (r < 0 || li < 0 || li >= p->gxm || lj < 0 || lj >= p->gym) continue;
          const PetscScalar *zb = zl + 3 * (lj * p->gxm + li);
          for (int d = 0; d < 3; d++)
            s[d] += row[9 * r + 3 * d] * zb[0] + row[9 * r + 3 * d + 1] * zb[1] + row[9 * r + 3 * d + 2] * zb[2];
        }
    for (int d = 0; d < 3; d++) ya[3 * k + d] = t->sinv[k] * s[d];
  }
  PetscCall(VecRestoreArray(y, &ya));
  PetscCall(VecRestoreArrayRead(t->zl, &zl));
  PetscFunctionReturn(0);
}

/* a . b as an exact sum of per-crossing terms: the same bits on any number of ranks */
static PetscErrorCode Dot(Tangent *t, Vec a, Vec b, PetscReal *dot)
{
  const PetscScalar *x, *y;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(a, &x));
  PetscCall(VecGetArrayRead(b, &y));
  for (PetscInt k = 0; k < t->fab->grid.nloc; k++)
    t->terms[k] = x[3 * k] * y[3 * k] + x[3 * k + 1] * y[3 * k + 1] + x[3 * k + 2] * y[3 * k + 2];
  PetscCall(VecRestoreArrayRead(b, &y));
  PetscCall(VecRestoreArrayRead(a, &x));
  PetscCall(GlobalSumsExact(t->fab->comm, 1, t->terms, t->fab->grid.nloc, dot));
  PetscFunctionReturn(0);
}

/* the number of eigenvalues below x of the symmetric tridiagonal matrix (diagonal a, off-diagonal b) */
static PetscInt SturmCount(const PetscReal *a, const PetscReal *b, PetscInt n, PetscReal x)
{
  PetscInt  count = 0;
  PetscReal d     = 1;
  for (PetscInt k = 0; k < n; k++) {
    d = a[k] - x - (k > 0 ? b[k - 1] * b[k - 1] / d : 0.0);
    if (d == 0) d = -PETSC_SMALL * (PetscAbsReal(a[k]) + PetscAbsReal(x) + PETSC_SMALL);
    if (d < 0) count++;
  }
  return count;
}

/* the largest eigenvalue of that matrix, by bisection between its Gershgorin bounds */
static PetscReal TridiagonalMax(const PetscReal *a, const PetscReal *b, PetscInt n)
{
  PetscReal lo = PETSC_MAX_REAL, hi = -PETSC_MAX_REAL;
  for (PetscInt k = 0; k < n; k++) {
    const PetscReal r = (k > 0 ? PetscAbsReal(b[k - 1]) : 0.0) + (k + 1 < n ? PetscAbsReal(b[k]) : 0.0);
    lo = PetscMin(lo, a[k] - r), hi = PetscMax(hi, a[k] + r);
  }
  for (int it = 0; it < 200 && hi - lo > 4 * PETSC_MACHINE_EPSILON * PetscMax(PetscAbsReal(lo), PetscAbsReal(hi));
       it++) {
    const PetscReal mid = 0.5 * (lo + hi);
    if (SturmCount(a, b, n, mid) == n)
      hi = mid; /* every eigenvalue is below mid */
    else
      lo = mid;
  }
  return hi;
}

PetscErrorCode TangentOmega2Max(Fabric fab, PetscReal *omega2, PetscInt *iterations)
{
  const Patch *p = &fab->grid.patch;
  Tangent      t = {fab, NULL, NULL, NULL, NULL, NULL, NULL};
  Vec          q, q_prev, w;
  PetscReal   *alpha, *beta, theta = 0, theta_10 = 0, norm2;
  PetscInt     n = 0;
  PetscScalar *a;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc4((size_t) fab->grid.nloc * REACH * 9, &t.rows, fab->grid.nloc, &t.sinv,
                         (size_t) p->gxm * p->gym, &t.free_g, fab->grid.nloc, &t.terms));
  PetscCall(PetscMalloc2(LANCZOS_MAX, &alpha, LANCZOS_MAX, &beta));
  PetscCall(FreeGhosted(fab, t.free_g));
  for (PetscInt k = 0; k < fab->grid.nloc; k++)
    t.sinv[k] = fab->grid.inv_m[k] > 0 ? PetscSqrtReal(fab->grid.inv_m[k]) : 0;
  PetscCall(AssembleRows(&t));
  PetscCall(DMGetGlobalVector(fab->grid.da, &t.z));
  PetscCall(DMGetLocalVector(fab->grid.da, &t.zl));
  PetscCall(DMGetGlobalVector(fab->grid.da, &q));
  PetscCall(DMGetGlobalVector(fab->grid.da, &q_prev));
  PetscCall(DMGetGlobalVector(fab->grid.da, &w));
  /* start: hashed from the global index in [-1, 1) on the free crossings */
  PetscCall(VecGetArray(q, &a));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) {
    const uint64_t g = (uint64_t) ((p->ys + k / p->xm) * p->nx + p->xs + k % p->xm);
    for (int d = 0; d < 3; d++)
      a[3 * k + d] =
          t.sinv[k] > 0 ? 2.0 * ldexp((double) (Mix64(HASH_GOLDEN * (3 * g + d + 1)) >> 11), -53) - 1.0 : 0.0;
  }
  PetscCall(VecRestoreArray(q, &a));
  PetscCall(VecZeroEntries(q_prev));
  PetscCall(Dot(&t, q, q, &norm2));
  if (norm2 > 0) {
    PetscCall(VecScale(q, 1.0 / PetscSqrtReal(norm2)));
    for (n = 0; n < LANCZOS_MAX;) {
      PetscReal al, be2;
      PetscCall(Apply(&t, q, w));
      if (n > 0) PetscCall(VecAXPY(w, -beta[n - 1], q_prev));
      PetscCall(Dot(&t, w, q, &al));
      PetscCall(VecAXPY(w, -al, q));
      PetscCall(Dot(&t, w, w, &be2));
      alpha[n] = al, beta[n] = PetscSqrtReal(be2);
      n++;
      if (n % 10 == 0 || !(beta[n - 1] > 1e-12 * PetscAbsReal(alpha[0]))) theta = TridiagonalMax(alpha, beta, n);
      if (!(beta[n - 1] > 1e-12 * PetscAbsReal(theta))) break; /* an invariant subspace: theta is exact */
      if (n % 10 == 0) {
        if (PetscAbsReal(theta - theta_10) <= LANCZOS_TOL * PetscAbsReal(theta)) break;
        theta_10 = theta;
      }
      PetscCall(VecCopy(q, q_prev));
      PetscCall(VecCopy(w, q));
      PetscCall(VecScale(q, 1.0 / beta[n - 1]));
    }
  }
  if (n > 0) theta = TridiagonalMax(alpha, beta, n);
  PetscCall(DMRestoreGlobalVector(fab->grid.da, &w));
  PetscCall(DMRestoreGlobalVector(fab->grid.da, &q_prev));
  PetscCall(DMRestoreGlobalVector(fab->grid.da, &q));
  PetscCall(DMRestoreLocalVector(fab->grid.da, &t.zl));
  PetscCall(DMRestoreGlobalVector(fab->grid.da, &t.z));
  PetscCall(PetscFree2(alpha, beta));
  PetscCall(PetscFree4(t.rows, t.sinv, t.free_g, t.terms));
  *omega2 = PetscMax(theta, 0.0);
  if (iterations) *iterations = n;
  PetscFunctionReturn(0);
}

/* keep m as the first, last, tightest (smallest limit) and worst (largest te / limit) record */
static void KeepRecord(StepControl *st, const TeMeasure *m)
{
  if (!st->te_measured) st->te_first = st->te_tightest = st->te_worst = *m;
  st->te_last = *m;
  if (m->limit < st->te_tightest.limit) st->te_tightest = *m;
  if (m->te / m->limit > st->te_worst.te / st->te_worst.limit) st->te_worst = *m;
  st->te_measured++;
}

/* the true limit at this state: of the load step starting here, or (end, or last: the run's last
   state) of the one that ended here */
static PetscErrorCode Measure(Fabric fab, PetscReal te_prev, PetscBool last)
{
  const PetscInt  every = fab->s.num.te_measure, step = fab->load.load_step;
  const PetscBool end = last || (step != fab->step.te_prev_step && fab->step.te_prev_step >= 1) ? PETSC_TRUE : PETSC_FALSE;
  const PetscInt  of  = last ? step : end ? fab->step.te_prev_step : step; /* the load step this state belongs to */
  PetscReal       omega2;
  PetscInt        its;
  TeMeasure       m;

  PetscFunctionBeginUser;
  fab->step.te_prev_step = step;
  /* the run's first state (load step 0) is never stepped with: load step 1 takes its te after its grips moved */
  /* last: the run's last state, also where it ended before its last load step (a rupture) */
  if (!every || of < 1 || !(of == 1 || of % every == 0 || of == fab->s.load.load_steps || last)) PetscFunctionReturn(0);
  PetscCall(TangentOmega2Max(fab, &omega2, &its));
  if (!(omega2 > 0)) PetscFunctionReturn(0); /* no stiffness between free crossings: no limit */
  m.load_step = of;
  m.end       = end;
  m.te        = end ? te_prev : fab->step.te;
  m.te_bound  = fab->step.te_bound;
  m.limit     = (PaperSteps(fab) ? 1.0 : 2.0) / PetscSqrtReal(omega2); /* the scheme te is for */
  KeepRecord(&fab->step, &m);
  PetscCall(PetscInfo(
      NULL,
      "load step %" PetscInt_FMT " %s: te %g s, stable bound %g s, measured limit %g s (%" PetscInt_FMT
      " Lanczos steps): te / limit %.4f\n",
      of, end ? "end" : "start", (double) m.te, (double) m.te_bound, (double) m.limit, its, (double) (m.te / m.limit)));
  PetscFunctionReturn(0);
}

PetscErrorCode StableStepMeasure(Fabric fab, PetscReal te_prev)
{
  PetscFunctionBeginUser;
  PetscCall(Measure(fab, te_prev, PETSC_FALSE));
  PetscFunctionReturn(0);
}

PetscErrorCode StableStepMeasureLast(Fabric fab)
{
  PetscFunctionBeginUser;
  if (fab->s.num.te_measure && fab->load.load_step >= 1) PetscCall(Measure(fab, fab->step.te, PETSC_TRUE));
  PetscFunctionReturn(0);
}

PetscErrorCode StableStepMeasureTear(Fabric fab, const char *when)
{
  PetscReal omega2;
  PetscInt  its;
  PetscBool info;

  PetscFunctionBeginUser;
  PetscCall(PetscInfoEnabled(PETSC_SMALLEST_CLASSID, &info)); /* PetscInfo(NULL, ...)'s class */
  if (!fab->s.num.te_measure || !info) PetscFunctionReturn(0);
  PetscCall(TangentOmega2Max(fab, &omega2, &its));
  if (!(omega2 > 0)) PetscFunctionReturn(0);
  {
    const PetscReal limit = 2.0 / PetscSqrtReal(omega2); /* a tear runs the damped scheme */
    PetscCall(PetscInfo(NULL,
                        "load step %" PetscInt_FMT " tear %s: te %.17g s, stable bound %.17g s, measured limit %.10g s "
                        "(%" PetscInt_FMT " Lanczos steps): te / limit %.4f\n",
                        fab->load.load_step, when, (double) fab->step.te, (double) fab->step.te_bound, (double) limit, its,
                        (double) (fab->step.te / limit)));
  }
  PetscFunctionReturn(0);
}
