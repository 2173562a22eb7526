/* integrate.c - explicit time integration (MODEL.md 7) and the stable step.
 *
 * damped (default), central differences with mass-proportional damping c = nu/m:
 *   v(n+1/2) = ((2 - c te) v(n-1/2) + 2 te F_n / m) / (2 + c te),  x(n+1) = x(n) + te v(n+1/2)
 *   stable for omega_max te <= 2 at any damping.
 * paper, eq. (10), a leapfrog over two interleaved chains:
 *   V(n+1) = (2 te / m)(R_n - nu V(n)) + V(n-1),  u(n+1) = 2 te V(n) + u(n-1)
 *   stable only for omega_max te <= 1, and with nu > 0 it has a growing parasitic mode.
 * te = safety * bound, bound = 2/omega_max (damped) or 1/omega_max (paper), with
 * omega_max^2 from the Gershgorin row sums of the tangent stiffness (kernels.c).
 */
#include "fabric.h"

#include <math.h>

/* internal forces at the current positions, plus the point load */
PetscErrorCode ComputeForces(Fabric fab, PetscReal *tension_max)
{
  const PetscScalar *xl;
  PetscScalar       *f;

  PetscFunctionBeginUser;
  PetscCall(HaloExchange(fab));
  PetscCall(PetscLogEventBegin(EV_Force, 0, 0, 0, 0));
  PetscCall(VecGetArrayRead(fab->Xl, &xl));
  PetscCall(VecGetArray(fab->F, &f));
  ComputeInternalForces(&fab->patch, xl, f, tension_max);
  if (fab->load_index >= 0)
    for (int d = 0; d < 3; d++) f[3 * fab->load_index + d] += fab->load_factor * fab->s.point_load[d];
  PetscCall(VecRestoreArray(fab->F, &f));
  PetscCall(VecRestoreArrayRead(fab->Xl, &xl));
  PetscCall(PetscLogEventEnd(EV_Force, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode StableStep(Fabric fab)
{
  const Scene       *s = &fab->s;
  const PetscScalar *xl;
  PetscReal          omega2[2];

  PetscFunctionBeginUser;
  PetscCall(HaloExchange(fab));
  PetscCall(PetscLogEventBegin(EV_Bound, 0, 0, 0, 0));
  PetscCall(VecGetArrayRead(fab->Xl, &xl));
  omega2[0] = StableOmega2(&fab->patch, xl, fab->inv_m, s->te_window, s->pull == PULL_WARP ? 0 : 1, &omega2[1]);
  PetscCall(VecRestoreArrayRead(fab->Xl, &xl));
  PetscCall(PetscLogEventEnd(EV_Bound, 0, 0, 0, 0));
  PetscCall(GlobalMax(fab->comm, omega2, 2));
  PetscCheck(omega2[0] > 0, fab->comm, PETSC_ERR_USER_INPUT, "no free crossing point has any stiffness: nothing to integrate (check -traction, -bending, -shear and the clamps)");
  fab->omega_max = PetscSqrtReal(omega2[0]);
  fab->te_bound  = (s->integrator == INTEGRATOR_PAPER ? 1.0 : 2.0) / fab->omega_max;
  if (s->te_user > 0) {
    PetscCheck(!s->te_check || s->te_user <= fab->te_bound, fab->comm, PETSC_ERR_USER_INPUT, "-te %g s is above the stable bound %g s at load step %" PetscInt_FMT " (%s integrator, omega_max = %g rad/s): use -te %g or less, or leave -te unset", (double)s->te_user, (double)fab->te_bound, fab->load_step, IntegratorNames[s->integrator], (double)fab->omega_max, (double)fab->te_bound);
    fab->te = s->te_user;
  } else fab->te = s->te_safety * fab->te_bound;
  /* damping: the paper's nu per point, plus a mass-proportional part c = 2 zeta omega_1 with
     omega_1 ~ pi omega_pull / (2 n) the slowest mode of the chain of n segments along the
     pull, omega_pull = 2 sqrt(k/m) its highest (from the pull-direction springs alone) */
  {
    const PetscInt n = (s->pull == PULL_WARP ? s->nx : s->ny) - 1;
    fab->damp_c      = 2.0 * s->damping_ratio * PETSC_PI * PetscSqrtReal(omega2[1]) / (2.0 * n);
  }
  PetscFunctionReturn(0);
}

/* accumulators of one sweep: max |F|^2 and |v|^2 over free points, sum |v|^2 (non-finite watch) */
typedef struct {
  PetscReal res2, v2, v2sum;
} SweepStats;

static void IntegrateDamped(PetscInt n, PetscReal te, PetscReal c0, PetscReal nu, const PetscReal g[3], const PetscReal *mass, const PetscReal *inv_m, const PetscReal *f, PetscReal *restrict x, PetscReal *restrict v, SweepStats *st)
{
  PetscReal res2 = 0, v2 = 0, v2sum = 0;
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
    const PetscReal w2 = vx * vx + vy * vy + vz * vz, r2 = im > 0 ? Fx * Fx + Fy * Fy + Fz * Fz : 0.0;
    res2 = PetscMax(res2, r2);
    v2   = PetscMax(v2, w2);
    v2sum += w2;
  }
  st->res2  = res2;
  st->v2    = v2;
  st->v2sum = v2sum;
}

static void IntegratePaper(PetscInt n, PetscReal te, PetscReal c0, PetscReal nu, const PetscReal g[3], const PetscReal *mass, const PetscReal *inv_m, const PetscReal *f, PetscReal *restrict x, PetscReal *restrict v, PetscReal *restrict xold, PetscReal *restrict vold, SweepStats *st)
{
  PetscReal res2 = 0, v2 = 0, v2sum = 0;
  for (PetscInt k = 0; k < n; k++) {
    const PetscReal im = inv_m[k], m = mass[k], c = c0 + nu * im;
    PetscReal       r2 = 0, w2 = 0;
    for (int d = 0; d < 3; d++) {
      const PetscReal F = f[3 * k + d] + m * g[d], Vn = v[3 * k + d], xn = x[3 * k + d];
      const PetscReal Vnew = vold[3 * k + d] + 2.0 * te * (F * im - c * Vn);
      vold[3 * k + d] = Vn;
      v[3 * k + d]    = Vnew;
      x[3 * k + d]    = xold[3 * k + d] + 2.0 * te * Vn;
      xold[3 * k + d] = xn;
      r2 += F * F;
      w2 += Vnew * Vnew;
    }
    res2 = PetscMax(res2, im > 0 ? r2 : 0.0);
    v2   = PetscMax(v2, w2);
    v2sum += w2;
  }
  st->res2  = res2;
  st->v2    = v2;
  st->v2sum = v2sum;
}

/* One te step: halo exchange, forces, integration, then the global balance test and the
   stability watch (one max-reduction). Stops with an error on NaN, Inf or runaway motion. */
PetscErrorCode TimeStep(Fabric fab, StepStats *out)
{
  const Scene *s = &fab->s;
  PetscReal    tension_max, red[4];
  SweepStats   st;
  PetscScalar *x, *v, *f, *xold, *vold;

  PetscFunctionBeginUser;
  PetscCall(ComputeForces(fab, &tension_max));
  PetscCall(PetscLogEventBegin(EV_Integrate, 0, 0, 0, 0));
  PetscCall(VecGetArray(fab->X, &x));
  PetscCall(VecGetArray(fab->V, &v));
  PetscCall(VecGetArray(fab->F, &f));
  if (s->integrator == INTEGRATOR_PAPER) {
    PetscCall(VecGetArray(fab->Xold, &xold));
    PetscCall(VecGetArray(fab->Vold, &vold));
    IntegratePaper(fab->nloc, fab->te, fab->damp_c, s->nu, s->gravity, fab->mass, fab->inv_m, f, x, v, xold, vold, &st);
    PetscCall(VecRestoreArray(fab->Xold, &xold));
    PetscCall(VecRestoreArray(fab->Vold, &vold));
  } else IntegrateDamped(fab->nloc, fab->te, fab->damp_c, s->nu, s->gravity, fab->mass, fab->inv_m, f, x, v, &st);
  PetscCall(VecRestoreArray(fab->F, &f));
  PetscCall(VecRestoreArray(fab->V, &v));
  PetscCall(VecRestoreArray(fab->X, &x));
  PetscCall(PetscLogEventEnd(EV_Integrate, 0, 0, 0, 0));

  red[0] = st.res2;
  red[1] = st.v2;
  red[2] = tension_max;
  red[3] = isfinite(st.v2sum) ? 0.0 : 1.0;
  PetscCall(GlobalMax(fab->comm, red, 4));
  fab->te_steps++;
  fab->point_updates += fab->points;
  PetscCheck(red[3] == 0.0, fab->comm, PETSC_ERR_FP, "numerical instability at load step %" PetscInt_FMT ", te step %" PetscInt64_FMT ": velocities became NaN or Inf (te = %g s, stable bound %g s)", fab->load_step, fab->te_steps, (double)fab->te, (double)fab->te_bound);
  out->speed       = PetscSqrtReal(red[1]);
  out->tension_max = red[2];
  out->residual    = PetscSqrtReal(red[0]) / PetscMax(red[2], fab->force_floor);
  PetscCheck(out->speed * fab->te <= fab->extent, fab->comm, PETSC_ERR_FP, "numerical instability at load step %" PetscInt_FMT ", te step %" PetscInt64_FMT ": runaway motion, a point moved %g m in one step, more than the fabric's size %g m (te = %g s, stable bound %g s)", fab->load_step, fab->te_steps, (double)(out->speed * fab->te), (double)fab->extent, (double)fab->te, (double)fab->te_bound);
  out->balanced = (out->residual <= s->balance_tol && out->speed <= s->speed_tol) ? PETSC_TRUE : PETSC_FALSE;
  fab->last     = *out;
  if (fab->io) PetscCall(FramesTeStep(fab)); /* -output_te_every (io.c) */
  PetscFunctionReturn(0);
}
