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
   bound is the frictionless one. Adds ft to f. */
static inline void StickSlip(const PetscReal rel[3], const PetscReal n[3], PetscReal fn, PetscReal k, PetscReal mu,
                             PetscReal a[3], PetscReal f[3])
{
  PetscReal t[3], dn = 0, t2 = 0;
  for (int d = 0; d < 3; d++) t[d] = rel[d] - a[d], dn += t[d] * n[d];
  for (int d = 0; d < 3; d++) t[d] -= dn * n[d], t2 += t[d] * t[d];
  PetscReal scale = -k; /* ft = scale * t */
  if (k * k * t2 > mu * mu * fn * fn) {
    scale = -mu * fn / PetscSqrtReal(t2);
    for (int d = 0; d < 3; d++) a[d] = rel[d] + scale * t[d] / k;
  }
  for (int d = 0; d < 3; d++) f[d] += scale * t[d];
}

/* The normal push fv (= fn n) on point q, and friction if anchors are kept; a point out of
   contact (fn <= 0) has its anchor reset to where it is. */
static inline void ContactForce(PetscInt q, const PetscReal *x, const PetscReal c[3], const PetscReal n[3],
                                PetscReal fn, const PetscReal fv[3], PetscReal k, PetscReal mu, PetscReal *anchor,
                                PetscReal *f)
{
  if (fn <= 0) {
    if (anchor)
      for (int d = 0; d < 3; d++) anchor[3 * q + d] = x[3 * q + d] - c[d];
    return;
  }
  for (int d = 0; d < 3; d++) f[3 * q + d] += fv[d];
  if (anchor && mu > 0) {
    const PetscReal rel[3] = {x[3 * q] - c[0], x[3 * q + 1] - c[1], x[3 * q + 2] - c[2]};
    StickSlip(rel, n, fn, k, mu, anchor + 3 * q, f + 3 * q);
  }
}

void SphereContact(PetscInt n, const PetscReal *x, const PetscReal *inv_m, const PetscReal c[3], PetscReal reach,
                   PetscReal k, PetscReal mu, PetscReal *anchor, PetscReal *f)
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
    ContactForce(q, x, c, nrm, fn, fv, k, mu, anchor, f);
  }
}

/* a push fn along the unit normal n (plane, disc) */
static inline void NormalPush(PetscInt q, const PetscReal *x, const PetscReal c[3], const PetscReal n[3], PetscReal fn,
                              PetscReal k, PetscReal mu, PetscReal *anchor, PetscReal *f)
{
  const PetscReal fv[3] = {fn * n[0], fn * n[1], fn * n[2]};
  ContactForce(q, x, c, n, fn, fv, k, mu, anchor, f);
}

void PlaneContact(PetscInt n, const PetscReal *x, const PetscReal *inv_m, const PetscReal p0[3], const PetscReal nrm[3],
                  PetscReal reach, PetscReal k, PetscReal mu, PetscReal *anchor, PetscReal *f)
{
  for (PetscInt q = 0; q < n; q++) {
    if (inv_m[q] <= 0) continue;
    const PetscReal dist =
        (x[3 * q] - p0[0]) * nrm[0] + (x[3 * q + 1] - p0[1]) * nrm[1] + (x[3 * q + 2] - p0[2]) * nrm[2];
    NormalPush(q, x, p0, nrm, dist < reach ? k * (reach - dist) : 0.0, k, mu, anchor, f);
  }
}

void DiscContact(PetscInt n, const PetscReal *x, const PetscReal *inv_m, const PetscReal top[3], PetscReal radius,
                 PetscReal height, PetscReal reach, PetscReal k, PetscReal mu, PetscReal *anchor, PetscReal *f)
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
    NormalPush(q, x, top, nrm, dist < reach ? k * (reach - dist) : 0.0, k, mu, anchor, f);
  }
}

const char *const BodyNames[BODY_KINDS] = {"sphere", "plane", "pedestal"};

void BodyPosition(const Body *b, PetscReal travel, PetscReal c[3])
{
  for (int d = 0; d < 3; d++) c[d] = b->kind == BODY_SPHERE ? b->ref[d] + travel * b->dir[d] : b->ref[d];
}

void BodyContact(const Body *b, const PetscReal c[3], PetscInt n, const PetscReal *x, const PetscReal *inv_m,
                 PetscReal *anchor, PetscReal *f)
{
  switch (b->kind) {
  case BODY_SPHERE: SphereContact(n, x, inv_m, c, b->reach, b->k, b->mu, anchor, f); break;
  case BODY_PLANE: PlaneContact(n, x, inv_m, c, b->dir, b->reach, b->k, b->mu, anchor, f); break;
  default: DiscContact(n, x, inv_m, c, b->radius, b->height, b->reach, b->k, b->mu, anchor, f);
  }
}

/* K -= k p dn/dx: the Hessian part of a penalty whose normal n turns as the point moves, with
   dn/dx = cm (I - n n^T - t t^T) + ct t t^T for a unit hoop direction t normal to n (t = NULL:
   dn/dx = cm (I - n n^T), a sphere) */
static void PenaltyCurvature(PetscReal K[9], PetscReal kp, const PetscReal n[3], const PetscReal *t, PetscReal cm,
                             PetscReal ct)
{
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      const PetscReal tt = t ? t[i] * t[j] : 0.0;
      K[3 * i + j] -= kp * (cm * ((i == j) - n[i] * n[j] - tt) + ct * tt);
    }
}

/* The penalty energy E = 0.5 k p^2, p = reach - distance > 0. With n the outward unit normal,
   dE/dx = -k p n; d2E/dx2 = k n n^T - k p dn/dx, where dn/dx = (I - n n^T)/r around a centre at
   distance r (the sphere, the pedestal's rim edge) and 0 on a flat face (plane, top, rim). */
PetscReal BodyEnergy(const Body *b, const PetscReal c[3], const PetscReal x[3], PetscReal g[3], PetscReal K[9])
{
  PetscReal f[3] = {0, 0, 0}, one = 1.0, nrm[3], p;
  Body      unit = *b; /* the push with unit stiffness and no friction is p n */

  unit.k = 1.0, unit.mu = 0.0;
  for (int q = 0; q < 9; q++) K[q] = 0;
  for (int d = 0; d < 3; d++) g[d] = 0;
  BodyContact(&unit, c, 1, x, &one, NULL, f);
  p = PetscSqrtReal(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]); /* |f| = 1 * p with unit stiffness */
  if (!(p > 0)) return 0.0;
  for (int d = 0; d < 3; d++) nrm[d] = f[d] / p, g[d] = -b->k * p * nrm[d];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) K[3 * i + j] = b->k * nrm[i] * nrm[j];
  if (b->kind == BODY_SPHERE) PenaltyCurvature(K, b->k * p, nrm, NULL, 1.0 / (b->reach - p), 0.0);
  if (b->kind == BODY_PEDESTAL) { /* the rim turns with the hoop; the rounded edge also bends in its own plane */
    const PetscReal dx = x[0] - c[0], dy = x[1] - c[1], rho = PetscSqrtReal(dx * dx + dy * dy);
    const PetscReal t[3] = {rho > 0 ? -dy / rho : 0.0, rho > 0 ? dx / rho : 1.0, 0}, d = b->reach - p;
    if (PetscAbsReal(nrm[2]) < 1e-12)
      PenaltyCurvature(K, b->k * p, nrm, t, 0.0, 1.0 / rho);
    else if (PetscAbsReal(nrm[2]) < 1.0 - 1e-12)
      PenaltyCurvature(K, b->k * p, nrm, t, 1.0 / d, (1.0 - b->radius / rho) / d);
  }
  return 0.5 * b->k * p * p;
}
