/* bodies.c - penalty contact of the crossings with rigid bodies and Coulomb friction
 * (MODEL.md 5.5): a sphere (the punch), a plane (a table) and a pedestal (a disc).
 */
#include "bodies.h"

#include <math.h>

/* Coulomb friction as a regularised stick spring (MODEL.md 5.5). A point in contact is tied
   to its anchor, a point of the body (rel and anchor a are taken from the body's reference
   point, so an anchor moves with its body), by a tangential spring of the contact stiffness k:
   ft = -k (rel - a) projected on the contact's tangent plane (unit normal n). When |ft| would
   exceed mu fn the point slips: ft is cut to mu fn and the anchor is dragged along behind the
   point, a = rel + ft / k. A point under a tangential load below mu fn sticks for good (it
   comes to rest, which a law of the slip velocity cannot do: its force vanishes at rest and
   the point creeps); above it, it slides with a friction force of exactly mu fn. With the
   tangential stiffness equal to the normal one the contact block is k I, so the stable-step
   bound is the frictionless one. Adds ft to f and to sum. */
static inline void StickSlip(const PetscReal rel[3], const PetscReal n[3], PetscReal fn, PetscReal k, PetscReal mu,
                             PetscReal a[3], PetscReal f[3], PetscReal sum[3])
{
  PetscReal t[3], dn = 0, t2 = 0;
  for (int d = 0; d < 3; d++) t[d] = rel[d] - a[d], dn += t[d] * n[d];
  for (int d = 0; d < 3; d++) t[d] -= dn * n[d], t2 += t[d] * t[d];
  PetscReal scale = -k; /* ft = scale * t */
  if (k * k * t2 > mu * mu * fn * fn) {
    scale = -mu * fn / PetscSqrtReal(t2);
    for (int d = 0; d < 3; d++) a[d] = rel[d] + scale * t[d] / k;
  }
  for (int d = 0; d < 3; d++) {
    f[d] += scale * t[d];
    sum[d] += scale * t[d];
  }
}

/* The normal push fv (= fn n) on point q, and friction if anchors are kept; a point out of
   contact (fn <= 0) has its anchor reset to where it is. */
static inline void ContactForce(PetscInt q, const PetscReal *x, const PetscReal c[3], const PetscReal n[3],
                                PetscReal fn, const PetscReal fv[3], PetscReal k, PetscReal mu, PetscReal *anchor,
                                PetscReal *f, PetscReal sum[3])
{
  if (fn <= 0) {
    if (anchor)
      for (int d = 0; d < 3; d++) anchor[3 * q + d] = x[3 * q + d] - c[d];
    return;
  }
  for (int d = 0; d < 3; d++) {
    f[3 * q + d] += fv[d];
    sum[d] += fv[d];
  }
  if (anchor && mu > 0) {
    const PetscReal rel[3] = {x[3 * q] - c[0], x[3 * q + 1] - c[1], x[3 * q + 2] - c[2]};
    StickSlip(rel, n, fn, k, mu, anchor + 3 * q, f + 3 * q, sum);
  }
}

void SphereContact(PetscInt n, const PetscReal *x, const PetscReal *inv_m, const PetscReal c[3], PetscReal reach,
                   PetscReal k, PetscReal mu, PetscReal *anchor, PetscReal *f, PetscReal sum[3])
{
  for (PetscInt q = 0; q < n; q++) {
    if (inv_m[q] <= 0) continue;
    const PetscReal dx = x[3 * q] - c[0], dy = x[3 * q + 1] - c[1], dz = x[3 * q + 2] - c[2];
    const PetscReal r2     = dx * dx + dy * dy + dz * dz;
    PetscReal       nrm[3] = {0, 0, 0}, fv[3] = {0, 0, 0}, fn = 0;
    if (r2 < reach * reach && r2 > 0) {
      const PetscReal r = PetscSqrtReal(r2), push = k * (reach - r) / r;
      fv[0] = push * dx, fv[1] = push * dy, fv[2] = push * dz;
      nrm[0] = dx / r, nrm[1] = dy / r, nrm[2] = dz / r;
      fn = k * (reach - r);
    }
    ContactForce(q, x, c, nrm, fn, fv, k, mu, anchor, f, sum);
  }
}

/* a push fn along the unit normal n (plane, disc) */
static inline void NormalPush(PetscInt q, const PetscReal *x, const PetscReal c[3], const PetscReal n[3], PetscReal fn,
                              PetscReal k, PetscReal mu, PetscReal *anchor, PetscReal *f, PetscReal sum[3])
{
  const PetscReal fv[3] = {fn * n[0], fn * n[1], fn * n[2]};
  ContactForce(q, x, c, n, fn, fv, k, mu, anchor, f, sum);
}

void PlaneContact(PetscInt n, const PetscReal *x, const PetscReal *inv_m, const PetscReal p0[3], const PetscReal nrm[3],
                  PetscReal reach, PetscReal k, PetscReal mu, PetscReal *anchor, PetscReal *f, PetscReal sum[3])
{
  for (PetscInt q = 0; q < n; q++) {
    if (inv_m[q] <= 0) continue;
    const PetscReal dist =
        (x[3 * q] - p0[0]) * nrm[0] + (x[3 * q + 1] - p0[1]) * nrm[1] + (x[3 * q + 2] - p0[2]) * nrm[2];
    NormalPush(q, x, p0, nrm, dist < reach ? k * (reach - dist) : 0.0, k, mu, anchor, f, sum);
  }
}

void DiscContact(PetscInt n, const PetscReal *x, const PetscReal *inv_m, const PetscReal top[3], PetscReal radius,
                 PetscReal height, PetscReal reach, PetscReal k, PetscReal mu, PetscReal *anchor, PetscReal *f,
                 PetscReal sum[3])
{
  for (PetscInt q = 0; q < n; q++) {
    if (inv_m[q] <= 0) continue;
    const PetscReal dx = x[3 * q] - top[0], dy = x[3 * q + 1] - top[1], dz = x[3 * q + 2] - top[2];
    const PetscReal rho   = PetscSqrtReal(dx * dx + dy * dy);
    const PetscReal ur[2] = {rho > 0 ? dx / rho : 1.0, rho > 0 ? dy / rho : 0.0}; /* radial unit */
    const PetscReal out_r = rho - radius, out_z = dz > 0 ? dz : (dz < -height ? dz + height : 0.0);
    PetscReal       nrm[3], dist;
    if (out_r > 0 || out_z != 0) { /* outside: distance to the nearest point of the cylinder */
      const PetscReal er = PetscMax(out_r, 0.0);
      dist               = PetscSqrtReal(er * er + out_z * out_z);
      nrm[0] = er * ur[0] / dist, nrm[1] = er * ur[1] / dist, nrm[2] = out_z / dist;
    } else { /* inside: out through the nearest face */
      const PetscReal d_top = -dz, d_rim = radius - rho, d_bot = dz + height;
      if (d_top <= d_rim && d_top <= d_bot)
        dist = -d_top, nrm[0] = 0, nrm[1] = 0, nrm[2] = 1;
      else if (d_rim <= d_bot)
        dist = -d_rim, nrm[0] = ur[0], nrm[1] = ur[1], nrm[2] = 0;
      else
        dist = -d_bot, nrm[0] = 0, nrm[1] = 0, nrm[2] = -1;
    }
    NormalPush(q, x, top, nrm, dist < reach ? k * (reach - dist) : 0.0, k, mu, anchor, f, sum);
  }
}
