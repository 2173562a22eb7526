/* bench_sweep.c - what one te step costs beside what the memory and a plain spring net allow.
 *
 *   mpiexec -n P build/bench_sweep -scene inputs/square_1000.yaml [-bench_sweeps 20]
 *
 * Builds the scene's fabric (as fabric does) and times, on each rank's owned patch, in one process:
 *  - triad: a = b + s c over three arrays of 3 doubles per owned point (STREAM's triad: 24 bytes
 *    per element counted, no write-allocate);
 *  - halo: HaloExchange of the positions (the ghosted copy the force kernel reads);
 *  - force: ComputeInternalForces over the owned patch (every term the scene switches on), at
 *    positions moved off rest by a fixed pseudo-random 1e-3 of the spacing so that yarns are
 *    strained both ways, as in a loaded fabric;
 *  - spring: a plain te step of a net of linear springs on the same grid and the same arrays:
 *    per point the four springs to its neighbours, k (L - L0) d / L, each computed at both ends,
 *    then v = a v + b f, x += te v over the owned points (two sweeps, as the solver's force
 *    and update).
 * Each figure is the median over -bench_sweeps repetitions, per owned point; rank 0 prints
 * the slowest rank's figures as key=value on one line (scripts/bench.sh reads it).
 */
#include "comm.h"
#include "fabric.h"
#include "hash.h"
#include "kernels.h"
#include "scene.h"
#include "scenefile.h"

#include <math.h>
#include <stdlib.h>

static int CompareReal(const void *a, const void *b)
{
  const PetscReal x = *(const PetscReal *) a, y = *(const PetscReal *) b;
  return (x > y) - (x < y);
}

static PetscReal Median(PetscReal *t, PetscInt n)
{
  qsort(t, (size_t) n, sizeof *t, CompareReal);
  return n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
}

/* a = b + s c (STREAM triad) */
static void Triad(PetscInt n, PetscReal s, PetscReal *restrict a, const PetscReal *restrict b,
                  const PetscReal *restrict c)
{
  for (PetscInt k = 0; k < n; k++) a[k] = b[k] + s * c[k];
}

/* the forces of a net of linear springs (stiffness k, rest length L0) on the owned xm x ym points
   of x (3 per point, rows of xm): the four neighbours within the patch. Built for the same
   instruction sets as the force kernel (FABRIC_WIDE), so that the two compare on one footing. */
FABRIC_WIDE static void SpringForces(PetscInt xm, PetscInt ym, PetscReal k, PetscReal L0, const PetscReal *restrict x,
                         PetscReal *restrict f)
{
  for (PetscInt j = 0; j < ym; j++)
    for (PetscInt i = 0; i < xm; i++) {
      const PetscInt   q = j * xm + i, nb[4] = {i > 0 ? q - 1 : -1, i < xm - 1 ? q + 1 : -1, j > 0 ? q - xm : -1,
                                                j < ym - 1 ? q + xm : -1};
      const PetscReal *a = x + 3 * q;
      PetscReal        fx = 0, fy = 0, fz = 0;
      for (int s = 0; s < 4; s++) {
        if (nb[s] < 0) continue;
        const PetscReal *b = x + 3 * nb[s];
        const PetscReal  dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
        const PetscReal  L = sqrt(dx * dx + dy * dy + dz * dz), t = k * (L - L0) / L;
        fx += t * dx, fy += t * dy, fz += t * dz;
      }
      f[3 * q] = fx, f[3 * q + 1] = fy, f[3 * q + 2] = fz;
    }
}

/* v = a v + b f, x += te v (the damped central-difference update, constant coefficients) */
FABRIC_WIDE static void SpringUpdate(PetscInt n, PetscReal a, PetscReal b, PetscReal te, const PetscReal *restrict f,
                         PetscReal *restrict v, PetscReal *restrict x)
{
  for (PetscInt k = 0; k < 3 * n; k++) {
    v[k] = a * v[k] + b * f[k];
    x[k] += te * v[k];
  }
}

int main(int argc, char **argv)
{
  Fabric             fab;
  PetscInt           reps = 20, nloc, n3;
  PetscReal         *t_triad, *t_halo, *t_force, *t_spring, res[4];
  PetscReal         *a, *b, *c, *f, *v, *x;
  const PetscScalar *xl;
  PetscScalar       *xg;
  PetscLogDouble     t0, t1;

  PetscCall(PetscInitialize(&argc, &argv, NULL, "bench_sweep: a te step beside a triad and a plain spring sweep\n"));
  PetscCall(SceneInsertFile(PETSC_COMM_WORLD, argc, argv));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-bench_sweeps", &reps, NULL));
  PetscCall(FabricCreate(PETSC_COMM_WORLD, &fab));
  nloc = fab->grid.nloc, n3 = 3 * nloc;
  PetscCall(PetscMalloc4(reps, &t_triad, reps, &t_halo, reps, &t_force, reps, &t_spring));
  PetscCall(PetscMalloc6(n3, &a, n3, &b, n3, &c, n3, &f, n3, &v, n3, &x));

  /* positions off rest: a fixed pseudo-random 1e-3 of the spacing per coordinate, by global index */
  {
    const Patch *p = &fab->grid.patch;
    PetscCall(VecGetArray(fab->state.X, &xg));
    for (PetscInt q = 0; q < nloc; q++) {
      const PetscInt i = p->xs + q % p->xm, j = p->ys + q / p->xm;
      for (int d = 0; d < 3; d++) {
        const PetscReal u = (PetscReal) (Mix64((uint64_t) (3 * (j * p->nx + i) + d)) >> 11) * 0x1.0p-53;
        xg[3 * q + d] += 1e-3 * p->ax * (2 * u - 1);
      }
    }
    PetscCall(PetscArraycpy(x, xg, n3));
    PetscCall(VecRestoreArray(fab->state.X, &xg));
  }
  for (PetscInt k = 0; k < n3; k++) a[k] = 0, b[k] = 1.0 + 1e-3 * (k % 7), c[k] = 2.0 - 1e-3 * (k % 5), v[k] = 0;

  for (PetscInt r = 0; r < reps; r++) {
    const Patch   *p      = &fab->grid.patch;
    const PetscInt box[4] = {p->xs, p->xs + p->xm, p->ys, p->ys + p->ym};
    PetscReal      tmax;
    PetscScalar   *F;

    PetscCall(PetscTime(&t0));
    Triad(n3, 3.0, a, b, c);
    PetscCall(PetscTime(&t1));
    t_triad[r] = t1 - t0;

    PetscCall(PetscTime(&t0));
    PetscCall(HaloExchange(fab->grid.da, fab->state.X, fab->state.Xl));
    PetscCall(PetscTime(&t1));
    t_halo[r] = t1 - t0;

    PetscCall(VecGetArrayRead(fab->state.Xl, &xl));
    PetscCall(VecGetArray(fab->state.F, &F));
    PetscCall(PetscTime(&t0));
    ComputeInternalForces(&fab->grid.patch, xl, box, F, &tmax);
    PetscCall(PetscTime(&t1));
    t_force[r] = t1 - t0;
    PetscCall(VecRestoreArray(fab->state.F, &F));
    PetscCall(VecRestoreArrayRead(fab->state.Xl, &xl));

    PetscCall(PetscTime(&t0));
    SpringForces(p->xm, p->ym, 1.0, p->ax, x, f);
    SpringUpdate(nloc, 0.999, 1e-12, 1e-9, f, v, x);
    PetscCall(PetscTime(&t1));
    t_spring[r] = t1 - t0;
  }
  /* per owned point, the slowest rank */
  res[0] = Median(t_triad, reps) / nloc, res[1] = Median(t_halo, reps) / nloc;
  res[2] = Median(t_force, reps) / nloc, res[3] = Median(t_spring, reps) / nloc;
  PetscCall(GlobalMax(fab->comm, res, 4));
  PetscCall(PetscPrintf(fab->comm,
                        "points_per_rank=%" PetscInt_FMT " sweeps=%" PetscInt_FMT
                        " triad_GBps=%.3f halo_ns=%.3f force_ns=%.3f spring_ns=%.3f spring_rate=%.4e\n",
                        nloc, reps, 24.0 / res[0] * 1e-9, res[1] * 1e9, res[2] * 1e9, res[3] * 1e9, 1.0 / res[3]));
  PetscCall(PetscFree6(a, b, c, f, v, x));
  PetscCall(PetscFree4(t_triad, t_halo, t_force, t_spring));
  PetscCall(FabricDestroy(&fab));
  PetscCall(PetscFinalize());
  return 0;
}
