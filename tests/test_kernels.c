/* test_kernels.c - unit tests of the force terms and the yarn law (MODEL.md 5.1-5.3, 7.3, 14).
 *
 *  forces:   the kernel's forces equal minus the gradient of the energies of MODEL.md 5.1-5.3,
 *            written here independently (linear laws, sharp kinks) and differentiated by central
 *            differences, on a randomly distorted grid with absent points (holes, a cut corner)
 *            that exercises compression, de-crimping, extension, one-sided shear at edges and
 *            jamming (and sheared the other way: jamming at negative shear angles); the kernel's energy
 *            (InternalEnergy) equals the one written here.
 *  law:      d/de ChordEnergy = ChordTension and ChordTensionSlope = dT/de (central differences)
 *            over every regime of a linear and a tabulated law with smoothing blends; the energy's
 *            increments equal Gauss integrals of T.
 *  terms:    on a distorted patch with crimp, a tabulated warp law, smoothing blends, jamming on
 *            some crossings, edges, absent points and broken segments, each term alone and all together:
 *            (a) forces = -grad(energy) by central differences; the instances' gradients = the forces;
 *            (b) tangent = central differences of the forces; the DMDA matrix (dof 3, box stencil
 *                width 2) assembled with TermBlocksAddToMat = the same tangent;
 *            energy and tangent over sub-boxes add up to the whole patch's.
 *  identity: (c) StableOmega2 and the per-term row bounds, (d) ComputeInternalForces: bit-identical
 *            to the implementation before the terms were split (kept below as the reference).
 *  table:    the fast yarn table equals GSL's Steffen spline of the CSV, and extends linearly.
 *  tangent:  ChordTangentMax of the piecewise-linear law over strain windows; of the tabulated and
 *            linear laws with blends: at least the law's slope in any window; the blends join the
 *            law C1.
 *  fields:   PointFields (tensions, shear angle) on a uniformly stretched, sheared grid; the
 *            quasi-static path's traction tangent (tension_field) is the convex one.
 *  bodies:   contact energy, gradient and Hessian on every face (the pedestal's bottom too); the push by hand;
 *            friction.
 *  breaking: a yarn's breaking chord strain c + break_ey (1 + c).
 */
#include "bodies.h"
#include "kernels.h"

#include <gsl/gsl_interp.h>
#include <math.h>
#include <petscdmda.h>
#include <string.h>

static int failures = 0;

static void Check(const char *what, double err, double tol)
{
  int ok = err <= tol;
  printf("%s %s: %.3e (tolerance %.1e)\n", ok ? "PASS" : "FAIL", what, err, tol);
  if (!ok) failures++;
}

#define NX 9
#define NY 7
#define NP (NX * NY)

/* ================= the reference: the pipeline and the bound before the split ================= */
/* A verbatim copy (names prefixed Ref, lines wrapped) of kernels.c at adb6773, so that a change of
   the kernels' floating-point expressions or summation order shows as a bit difference. */

#define STRAIN_ROUNDOFF 1e-12
#define SLOT(r)         ((((r) % KERNEL_RING) + KERNEL_RING) % KERNEL_RING)

/* padded existence of the point at local (li, lj); -1 and gxm/gym are absent */
static inline unsigned char RefExists(const Patch *p, PetscInt li, PetscInt lj)
{
  return p->epad[(lj + 1) * (p->gxm + 2) + li + 1];
}

static void RefZeroSegmentRow(SegmentRow *s, PetscInt c0, PetscInt c1)
{
  PetscReal *a[] = {s->ux, s->uy, s->uz, s->inv_len, s->fx, s->fy, s->fz, s->T};
  for (int k = 0; k < 8; k++) memset(a[k] + c0, 0, sizeof(PetscReal) * (size_t) (c1 - c0));
}

/* Segments a[i] -> b[i], c0 <= i < c1: chord and tension (MODEL.md 5.1). */
static void RefComputeSegmentRow(const YarnLaw *law, PetscReal L0, PetscBool traction, PetscInt c0, PetscInt c1,
                                 const PetscReal *restrict xa, const PetscReal *restrict xb, const unsigned char *ea,
                                 const unsigned char *eb, const unsigned char *broken, SegmentRow *s)
{
  const PetscReal inv_L0 = 1.0 / L0;

  for (PetscInt i = c0; i < c1; i++) {
    const PetscReal dx = xb[3 * i] - xa[3 * i], dy = xb[3 * i + 1] - xa[3 * i + 1], dz = xb[3 * i + 2] - xa[3 * i + 2];
    const PetscReal L = PetscSqrtReal(dx * dx + dy * dy + dz * dz), e_raw = L * inv_L0 - 1.0;
    const PetscReal e     = PetscAbsReal(e_raw) < STRAIN_ROUNDOFF ? 0.0 : e_raw;
    const int       alive = ea[i] && eb[i] && !broken[i];
    const PetscReal inv   = alive ? 1.0 / L : 0.0;
    const PetscReal T     = (alive && traction) ? ChordTension(law, e) : 0.0;
    s->ux[i]              = dx * inv;
    s->uy[i]              = dy * inv;
    s->uz[i]              = dz * inv;
    s->inv_len[i]         = inv;
    s->T[i]               = T;
    s->fx[i]              = T * dx * inv;
    s->fy[i]              = T * dy * inv;
    s->fz[i]              = T * dz * inv;
  }
}

/* Bending centres c0 <= i < c1 with incoming chord s1[i] and outgoing chord s2[i] (MODEL.md 5.2). */
static void RefComputeBendRow(PetscReal kb, PetscInt c0, PetscInt c1, const PetscReal *u1x, const PetscReal *u1y,
                              const PetscReal *u1z, const PetscReal *i1, const PetscReal *u2x, const PetscReal *u2y,
                              const PetscReal *u2z, const PetscReal *i2, BendRow *b, PetscInt off)
{
  /* u2 - s u1 = (u1 x u2) x u1 and u1 - s u2 = u2 x (u1 x u2): the cross-product form has no
     cancellation for nearly straight yarns and is exactly zero for parallel chords */
  for (PetscInt i = c0; i < c1; i++) {
    const PetscReal cx = u1y[i] * u2z[i] - u1z[i] * u2y[i], cy = u1z[i] * u2x[i] - u1x[i] * u2z[i],
                    cz = u1x[i] * u2y[i] - u1y[i] * u2x[i];
    const PetscReal c1 = kb * i1[i], c2 = kb * i2[i];
    b->g1x[i + off] = c1 * (cy * u1z[i] - cz * u1y[i]);
    b->g1y[i + off] = c1 * (cz * u1x[i] - cx * u1z[i]);
    b->g1z[i + off] = c1 * (cx * u1y[i] - cy * u1x[i]);
    b->g2x[i + off] = c2 * (u2y[i] * cz - u2z[i] * cy);
    b->g2y[i + off] = c2 * (u2z[i] * cx - u2x[i] * cz);
    b->g2z[i + off] = c2 * (u2x[i] * cy - u2y[i] * cx);
  }
}

/* Shear crossings of row r (global), local columns [c0, c1) (MODEL.md 5.3). */
static void RefComputeShearRow(const Patch *p, const PetscReal *x, PetscInt r, PetscInt c0, PetscInt c1, ShearRow *sh)
{
  const PetscInt   n = p->gxm, lr = r - p->gys;
  const PetscReal *xr = (lr >= 0 && lr < p->gym) ? x + 3 * lr * n : p->zero_row;
  const PetscReal *xd = (lr - 1 >= 0 && lr - 1 < p->gym) ? x + 3 * (lr - 1) * n : p->zero_row;
  const PetscReal *xu = (lr + 1 >= 0 && lr + 1 < p->gym) ? x + 3 * (lr + 1) * n : p->zero_row;
  const PetscReal  Ks = p->Ks, Kj = p->Kj, sl = p->s_lock;

  if (lr < 0 || lr >= p->gym) { /* no crossing outside the patch */
    PetscReal *a[] = {sh->hwx, sh->hwy, sh->hwz, sh->hfx, sh->hfy, sh->hfz, sh->sx, sh->sy, sh->sz};
    for (int k = 0; k < 9; k++) memset(a[k] + c0, 0, sizeof(PetscReal) * (size_t) (c1 - c0));
    return;
  }
  for (PetscInt li = c0; li < c1; li++) {
    const int        self = RefExists(p, li, lr), hl = RefExists(p, li - 1, lr), hr = RefExists(p, li + 1, lr);
    const int        hd = RefExists(p, li, lr - 1), hu = RefExists(p, li, lr + 1);
    const PetscInt   il = hl ? li - 1 : li, ir = hr ? li + 1 : li;
    const PetscReal *xp = xr + 3 * ir, *xm = xr + 3 * il, *yp = hu ? xu + 3 * li : xr + 3 * li,
                    *ym = hd ? xd + 3 * li : xr + 3 * li;
    const PetscReal twx = xp[0] - xm[0], twy = xp[1] - xm[1], twz = xp[2] - xm[2];
    const PetscReal tfx = yp[0] - ym[0], tfy = yp[1] - ym[1], tfz = yp[2] - ym[2];
    const int       active = self && (hl || hr) && (hd || hu);
    const PetscReal iw     = active ? 1.0 / PetscSqrtReal(twx * twx + twy * twy + twz * twz) : 0.0;
    const PetscReal jf     = active ? 1.0 / PetscSqrtReal(tfx * tfx + tfy * tfy + tfz * tfz) : 0.0;
    const PetscReal uwx = twx * iw, uwy = twy * iw, uwz = twz * iw, ufx = tfx * jf, ufy = tfy * jf, ufz = tfz * jf;
    const PetscReal s = uwx * ufx + uwy * ufy + uwz * ufz, as = PetscAbsReal(s);
    const PetscReal jam = as > sl ? (s > 0 ? as - sl : sl - as) : 0.0;
    const PetscReal Ep  = Ks * s + Kj * jam;
    const PetscReal cw = Ep * iw, cf = Ep * jf;
    const PetscReal hwx = cw * (ufx - s * uwx), hwy = cw * (ufy - s * uwy), hwz = cw * (ufz - s * uwz);
    const PetscReal hfx = cf * (uwx - s * ufx), hfy = cf * (uwy - s * ufy), hfz = cf * (uwz - s * ufz);
    const PetscReal aw = (PetscReal) (hr - hl), af = (PetscReal) (hu - hd);
    sh->hwx[li] = hwx;
    sh->hwy[li] = hwy;
    sh->hwz[li] = hwz;
    sh->hfx[li] = hfx;
    sh->hfy[li] = hfy;
    sh->hfz[li] = hfz;
    sh->sx[li]  = aw * hwx + af * hfx;
    sh->sy[li]  = aw * hwy + af * hfy;
    sh->sz[li]  = aw * hwz + af * hfz;
  }
}

/* y-segments between rows r and r+1, local columns [c0, c1) */
static void RefYSegments(Patch *p, const PetscReal *x, PetscInt r, PetscInt c0, PetscInt c1)
{
  const PetscInt n = p->gxm, lr = r - p->gys;
  SegmentRow    *s = &p->ys_ring[SLOT(r)];

  if (lr < 0 || lr + 1 >= p->gym) {
    RefZeroSegmentRow(s, c0, c1);
    return;
  }
  RefComputeSegmentRow(p->weft, p->ay, p->traction, c0, c1, x + 3 * lr * n, x + 3 * (lr + 1) * n, p->exists + lr * n,
                       p->exists + (lr + 1) * n, p->broken_y + lr * n, s);
}

/* y-bending centres of row r: chords y(r-1) and y(r) */
static void RefYBending(Patch *p, PetscInt r, PetscInt c0, PetscInt c1)
{
  const SegmentRow *a = &p->ys_ring[SLOT(r - 1)], *b = &p->ys_ring[SLOT(r)];
  RefComputeBendRow(p->kby, c0, c1, a->ux, a->uy, a->uz, a->inv_len, b->ux, b->uy, b->uz, b->inv_len,
                    &p->by_ring[SLOT(r)], 0);
}

static void RefComputeInternalForces(Patch *p, const PetscReal *x, const PetscInt box[4], PetscReal *f,
                                     PetscReal *tension_max)
{
  const PetscInt  n = p->gxm, i0 = box[0] - p->gxs, i1 = box[1] - p->gxs, j0 = box[2], j1 = box[3];
  const PetscInt  c0 = PetscMax(i0 - 2, 0), c1 = PetscMin(i1 + 2, n); /* columns the box's forces need */
  const PetscBool bend = p->bending, shear = p->shear;
  PetscReal       tmax = 0.0;

  *tension_max = 0.0;
  if (i1 <= i0 || j1 <= j0) return;
  /* prime the pipeline: rows below the first row of the box */
  for (PetscInt r = j0 - 2; r <= j0; r++) RefYSegments(p, x, r, c0, c1);
  if (bend)
    for (PetscInt r = j0 - 1; r <= j0; r++) RefYBending(p, r, c0, c1);
  if (shear)
    for (PetscInt r = j0 - 1; r <= j0; r++) RefComputeShearRow(p, x, r, c0, c1, &p->sh_ring[SLOT(r)]);

  for (PetscInt j = j0; j < j1; j++) {
    const PetscInt lj = j - p->gys;
    SegmentRow    *xs = &p->xs_row;

    /* advance the pipeline by one row */
    RefYSegments(p, x, j + 1, c0, c1);
    if (bend) RefYBending(p, j + 1, c0, c1);
    if (shear) RefComputeShearRow(p, x, j + 1, c0, c1, &p->sh_ring[SLOT(j + 1)]);
    RefComputeSegmentRow(p->warp, p->ax, p->traction, c0, PetscMin(c1, n - 1), x + 3 * lj * n, x + 3 * lj * n + 3,
                         p->exists + lj * n, p->exists + lj * n + 1, p->broken_x + lj * n, xs);
    if (bend)
      RefComputeBendRow(p->kbx, c0, PetscMin(c1, n - 1) - 1, xs->ux, xs->uy, xs->uz, xs->inv_len, xs->ux + 1,
                        xs->uy + 1, xs->uz + 1, xs->inv_len + 1, &p->bx_row, 1);

    /* gather: each point of row j in the box sums its terms in a fixed order */
    {
      const SegmentRow *yd = &p->ys_ring[SLOT(j - 1)], *yu = &p->ys_ring[SLOT(j)];
      PetscReal *restrict fr = f + 3 * (j - p->ys) * p->xm - 3 * (p->xs - p->gxs);
      for (PetscInt i = i0; i < i1; i++) {
        fr[3 * i]         = xs->fx[i] - xs->fx[i - 1] + yu->fx[i] - yd->fx[i];
        fr[3 * i + 1]     = xs->fy[i] - xs->fy[i - 1] + yu->fy[i] - yd->fy[i];
        fr[3 * i + 2]     = xs->fz[i] - xs->fz[i - 1] + yu->fz[i] - yd->fz[i];
        const PetscReal t = PetscMax(PetscMax(PetscAbsReal(xs->T[i]), PetscAbsReal(xs->T[i - 1])),
                                     PetscMax(PetscAbsReal(yu->T[i]), PetscAbsReal(yd->T[i])));
        tmax              = PetscMax(tmax, t);
      }
      if (bend) {
        const BendRow *bx = &p->bx_row, *bd = &p->by_ring[SLOT(j - 1)], *bc = &p->by_ring[SLOT(j)],
                      *bu = &p->by_ring[SLOT(j + 1)];
        for (PetscInt i = i0; i < i1; i++) {
          fr[3 * i] += bx->g2x[i - 1] + bx->g1x[i] - bx->g2x[i] - bx->g1x[i + 1] + bd->g2x[i] + bc->g1x[i] -
                       bc->g2x[i] - bu->g1x[i];
          fr[3 * i + 1] += bx->g2y[i - 1] + bx->g1y[i] - bx->g2y[i] - bx->g1y[i + 1] + bd->g2y[i] + bc->g1y[i] -
                           bc->g2y[i] - bu->g1y[i];
          fr[3 * i + 2] += bx->g2z[i - 1] + bx->g1z[i] - bx->g2z[i] - bx->g1z[i + 1] + bd->g2z[i] + bc->g1z[i] -
                           bc->g2z[i] - bu->g1z[i];
        }
      }
      if (shear) {
        const ShearRow *sd = &p->sh_ring[SLOT(j - 1)], *sc = &p->sh_ring[SLOT(j)], *su = &p->sh_ring[SLOT(j + 1)];
        for (PetscInt i = i0; i < i1; i++) {
          fr[3 * i] += sc->hwx[i + 1] - sc->hwx[i - 1] + su->hfx[i] - sd->hfx[i] + sc->sx[i];
          fr[3 * i + 1] += sc->hwy[i + 1] - sc->hwy[i - 1] + su->hfy[i] - sd->hfy[i] + sc->sy[i];
          fr[3 * i + 2] += sc->hwz[i + 1] - sc->hwz[i - 1] + su->hfz[i] - sd->hfz[i] + sc->sz[i];
        }
      }
    }
  }
  *tension_max = tmax;
}
/* ---------------- stable step: the bound on the tangent stiffness over a window ---------------- */

typedef struct {
  PetscReal L; /* chord length */
  int       alive;
} RefChord;

static inline const PetscReal *RefPos(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j)
{
  return x + 3 * ((j - p->gys) * p->gxm + (i - p->gxs));
}

/* existence of the point at global (i, j); points beyond the ghosted patch (two or more
   crossings outside the grid, where the padding of epad ends) do not exist */
static inline int RefExistsG(const Patch *p, PetscInt i, PetscInt j)
{
  const PetscInt li = i - p->gxs, lj = j - p->gys;
  if (li < -1 || li > p->gxm || lj < -1 || lj > p->gym) return 0;
  return RefExists(p, li, lj);
}

/* chord from (i,j) along x (dir 0) or y (dir 1) */
static RefChord RefChordAt(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, int dir)
{
  RefChord       c  = {0.0, 0};
  const PetscInt i2 = i + (dir == 0), j2 = j + (dir == 1);
  if (!RefExistsG(p, i, j) || !RefExistsG(p, i2, j2)) return c;
  const unsigned char *broken = dir == 0 ? p->broken_x : p->broken_y;
  if (broken[(j - p->gys) * p->gxm + (i - p->gxs)]) return c;
  const PetscReal *a = RefPos(p, x, i, j), *b = RefPos(p, x, i2, j2);
  c.L     = PetscSqrtReal(PetscSqr(b[0] - a[0]) + PetscSqr(b[1] - a[1]) + PetscSqr(b[2] - a[2]));
  c.alive = 1;
  return c;
}

/* The cosine s of the angle between crossing (i,j)'s warp tangent x(i+1,j) - x(i-1,j) and
   weft tangent x(i,j+1) - x(i,j-1), one-sided at an edge (MODEL.md 5.3), and the shorter
   tangent's length. 0 if the crossing has no shear (absent, or no warp or no weft neighbour). */
static int RefCrossingShear(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, PetscReal *s, PetscReal *tmin)
{
  if (!RefExistsG(p, i, j)) return 0;
  const int hl = RefExistsG(p, i - 1, j), hr = RefExistsG(p, i + 1, j), hd = RefExistsG(p, i, j - 1),
            hu = RefExistsG(p, i, j + 1);
  if (!(hl || hr) || !(hd || hu)) return 0;
  const PetscReal *xp = RefPos(p, x, hr ? i + 1 : i, j), *xm = RefPos(p, x, hl ? i - 1 : i, j);
  const PetscReal *yp = RefPos(p, x, i, hu ? j + 1 : j), *ym = RefPos(p, x, i, hd ? j - 1 : j);
  PetscReal        tw[3], tf[3];
  for (int d = 0; d < 3; d++) {
    tw[d] = xp[d] - xm[d];
    tf[d] = yp[d] - ym[d];
  }
  const PetscReal nw = PetscSqrtReal(tw[0] * tw[0] + tw[1] * tw[1] + tw[2] * tw[2]),
                  nf = PetscSqrtReal(tf[0] * tf[0] + tf[1] * tf[1] + tf[2] * tf[2]);
  if (!(nw > 0 && nf > 0)) return 0;
  *s    = PetscMax(-1.0, PetscMin(1.0, (tw[0] * tf[0] + tw[1] * tf[1] + tw[2] * tf[2]) / (nw * nf)));
  *tmin = PetscMin(nw, nf);
  return 1;
}

/* Gershgorin contribution of crossing (i,j)'s shear energy to one of its points, for any |s| up
   to s_hi: |E''| |grad s|_a sum_b |grad s|_b + |E'| |hess s| row <= (Ks+Kj)(4 + 12 s_hi)/tmin^2;
   the jamming stiffness counts once s_hi reaches the lock */
static PetscReal RefShearRowBound(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, PetscReal s_hi)
{
  PetscReal s, tmin;
  if (!RefCrossingShear(p, x, i, j, &s, &tmin)) return 0.0;
  return (p->Ks + (s_hi >= p->s_lock ? p->Kj : 0.0)) * (4.0 + 12.0 * PetscMin(s_hi, 1.0)) / (tmin * tmin);
}

/* the window of the owned points' state widened by margin: lo[d], hi[d] the chord strains of
   family d, *s_hi the largest |sin(shear angle)| */
/* the state's range: the smallest and largest chord strain of each family (emin > emax: none) and
   the largest |s| (0 if none) over the owned crossings */
static void RefWindowRange(const Patch *p, const PetscReal *x, PetscReal emin[2], PetscReal emax[2], PetscReal *smax)
{
  emin[0] = emin[1] = 1e300, emax[0] = emax[1] = -1e300, *smax = 0.0;
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
    for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
      PetscReal s, tmin;
      for (int dir = 0; dir < 2; dir++) {
        const RefChord c = RefChordAt(p, x, i, j, dir);
        if (!c.alive) continue;
        const PetscReal e = c.L / (dir == 0 ? p->ax : p->ay) - 1.0;
        emin[dir] = PetscMin(emin[dir], e), emax[dir] = PetscMax(emax[dir], e);
      }
      if (p->shear && RefCrossingShear(p, x, i, j, &s, &tmin)) *smax = PetscMax(*smax, PetscAbsReal(s));
    }
}

/* WindowRange's r = {-min e_warp, max e_warp, -min e_weft, max e_weft, max |s|} (-PETSC_MAX_REAL where
   there is none) against the reference's range, value for value: 0 if the same */
static int RefWindowRangeDiffers(const Patch *p, const PetscReal *x, const PetscReal r[5])
{
  PetscReal emin[2], emax[2], smax;
  int       bad = 0;
  RefWindowRange(p, x, emin, emax, &smax);
  for (int dir = 0; dir < 2; dir++)
    if (emin[dir] > emax[dir]) bad += r[2 * dir] != -PETSC_MAX_REAL || r[2 * dir + 1] != -PETSC_MAX_REAL;
    else bad += r[2 * dir] != -emin[dir] || r[2 * dir + 1] != emax[dir];
  bad += PetscMax(r[4], 0.0) != smax;
  return bad;
}

static void RefWindow(const Patch *p, const PetscReal *x, PetscReal margin, PetscReal lo[2], PetscReal hi[2],
                      PetscReal *s_hi)
{
  PetscReal emin[2], emax[2], smax;
  RefWindowRange(p, x, emin, emax, &smax);
  for (int dir = 0; dir < 2; dir++) {
    lo[dir] = emin[dir] > emax[dir] ? 0.0 : emin[dir] - margin;
    hi[dir] = emin[dir] > emax[dir] ? 0.0 : emax[dir] + margin;
  }
  *s_hi = smax + margin;
}

/* the largest eigenvalue of a symmetric 3x3 matrix by cyclic Jacobi rotations */
static PetscReal RefMaxEig3(const PetscReal A[3][3])
{
  PetscReal a[3][3];
  memcpy(a, A, sizeof a);
  for (int sweep = 0; sweep < 50; sweep++) {
    const PetscReal off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    if (off <= 1e-34 * (a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2])) break;
    for (int pp = 0; pp < 2; pp++)
      for (int q = pp + 1; q < 3; q++) {
        if (a[pp][q] == 0.0) continue;
        const PetscReal th = (a[q][q] - a[pp][pp]) / (2.0 * a[pp][q]);
        const PetscReal t  = (th >= 0 ? 1.0 : -1.0) / (PetscAbsReal(th) + PetscSqrtReal(th * th + 1.0));
        const PetscReal c = 1.0 / PetscSqrtReal(t * t + 1.0), sn = t * c;
        for (int k = 0; k < 3; k++) { /* columns pp, q */
          const PetscReal akp = a[k][pp], akq = a[k][q];
          a[k][pp] = c * akp - sn * akq, a[k][q] = sn * akp + c * akq;
        }
        for (int k = 0; k < 3; k++) { /* rows pp, q */
          const PetscReal apk = a[pp][k], aqk = a[q][k];
          a[pp][k] = c * apk - sn * aqk, a[q][k] = sn * apk + c * aqk;
        }
      }
  }
  return PetscMax(PetscMax(a[0][0], a[1][1]), a[2][2]);
}

static PetscReal RefStableOmega2(const Patch *p, const PetscReal *x, const PetscReal *inv_m, const PetscReal lo[2],
                                 const PetscReal hi[2], PetscReal s_hi, int pull_dir, PetscReal *omega2_pull)
{
  PetscReal omega2 = 0.0, pull2 = 0.0;

  for (PetscInt j = p->ys; j < p->ys + p->ym; j++) {
    for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
      const PetscReal im = inv_m[(j - p->ys) * p->xm + (i - p->xs)];
      PetscReal       rs = 0.0, rp = 0.0, B[3][3] = {{0}};
      if (im <= 0.0) continue;
      /* traction: each segment's block k n n^T + max(T,0)/L (I - n n^T), k the largest yarn
         tangent in its family's window over L0; the point's row is 2 lambda_max of their sum */
      for (int dir = 0; dir < 2 && p->traction; dir++) {
        const YarnLaw  *law = dir == 0 ? p->warp : p->weft;
        const PetscReal L0  = dir == 0 ? p->ax : p->ay;
        const PetscReal k   = ChordTangentMax(law, lo[dir], hi[dir]) / L0;
        for (int side = -1; side <= 0; side++) {
          const PetscInt ia = i + (dir == 0 ? side : 0), ja = j + (dir == 1 ? side : 0);
          const RefChord c = RefChordAt(p, x, ia, ja, dir);
          if (!c.alive) continue;
          const PetscReal *a = RefPos(p, x, ia, ja), *b = RefPos(p, x, ia + (dir == 0), ja + (dir == 1));
          const PetscReal  e = c.L / L0 - 1.0, T = ChordTension(law, e), g = PetscMax(T, 0.0) / c.L;
          PetscReal        n[3];
          for (int d = 0; d < 3; d++) n[d] = (b[d] - a[d]) / c.L;
          for (int r = 0; r < 3; r++)
            for (int q = 0; q < 3; q++) B[r][q] += k * n[r] * n[q] + g * ((r == q) - n[r] * n[q]);
          if (dir == pull_dir)
            rp += 2.0 * PetscMax(ChordTangentMax(law, e, e + 0.005) / L0,
                                 PetscAbsReal(T) / c.L); /* current stiffness, tension side */
        }
      }
      if (p->traction) rs += 2.0 * RefMaxEig3(B);
      /* bending: centre c in {p-1, p, p+1}; row sums 12, 24, 12 times kb / Lmin^2, with
         Lmin no longer than the contact length (a chord can be squeezed that far in a step) */
      if (p->bending) {
        for (int dir = 0; dir < 2; dir++) {
          const PetscReal kb = dir == 0 ? p->kbx : p->kby;
          const PetscReal Lc = (1.0 + (dir == 0 ? p->warp : p->weft)->e_contact) * (dir == 0 ? p->ax : p->ay);
          for (int k = -1; k <= 1; k++) {
            const PetscInt ic = i + (dir == 0 ? k : 0), jc = j + (dir == 1 ? k : 0);
            const RefChord c1 = RefChordAt(p, x, ic - (dir == 0), jc - (dir == 1), dir),
                           c2 = RefChordAt(p, x, ic, jc, dir);
            if (!c1.alive || !c2.alive) continue;
            const PetscReal Lmin = PetscMin(PetscMin(c1.L, c2.L), Lc);
            rs += kb * (k == 0 ? 24.0 : 12.0) / (Lmin * Lmin);
          }
        }
      }
      /* shear: the crossings that involve this point */
      if (p->shear) {
        rs += RefShearRowBound(p, x, i - 1, j, s_hi) + RefShearRowBound(p, x, i + 1, j, s_hi) +
              RefShearRowBound(p, x, i, j - 1, s_hi) + RefShearRowBound(p, x, i, j + 1, s_hi);
        if (!RefExistsG(p, i - 1, j) || !RefExistsG(p, i + 1, j) || !RefExistsG(p, i, j - 1) ||
            !RefExistsG(p, i, j + 1))
          rs += RefShearRowBound(p, x, i, j, s_hi);
      }
      /* the rigid bodies: k_contact in every direction; the frictionless ones k n n^T along their
         normal n at the point, joined to the traction block */
      rs += p->k_contact;
      if (p->ncb) {
        const PetscReal *xp = RefPos(p, x, i, j);
        PetscReal        C[3][3], turn = 0.0, ksum = 0.0;
        memcpy(C, B, sizeof C);
        for (int q = 0; q < p->ncb; q++) {
          const ContactBound *b = &p->cb[q];
          PetscReal           n[3] = {b->n[0], b->n[1], b->n[2]}, r = 0.0;
          if (b->sphere) {
            for (int d = 0; d < 3; d++) n[d] = xp[d] - b->c[d], r += n[d] * n[d];
            r = PetscSqrtReal(r);
            for (int d = 0; d < 3; d++) n[d] = r > 0 ? n[d] / r : 0.0;
            if (r > 0) turn += b->k * PetscMin(b->span / r, 1.0); /* sin(theta) <= span / r */
          }
          ksum += b->k;
          for (int a = 0; a < 3; a++)
            for (int c = 0; c < 3; c++) C[a][c] += 0.5 * b->k * (b->sphere && r == 0 ? (a == c) : n[a] * n[c]);
        }
        rs += PetscMin(2.0 * RefMaxEig3(C) - (p->traction ? 2.0 * RefMaxEig3(B) : 0.0) + turn, ksum);
      }
      omega2 = PetscMax(omega2, rs * im);
      pull2  = PetscMax(pull2, rp * im);
    }
  }
  *omega2_pull = pull2;
  return omega2;
}

/* ============ forces against an energy written here (linear laws, sharp kinks) ============ */

static int Ex(const Patch *p, int i, int j)
{
  return i >= 0 && i < NX && j >= 0 && j < NY && p->exists[j * NX + i];
}

/* traction energy per unit rest length: W(e) = integral of T(e) de (linear laws) */
static double W(const YarnLaw *y, double e)
{
  const double c = y->crimp, kEA = y->k_comp * y->EA, ec = y->e_contact;
  if (e <= ec) return 0.5 * kEA * ec * ec + kEA * ec * (e - ec) + 0.5 * y->EA * (e - ec) * (e - ec);
  if (e <= 0) return 0.5 * kEA * e * e;
  if (e <= c) return 0.5 * y->Ec * e * e;
  return 0.5 * y->Ec * c * c + y->Ec * c * (e - c) + y->EA * (e - c) * (e - c) / (2 * (1 + c));
}

static double Dist(const double *a, const double *b)
{
  return sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
}

#define X(i, j) (x + 3 * ((j) *NX + (i)))

/* bending energy of centre (i,j) along x (dir 0) or y (dir 1) */
static double BendEnergy(const Patch *p, const double *x, int i, int j, int dir)
{
  const int     di = dir == 0, dj = dir == 1;
  const double *a = X(i - di, j - dj), *b = X(i, j), *c = X(i + di, j + dj);
  double        e1[3], e2[3], s                         = 0;
  if (!Ex(p, i - di, j - dj) || !Ex(p, i + di, j + dj)) return 0;
  for (int d = 0; d < 3; d++) e1[d] = b[d] - a[d], e2[d] = c[d] - b[d];
  for (int d = 0; d < 3; d++) s += e1[d] * e2[d];
  s /= Dist(a, b) * Dist(b, c);
  return (dir == 0 ? p->kbx : p->kby) * (1 - s);
}

/* shear energy at crossing (i,j), one-sided tangents at edges */
static double ShearEnergy(const Patch *p, const double *x, int i, int j)
{
  int hl = Ex(p, i - 1, j), hr = Ex(p, i + 1, j), hd = Ex(p, i, j - 1), hu = Ex(p, i, j + 1);
  if (!(hl || hr) || !(hd || hu)) return 0;
  const double *xp = X(hr ? i + 1 : i, j), *xm = X(hl ? i - 1 : i, j), *yp = X(i, hu ? j + 1 : j);
  const double *ym = X(i, hd ? j - 1 : j);
  double        tw[3], tf[3], s = 0;
  for (int d = 0; d < 3; d++) tw[d] = xp[d] - xm[d], tf[d] = yp[d] - ym[d];
  for (int d = 0; d < 3; d++) s += tw[d] * tf[d];
  s /= Dist(xm, xp) * Dist(ym, yp);
  double jam = fabs(s) > p->s_lock ? fabs(s) - p->s_lock : 0;
  return 0.5 * p->Ks * s * s + 0.5 * p->Kj * jam * jam;
}

/* total energy of MODEL.md 5.1-5.3 */
static double Energy(const Patch *p, const double *x)
{
  double E = 0;
  for (int j = 0; j < NY; j++)
    for (int i = 0; i < NX; i++) {
      if (!Ex(p, i, j)) continue;
      if (Ex(p, i + 1, j)) E += p->ax * W(p->warp, Dist(X(i, j), X(i + 1, j)) / p->ax - 1);
      if (Ex(p, i, j + 1)) E += p->ay * W(p->weft, Dist(X(i, j), X(i, j + 1)) / p->ay - 1);
      E += BendEnergy(p, x, i, j, 0) + BendEnergy(p, x, i, j, 1) + ShearEnergy(p, x, i, j);
    }
  return E;
}

/* what a distorted state exercises: x-segments compressed, in contact, in yarn extension;
   interior crossings jammed with shear of the sign sign (s > s_lock, or s < -s_lock) */
static void CountRegimes(const Patch *p, const double *x, int sign, int *compressed, int *contact, int *extended,
                         int *jammed)
{
  *compressed = *contact = *extended = *jammed = 0;
  for (int j = 0; j < NY; j++)
    for (int i = 0; i + 1 < NX; i++)
      if (Ex(p, i, j) && Ex(p, i + 1, j)) {
        double                              e = Dist(X(i, j), X(i + 1, j)) / p->ax - 1;
        *compressed += e<0, *extended += e> p->warp->crimp, *contact += e < p->warp->e_contact;
      }
  for (int j = 1; j + 1 < NY; j++)
    for (int i = 1; i + 1 < NX; i++) {
      const double *a = X(i - 1, j), *b = X(i + 1, j), *c = X(i, j - 1), *d = X(i, j + 1);
      double        s = 0;
      if (!Ex(p, i, j) || !Ex(p, i - 1, j) || !Ex(p, i + 1, j) || !Ex(p, i, j - 1) || !Ex(p, i, j + 1)) continue;
      for (int q = 0; q < 3; q++) s += (b[q] - a[q]) * (d[q] - c[q]);
      *jammed += sign * s / (Dist(a, b) * Dist(c, d)) > p->s_lock;
    }
}
#undef X

/* randomly distorted grid (patch-local arrays, global indices): ~17 deg shear, strains of
   -0.2..0.3 along x */
static void DistortedState(const Patch *p, double *x, unsigned seed)
{
  srand(seed);
  for (int lj = 0; lj < p->gym; lj++)
    for (int li = 0; li < p->gxm; li++) {
      const int i = p->gxs + li, j = p->gys + lj;
      double   *q = x + 3 * (lj * p->gxm + li);
      q[0]        = i * p->ax * 1.04 + 0.3 * j * p->ay + 0.12 * p->ax * (2.0 * rand() / RAND_MAX - 1);
      q[1]        = j * p->ay + 0.12 * p->ay * (2.0 * rand() / RAND_MAX - 1);
      q[2]        = 0.2 * p->ax * (2.0 * rand() / RAND_MAX - 1);
    }
}

/* the grid at rest (strains of about 0, some exactly 0) but for one owned crossing moved onto its
   neighbour on the right: a zero-length chord (the bound's yarn stiffness in every direction) */
static void RestState(const Patch *p, double *x)
{
  for (int lj = 0; lj < p->gym; lj++)
    for (int li = 0; li < p->gxm; li++) {
      double *q = x + 3 * (lj * p->gxm + li);
      q[0] = (p->gxs + li) * p->ax, q[1] = (p->gys + lj) * p->ay, q[2] = 0.0;
    }
  {
    const int li = p->xs - p->gxs + 1, lj = p->ys - p->gys + 1;
    for (int d = 0; d < 3; d++) x[3 * (lj * p->gxm + li) + d] = x[3 * (lj * p->gxm + li + 1) + d];
  }
}

static PetscErrorCode PatchFree(Patch *p)
{
  PetscFunctionBeginUser;
  PetscCall(PatchDestroy(p));
  PetscCall(PetscFree(p->exists));
  PetscCall(PetscFree(p->broken_x));
  PetscCall(PetscFree(p->broken_y));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestForces(int mirror)
{
  YarnLaw warp = {0}, weft = {0};
  Patch   p = {0};
  double  x[3 * NP], f[3 * NP], tmax, fbig = 0, errmax = 0;
  int     jammed, compressed, extended, contact;
  char    what[256];

  PetscFunctionBeginUser;
  warp.name = "warp", warp.EA = 52, warp.crimp = 0.08, warp.Ec = 2.6, warp.k_comp = 1e-3, warp.e_contact = -0.08;
  weft.name = "weft", weft.EA = 40, weft.crimp = 0.05, weft.Ec = 3.0, weft.k_comp = 1e-3, weft.e_contact = -0.2;
  warp.break_e = weft.break_e = INFINITY;
  p.nx = NX, p.ny = NY, p.xm = p.gxm = NX, p.ym = p.gym = NY;
  p.ax = 4.2e-4, p.ay = 3.9e-4, p.warp = &warp, p.weft = &weft;
  p.traction = p.bending = p.shear = PETSC_TRUE;
  p.kbx = 1e-6 / p.ax, p.kby = 2e-6 / p.ay;
  p.Ks = 5000 * p.ax * p.ay, p.Kj = 30 * p.Ks, p.s_lock = sin(10 * M_PI / 180);
  PetscCall(PetscCalloc1(NP, &p.exists));
  PetscCall(PetscCalloc1(NP, &p.broken_x));
  PetscCall(PetscCalloc1(NP, &p.broken_y));
  for (int k = 0; k < NP; k++) p.exists[k] = 1;
  p.exists[3 * NX + 4] = 0; /* a hole */
  p.exists[0]          = 0; /* a cut corner */
  p.exists[NX - 1]     = 0;
  PetscCall(PatchSetUp(&p));
  DistortedState(&p, x, 12345);
  if (mirror) /* sheared the other way (x by -0.3 j ay, not +0.3): jamming at s < -s_lock */
    for (int k = 0; k < NP; k++) x[3 * k] -= 0.6 * (k / NX) * p.ay;
  {
    const PetscInt box[4] = {0, NX, 0, NY};
    ComputeInternalForces(&p, x, box, f, &tmax);
    Check("kernel energy (InternalEnergy) vs the energy written here, relative",
          fabs(InternalEnergy(&p, x, box) - Energy(&p, x)) / Energy(&p, x), 1e-13);
  }
  for (int k = 0; k < 3 * NP; k++) {
    const double h = 1e-6 * p.ax, keep = x[k];
    double       Ep, Em, fd;
    if (!p.exists[k / 3]) continue;
    x[k]   = keep + h;
    Ep     = Energy(&p, x);
    x[k]   = keep - h;
    Em     = Energy(&p, x);
    x[k]   = keep;
    fd     = -(Ep - Em) / (2 * h);
    fbig   = fbig > fabs(fd) ? fbig : fabs(fd);
    errmax = errmax > fabs(fd - f[k]) ? errmax : fabs(fd - f[k]);
  }
  CountRegimes(&p, x, mirror ? -1 : 1, &compressed, &contact, &extended, &jammed);
  /* a sub-box computes exactly the forces the full sweep computes on its points */
  {
    const PetscInt boxes[4][4] = {{3, NX, 0, NY}, {0, 4, 2, 6}, {2, 7, 1, 5}, {5, 6, 6, 7}};
    double         g[3 * NP], tm, worst = 0;
    for (int b = 0; b < 4; b++) {
      for (int k = 0; k < 3 * NP; k++) g[k] = -12345.0;
      ComputeInternalForces(&p, x, boxes[b], g, &tm);
      for (int j = boxes[b][2]; j < boxes[b][3]; j++)
        for (int i = boxes[b][0]; i < boxes[b][1]; i++)
          for (int d = 0; d < 3; d++) worst = fmax(worst, fabs(g[3 * (j * NX + i) + d] - f[3 * (j * NX + i) + d]));
    }
    Check("forces on sub-boxes equal the full sweep's (bit-identical: max difference)", worst, 0.0);
  }
  printf("segments along x: %d compressed (%d in contact), %d in yarn extension; %d jammed crossings; "
         "largest force %.3e N%s\n",
         compressed, contact, extended, jammed, fbig, mirror ? " (sheared the other way: s < 0)" : "");
  snprintf(what, sizeof what, "kernel force vs -grad(energy) by central differences%s, max error / max force",
           mirror ? " (negative shear)" : "");
  Check(what, errmax / fbig, 1e-6);
  snprintf(what, sizeof what,
           "distorted state%s has compressed, in-contact, extended segments and jammed crossings (0 = yes)",
           mirror ? " (negative shear)" : "");
  Check(what, (compressed > 0 && contact > 0 && extended > 0 && jammed > 0) ? 0 : 1, 0);
  PetscCall(PatchFree(&p));
  PetscFunctionReturn(0);
}

/* ============================ the law's slope and integral ============================ */

/* the test's two laws: warp tabulated (csv, or linear if none), weft linear; both with crimp
   and smoothing blends at their kinks */
static PetscErrorCode LawsSetUp(YarnLaw *warp, YarnLaw *weft, const char *csv)
{
  PetscFunctionBeginUser;
  warp->name = "warp", warp->tex = 20, warp->EA = 52, warp->crimp = 0.08, warp->Ec = 2.6, warp->k_comp = 1e-3;
  warp->e_contact = -0.08, warp->smoothing = 0.004;
  weft->name = "weft", weft->tex = 20, weft->EA = 40, weft->crimp = 0.05, weft->Ec = 3.0, weft->k_comp = 1e-3;
  weft->e_contact = -0.2, weft->smoothing = 0.003;
  PetscCall(PetscStrncpy(warp->csv, csv, sizeof warp->csv));
  PetscCall(YarnLawSetUp(warp, PETSC_COMM_SELF));
  PetscCall(YarnLawSetUp(weft, PETSC_COMM_SELF));
  PetscFunctionReturn(0);
}

/* the law's kinks and blend ends (where dT/de jumps) and the end of its table; returns how many */
static int LawBreaks(const YarnLaw *y, double ends[10])
{
  int n     = 0;
  ends[n++] = y->e_contact, ends[n++] = 0.0, ends[n++] = y->crimp;
  for (PetscInt k = 0; k < y->nblend; k++) ends[n++] = y->blend[k].lo, ends[n++] = y->blend[k].hi;
  if (y->ntab) ends[n++] = y->crimp + y->tab_end * (1 + y->crimp);
  return n;
}

/* a strain at least 2h away from every kink and blend end of the law */
static int AwayFromKinks(const YarnLaw *y, double e, double h)
{
  double ends[10];
  int    n = LawBreaks(y, ends);
  for (int k = 0; k < n; k++)
    if (fabs(e - ends[k]) < 2 * h) return 0;
  return 1;
}

/* integral of ChordTension over [a, b]: 5-point Gauss-Legendre on each piece between the law's breaks */
static double GaussIntegral(const YarnLaw *y, double a, double b)
{
  const double xg[5] = {0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640, 0.9061798459386640};
  const double wg[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665, 0.2369268850561891,
                        0.2369268850561891};
  double       ends[10], cuts[12], sum = 0;
  int          n = LawBreaks(y, ends), m = 0;
  cuts[m++] = a;
  for (int k = 0; k < n; k++)
    if (ends[k] > a && ends[k] < b) cuts[m++] = ends[k];
  cuts[m++] = b;
  for (int k = 1; k < m; k++) /* sort */
    for (int q = k; q > 0 && cuts[q] < cuts[q - 1]; q--) {
      double t = cuts[q];
      cuts[q] = cuts[q - 1], cuts[q - 1] = t;
    }
  for (int k = 0; k + 1 < m; k++) {
    const double mid = 0.5 * (cuts[k] + cuts[k + 1]), half = 0.5 * (cuts[k + 1] - cuts[k]);
    for (int g = 0; g < 5; g++) sum += half * wg[g] * ChordTension(y, mid + half * xg[g]);
  }
  return sum;
}

/* over e in [-0.3, 0.3]: d/de ChordEnergy = ChordTension and ChordTensionSlope = dT/de by central
   differences (h 1e-7, away from the kinks), ChordEnergy(0) = 0 and its increments = Gauss
   integrals of T (a jump of the energy anywhere would show), and the energy with the table of
   cell integrals = the energy summing the cells */
static PetscErrorCode CheckLaw(const char *name, const YarnLaw *y, const PetscReal *integral)
{
  const double h = 1e-7, de = 0.6 / 4000;
  double       tbig = 0, kbig = 0, eW = 0, eK = 0, eI = 0, eG = 0, prev = -0.3;
  char         what[256];

  PetscFunctionBeginUser;
  for (int q = 0; q <= 4000; q++) {
    const double e = -0.3 + de * q + 1.234567e-5; /* contact, compression, blends, crimp, table, beyond */
    const double T = ChordTension(y, e), dT = ChordTensionSlope(y, e);
    tbig = fmax(tbig, fabs(T)), kbig = fmax(kbig, fabs(dT));
    eG   = fmax(eG, fabs(ChordEnergy(y, integral, e) - ChordEnergy(y, integral, prev) - GaussIntegral(y, prev, e)));
    eI   = fmax(eI, fabs(ChordEnergy(y, integral, e) - ChordEnergy(y, NULL, e)));
    prev = e;
    if (!AwayFromKinks(y, e, h)) continue;
    const double dW = (ChordEnergy(y, integral, e + h) - ChordEnergy(y, integral, e - h)) / (2 * h);
    const double fd = (ChordTension(y, e + h) - ChordTension(y, e - h)) / (2 * h);
    eW = fmax(eW, fabs(dW - T)), eK = fmax(eK, fabs(fd - dT));
  }
  snprintf(what, sizeof what, "%s: d/de ChordEnergy vs ChordTension (h 1e-7), max error / max |T|", name);
  Check(what, eW / tbig, 1e-7);
  snprintf(what, sizeof what, "%s: ChordEnergy increments vs Gauss integrals of T, max error / (max |T| de)", name);
  Check(what, eG / (tbig * de), 1e-8);
  snprintf(what, sizeof what, "%s: ChordEnergy(0)", name);
  Check(what, fabs(ChordEnergy(y, integral, 0.0)), 0.0);
  snprintf(what, sizeof what, "%s: ChordTensionSlope vs dT/de (h 1e-7), max error / max slope", name);
  Check(what, eK / kbig, 1e-6);
  snprintf(what, sizeof what, "%s: ChordEnergy with the cell table vs summing the cells (bits)", name);
  Check(what, eI, 0.0);
  { /* the force rows' vectorised law: the same bits as ChordTension, on the grid above and at each
       break of the law and one ulp either side of it */
    double ends[10], *e, *Trow;
    int    n = 0, nb = LawBreaks(y, ends), differ = 0;
    PetscCall(PetscMalloc2(4002 + 30 + 3 * y->ntab, &e, 4002 + 30 + 3 * y->ntab, &Trow));
    for (int q = 0; q <= 4000; q++) e[n++] = -0.3 + de * q + 1.234567e-5;
    e[n++] = NAN; /* NaN in both, whatever its bits */
    for (int k = 0; k < nb; k++) e[n++] = ends[k], e[n++] = nextafter(ends[k], -1.0), e[n++] = nextafter(ends[k], 1.0);
    for (PetscInt k = 0; k < y->ntab; k++) { /* a table's nodes (the cells' ends, the table's end) */
      const double at = y->crimp + (double) k * y->tab_h * (1.0 + y->crimp);
      e[n++] = at, e[n++] = nextafter(at, -1.0), e[n++] = nextafter(at, 1.0);
    }
    ChordTensionLive(y, n, e, Trow);
    for (int q = 0; q < n; q++) {
      const double T = ChordTension(y, e[q]);
      differ += isnan(e[q]) ? !(isnan(T) && isnan(Trow[q])) : memcmp(&T, &Trow[q], sizeof T) != 0;
    }
    snprintf(what, sizeof what, "%s: the force rows' law vs ChordTension at %d strains (values that differ)", name, n);
    Check(what, differ, 0.0);
    PetscCall(PetscFree2(e, Trow));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode TestLaw(const char *csv)
{
  YarnLaw       warp = {0}, weft = {0}, sharp = {0};
  unsigned char one = 1;
  Patch         p   = {0};

  PetscFunctionBeginUser;
  PetscCall(LawsSetUp(&warp, &weft, csv));
  p.warp = &warp, p.weft = &weft, p.exists = &one, p.gxm = p.gym = 1;
  PetscCall(PatchSetUp(&p)); /* the warp law's integral table */
  printf("laws: warp %s, %" PetscInt_FMT " blends, EA %.4g N; weft linear, %" PetscInt_FMT " blends\n",
         warp.ntab ? "tabulated" : "linear", warp.nblend, (double) warp.EA, weft.nblend);
  PetscCall(CheckLaw("warp law", &warp, p.yarn_integral[0]));
  PetscCall(CheckLaw("weft law", &weft, NULL));
  sharp = weft, sharp.nblend = 0; /* sharp kinks */
  PetscCall(CheckLaw("linear law with sharp kinks", &sharp, NULL));
  p.exists = NULL;
  PetscCall(PatchDestroy(&p));
  PetscCall(YarnLawDestroy(&warp));
  PetscFunctionReturn(0);
}

/* ================== the terms on a distorted patch: energy, forces, tangent ================== */

/* The test's patch: with offset 0 the whole NX x NY grid on one rank; else a rank's patch inside
   a 20 x 15 grid, ghosted NX x NY: offset 1 from (5,4), owned [7,12) x [6,9) (ghosts on every
   side); offset 2 from (0,0), owned [0,7) x [0,5) (the grid's left and bottom edges); offset 3
   from (11,8), owned [13,20) x [10,15) (its right and top edges). Crimp, a tabulated warp law,
   smoothing blends, a hole, cut corners and two broken segments. */
static PetscErrorCode RichPatch(Patch *p, const YarnLaw *warp, const YarnLaw *weft, int offset)
{
  static const PetscInt gxs[4] = {0, 5, 0, 11}, gys[4] = {0, 4, 0, 8}, xs[4] = {0, 7, 0, 13}, ys[4] = {0, 6, 0, 10};
  static const PetscInt xm[4] = {NX, 5, 7, 7}, ym[4] = {NY, 3, 5, 5};

  PetscFunctionBeginUser;
  memset(p, 0, sizeof *p);
  p->nx = offset ? 20 : NX, p->ny = offset ? 15 : NY, p->gxm = NX, p->gym = NY;
  p->gxs = gxs[offset], p->gys = gys[offset], p->xs = xs[offset], p->ys = ys[offset];
  p->xm = xm[offset], p->ym = ym[offset];
  p->ax = 4.2e-4, p->ay = 3.9e-4, p->warp = warp, p->weft = weft;
  p->traction = p->bending = p->shear = PETSC_TRUE;
  p->kbx = 1e-6 / p->ax, p->kby = 2e-6 / p->ay;
  p->Ks = 5000 * p->ax * p->ay, p->Kj = 30 * p->Ks, p->s_lock = sin(17 * M_PI / 180); /* about half jam */
  PetscCall(PetscCalloc1(NP, &p->exists));
  PetscCall(PetscCalloc1(NP, &p->broken_x));
  PetscCall(PetscCalloc1(NP, &p->broken_y));
  for (int k = 0; k < NP; k++) p->exists[k] = 1;
  p->exists[3 * NX + 4] = 0;                                /* a hole */
  p->exists[0] = p->exists[NX - 1] = p->exists[NP - 1] = 0; /* cut corners */
  p->broken_x[4 * NX + 2]                              = 1; /* segment (2,4)-(3,4) */
  p->broken_y[2 * NX + 6]                              = 1; /* segment (6,2)-(6,3) */
  PetscCall(PatchSetUp(p));
  PetscFunctionReturn(0);
}

static void OwnedBox(const Patch *p, PetscInt box[4])
{
  box[0] = p->xs, box[1] = p->xs + p->xm, box[2] = p->ys, box[3] = p->ys + p->ym;
}

/* forces of term t alone (NULL: all terms, the fused pipeline) on the owned points */
static void Forces(Patch *p, const ForceTerm *t, const double *x, double *f)
{
  PetscInt  box[4];
  PetscReal tm;
  OwnedBox(p, box);
  if (t)
    t->forces(p, x, box, f);
  else
    ComputeInternalForces(p, x, box, f, &tm);
}

static double EnergyOf(const Patch *p, const ForceTerm *t, const double *x, const PetscInt box[4])
{
  return t ? TermEnergy(t, p, x, box) : InternalEnergy(p, x, box);
}

static const char *NameOf(const ForceTerm *t)
{
  return t ? t->name : "all terms";
}

/* (a) forces = -grad(energy), central differences with step 1e-6 of the chord */
static void CheckGradient(Patch *p, const ForceTerm *t, double *x)
{
  double   f[3 * NP], fbig = 0, err = 0;
  PetscInt box[4];
  char     what[256];
  OwnedBox(p, box);
  Forces(p, t, x, f);
  for (int k = 0; k < 3 * NP; k++) {
    const double keep = x[k], h = 1e-6 * p->ax;
    if (!p->exists[k / 3]) continue;
    x[k]            = keep + h;
    const double Ep = EnergyOf(p, t, x, box);
    x[k]            = keep - h;
    const double Em = EnergyOf(p, t, x, box);
    x[k]            = keep;
    const double fd = -(Ep - Em) / ((keep + h) - (keep - h));
    fbig = fmax(fbig, fabs(f[k])), err = fmax(err, fabs(fd - f[k]));
  }
  snprintf(what, sizeof what, "(a) %s: force vs -grad(energy) (h 1e-6 chord), max error / max force", NameOf(t));
  Check(what, err / fbig, 1e-6);
}

/* (a) the instances' gradients, scattered, equal the pipeline's forces (to round-off) */
static void CheckInstanceGradients(Patch *p, const ForceTerm *t, const double *x)
{
  double       f[3 * NP], g[3 * NP] = {0}, fbig = 0, err = 0;
  TermInstance inst;
  char         what[256];
  Forces(p, t, x, f);
  for (int q = 0; q < INTERNAL_TERMS; q++) {
    const ForceTerm *term = InternalTerms[q];
    if ((t && term != t) || !term->enabled(p)) continue;
    for (int j = 0; j < NY; j++)
      for (int i = 0; i < NX; i++)
        for (int k = 0; k < term->per_point; k++)
          if (term->instance(p, x, i, j, k, TERM_GRADIENT, &inst))
            for (int a = 0; a < inst.n; a++)
              for (int d = 0; d < 3; d++) g[3 * (inst.j[a] * NX + inst.i[a]) + d] -= inst.g[3 * a + d];
  }
  for (int k = 0; k < 3 * NP; k++) /* absent points: the shear gather adds neighbouring crossings there (unused) */
    if (p->exists[k / 3]) fbig = fmax(fbig, fabs(f[k])), err = fmax(err, fabs(g[k] - f[k]));
  snprintf(what, sizeof what, "(a) %s: -(instance gradients) vs the pipeline's forces, max error / max force",
           NameOf(t));
  Check(what, err / fbig, 1e-12);
}

typedef struct {
  const Patch *p;
  double      *K; /* dense 3NP x 3NP, patch-local points */
} Dense;

static PetscErrorCode AddDense(void *ctx, PetscInt n, const PetscInt i[], const PetscInt j[], const PetscReal K[])
{
  Dense *d = (Dense *) ctx;
  PetscFunctionBeginUser;
  for (PetscInt a = 0; a < n; a++)
    for (PetscInt b = 0; b < n; b++) {
      const PetscInt ka = (j[a] - d->p->gys) * NX + i[a] - d->p->gxs, kb = (j[b] - d->p->gys) * NX + i[b] - d->p->gxs;
      for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) d->K[(3 * ka + r) * 3 * NP + 3 * kb + c] += K[(3 * a + r) * 3 * n + 3 * b + c];
    }
  PetscFunctionReturn(0);
}

static PetscErrorCode DenseTangent(const Patch *p, const ForceTerm *t, const double *x, const PetscInt box[4],
                                   double *K)
{
  Dense d = {p, K};
  PetscFunctionBeginUser;
  if (t)
    PetscCall(TermTangent(t, p, x, box, PETSC_FALSE, AddDense, &d));
  else
    PetscCall(InternalTangent(p, x, box, PETSC_FALSE, AddDense, &d));
  PetscFunctionReturn(0);
}

static double MaxAbs(const double *a, int n)
{
  double m = 0;
  for (int k = 0; k < n; k++) m = fmax(m, fabs(a[k]));
  return m;
}

/* (b) tangent = -d(forces)/dx by central differences, step 1e-7 of the chord */
static void CheckTangent(Patch *p, const ForceTerm *t, double *x, const double *K)
{
  const int N = 3 * NP;
  double    fp[3 * NP], fm[3 * NP], err = 0, asym = 0, big = MaxAbs(K, N * N);
  char      what[256];
  for (int k = 0; k < N; k++) {
    const double keep = x[k], h = 1e-7 * p->ax, dx = (keep + h) - (keep - h);
    if (!p->exists[k / 3]) continue;
    x[k] = keep + h;
    Forces(p, t, x, fp);
    x[k] = keep - h;
    Forces(p, t, x, fm);
    x[k] = keep;
    for (int m = 0; m < N; m++)
      if (p->exists[m / 3]) err = fmax(err, fabs(-(fp[m] - fm[m]) / dx - K[m * N + k]));
  }
  for (int m = 0; m < N; m++)
    for (int k = 0; k < N; k++) asym = fmax(asym, fabs(K[m * N + k] - K[k * N + m]));
  snprintf(what, sizeof what, "(b) %s: tangent vs -d(force)/dx (h 1e-7 chord), max error / max entry (%.2e N/m)",
           NameOf(t), big);
  Check(what, err / big, 1e-6);
  snprintf(what, sizeof what, "(b) %s: tangent symmetry, max |K - K^T| / max entry", NameOf(t));
  Check(what, asym / big, 1e-14);
}

/* the tangent assembled in a DMDA matrix (dof 3, box stencil width 2) equals the dense one */
static PetscErrorCode CheckMat(const Patch *p, const double *x, const double *K)
{
  const int N = 3 * NP;
  DM        da;
  Mat       A;
  PetscInt  box[4], cols[3 * NP];
  double    row[3 * NP], err = 0;

  PetscFunctionBeginUser;
  OwnedBox(p, box);
  PetscCall(DMDACreate2d(PETSC_COMM_SELF, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DMDA_STENCIL_BOX, NX, NY, 1, 1, 3, 2,
                         NULL, NULL, &da));
  PetscCall(DMSetUp(da));
  PetscCall(DMCreateMatrix(da, &A));
  PetscCall(MatSetOption(A, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE)); /* the stencil holds every block */
  PetscCall(InternalTangent(p, x, box, PETSC_FALSE, TermBlocksAddToMat, A));
  PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  for (PetscInt k = 0; k < N; k++) cols[k] = k;
  for (PetscInt m = 0; m < N; m++) {
    PetscCall(MatGetValues(A, 1, &m, N, cols, row));
    for (int k = 0; k < N; k++) err = fmax(err, fabs(row[k] - K[m * N + k]));
  }
  Check("(b) DMDA matrix (TermBlocksAddToMat) vs the dense tangent, max difference / max entry", err / MaxAbs(K, N * N),
        1e-14);
  PetscCall(MatDestroy(&A));
  PetscCall(DMDestroy(&da));
  PetscFunctionReturn(0);
}

/* energy and tangent over sub-boxes (a split over ranks) add up to the whole patch's */
static PetscErrorCode CheckPartition(const Patch *p, const double *x, const double *K)
{
  const PetscInt full[4] = {0, NX, 0, NY}, parts[3][4] = {{0, 4, 0, 3}, {4, NX, 0, 3}, {0, NX, 3, NY}};
  const int      N = 3 * NP;
  double        *Ks, E = 0, err = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(N * N, &Ks));
  for (int b = 0; b < 3; b++) {
    E += InternalEnergy(p, x, parts[b]);
    PetscCall(DenseTangent(p, NULL, x, parts[b], Ks));
  }
  for (int m = 0; m < N * N; m++) err = fmax(err, fabs(Ks[m] - K[m]));
  Check("energy over three sub-boxes vs the whole patch's, relative",
        fabs(E - InternalEnergy(p, x, full)) / InternalEnergy(p, x, full), 1e-14);
  Check("tangent over three sub-boxes vs the whole patch's, max difference / max entry", err / MaxAbs(K, N * N), 1e-14);
  PetscCall(PetscFree(Ks));
  PetscFunctionReturn(0);
}

/* what the distorted rich patch exercises; 0 if it has every regime the tests need */
static int RichRegimes(const Patch *p, const double *x)
{
  int n[9] = {0}; /* contact, compressed, de-crimping, table, beyond the table, blends, jammed, free, broken */
  for (int j = 0; j < NY; j++)
    for (int i = 0; i + 1 < NX; i++) {
      const double *a = x + 3 * (j * NX + i), *b = a + 3;
      const double  e = Dist(a, b) / p->ax - 1, ey = (1 + e) / (1 + p->warp->crimp) - 1;
      if (!p->exists[j * NX + i] || !p->exists[j * NX + i + 1]) continue;
      if (p->broken_x[j * NX + i])
        n[8]++;
      else if (e < p->warp->e_contact)
        n[0]++;
      else if (e < 0)
        n[1]++;
      else if (e < p->warp->crimp)
        n[2]++;
      else if (ey < p->warp->tab_end)
        n[3]++;
      else
        n[4]++;
      for (PetscInt k = 0; k < p->warp->nblend; k++) n[5] += e >= p->warp->blend[k].lo && e <= p->warp->blend[k].hi;
    }
  for (int j = 0; j < NY; j++)
    for (int i = 0; i < NX; i++) {
      PetscReal s, tmin;
      if (CrossingShear(p, x, i, j, &s, &tmin)) n[PetscAbsReal(s) > p->s_lock ? 6 : 7]++;
    }
  printf("rich patch, segments along x: %d in contact, %d compressed, %d de-crimping, %d on the yarn table, "
         "%d beyond it, %d in blends, %d broken; crossings: %d jammed, %d below the lock\n",
         n[0], n[1], n[2], n[3], n[4], n[5], n[8], n[6], n[7]);
  for (int k = 0; k < 9; k++) /* blends: not required; the table: if the warp law has one */
    if (k != 5 && (k != 3 || p->warp->ntab) && n[k] == 0) return 1;
  return 0;
}

static PetscErrorCode CountBlocks(void *ctx, PetscInt n, const PetscInt i[], const PetscInt j[], const PetscReal K[])
{
  (*(int *) ctx)++;
  return 0;
}


/* ======== (b') positive parts: SymPositivePart and the convex tangent (TERM_CONVEX) ======== */

/* how far the symmetric n x n matrix M is from positive semi-definite: the smallest shift s >= 0
   (relative to big, the scale of the matrices it comes from, to 1e-14) with which M + s I has a
   Cholesky factor, found by bisection: an answer by elimination, independent of the rotations of
   SymPositivePart */
static double NonPsd(int n, const double *M, double big)
{
  double lo = 0, hi = 2.0 * n;
  if (big == 0) return 0;
  for (int it = 0; it < 60 && hi - lo > 1e-14; it++) {
    const double s = it == 0 ? 1e-14 : 0.5 * (lo + hi);
    double       L[15 * 15];
    int          ok = 1;
    for (int r = 0; r < n && ok; r++)
      for (int c = 0; c <= r && ok; c++) {
        double v = M[n * r + c] / big + (r == c ? s : 0.0);
        for (int k = 0; k < c; k++) v -= L[n * r + k] * L[n * c + k];
        if (r == c) ok = v > 0, L[n * r + r] = ok ? sqrt(v) : 0;
        else L[n * r + c] = v / L[n * c + c];
      }
    if (it == 0 && ok) return 0;
    if (ok) hi = s;
    else lo = s;
  }
  return hi;
}

static void TestPositivePart(void)
{
  double worst[3] = {0, 0, 0}, same = 0, zero = 0;
  srand(77);
  for (int trial = 0; trial < 200; trial++) {
    const int n = trial % 2 ? 6 : 3;
    double    A[36], P[36], N[36], PN = 0, big;
    for (int r = 0; r < n; r++)
      for (int c = 0; c <= r; c++) A[n * r + c] = A[n * c + r] = 2.0 * rand() / RAND_MAX - 1.0;
    memcpy(P, A, sizeof P);
    SymPositivePart(n, P);
    big = MaxAbs(A, n * n);
    for (int e = 0; e < n * n; e++) N[e] = P[e] - A[e];
    for (int r = 0; r < n; r++) /* P (P - A) = 0: the parts are orthogonal */
      for (int c = 0; c < n; c++) {
        double v = 0;
        for (int k = 0; k < n; k++) v += P[n * r + k] * N[n * k + c];
        PN = fmax(PN, fabs(v) / (big * big));
      }
    worst[0] = fmax(worst[0], NonPsd(n, P, big)), worst[1] = fmax(worst[1], NonPsd(n, N, big)), worst[2] = fmax(worst[2], PN);
    { /* a positive semi-definite matrix stays (A^T A); a negative one vanishes */
      double S[36], Z[36];
      for (int r = 0; r < n; r++)
        for (int c = 0; c < n; c++) {
          double v = 0;
          for (int k = 0; k < n; k++) v += A[n * k + r] * A[n * k + c];
          S[n * r + c] = v, Z[n * r + c] = -v;
        }
      memcpy(P, S, sizeof P);
      SymPositivePart(n, P);
      SymPositivePart(n, Z);
      big = MaxAbs(S, n * n);
      for (int e = 0; e < n * n; e++) same = fmax(same, fabs(P[e] - S[e]) / big), zero = fmax(zero, fabs(Z[e]) / big);
    }
  }
  Check("positive part of 200 random symmetric 3x3 and 6x6 matrices: positive semi-definite (Cholesky shift)",
        worst[0], 1e-13);
  Check("positive part minus the matrix: positive semi-definite (Cholesky shift)", worst[1], 1e-13);
  Check("positive part times (positive part minus the matrix) / max|A|^2: zero", worst[2], 1e-13);
  Check("positive part of a positive semi-definite A^T A: itself, relative", same, 1e-13);
  Check("positive part of a negative semi-definite -A^T A: zero, relative", zero, 1e-13);
}

/* every instance of the rich patch (its terms with exact tangents: compressed segments keep their
   negative geometric part): the convex tangent is positive semi-definite and exceeds the exact
   one by a positive semi-definite matrix; a segment whose own tangent is so keeps it */
static void CheckConvexInstances(const Patch *p, const double *x)
{
  double worst[3] = {0, 0, 0};
  int    count[3] = {0, 0, 0}, indefinite = 0;
  for (int t = 0; t < INTERNAL_TERMS; t++)
    for (int j = 0; j < NY; j++)
      for (int i = 0; i < NX; i++)
        for (int k = 0; k < InternalTerms[t]->per_point; k++) {
          TermInstance ex, cv;
          double       D[225];
          if (!InternalTerms[t]->instance(p, x, i, j, k, TERM_HESSIAN, &ex)) continue;
          InternalTerms[t]->instance(p, x, i, j, k, TERM_HESSIAN | TERM_CONVEX, &cv);
          const int    m   = 3 * (int) ex.n;
          const double big = MaxAbs(ex.K, m * m);
          if (!(big > 0)) continue;
          for (int e = 0; e < m * m; e++) D[e] = cv.K[e] - ex.K[e];
          count[t]++;
          indefinite += NonPsd(m, ex.K, big) > 1e-10;
          worst[0] = fmax(worst[0], NonPsd(m, cv.K, big)), worst[1] = fmax(worst[1], NonPsd(m, D, big));
          if (ex.n == 2 && NonPsd(m, ex.K, big) == 0) /* a segment in tension: its own tangent */
            worst[2] = fmax(worst[2], MaxAbs(D, m * m) / big);
        }
  printf("convex tangent: %d segments, %d bending centres, %d crossings; %d exact instances indefinite\n", count[0],
         count[1], count[2], indefinite);
  Check("convex tangent of the rich patch: some exact instance is indefinite (0 = yes)", indefinite > 0 ? 0 : 1, 0);
  Check("convex tangent of every instance: positive semi-definite (Cholesky shift)", worst[0], 1e-12);
  Check("convex minus exact tangent of every instance: positive semi-definite (Cholesky shift)", worst[1], 1e-12);
  Check("convex tangent of a segment whose own is positive semi-definite: the same, relative", worst[2], 1e-15);
}

static PetscErrorCode TestTerms(const char *csv)
{
  YarnLaw  warp = {0}, weft = {0};
  Patch    p;
  double   x[3 * NP], *K;
  PetscInt full[4] = {0, NX, 0, NY};

  PetscFunctionBeginUser;
  PetscCall(LawsSetUp(&warp, &weft, csv));
  PetscCall(RichPatch(&p, &warp, &weft, 0));
  PetscCall(PetscMalloc1(9 * NP * NP, &K));
  /* the shear terms at crossings jammed the other way (s < -s_lock): the state sheared by -0.3 j ay */
  DistortedState(&p, x, 2024);
  for (int k = 0; k < NP; k++) x[3 * k] -= 0.6 * (k / NX) * p.ay;
  {
    int negative = 0;
    for (int j = 0; j < NY; j++)
      for (int i = 0; i < NX; i++) {
        PetscReal sc, tmin;
        negative += CrossingShear(&p, x, i, j, &sc, &tmin) && sc < -p.s_lock;
      }
    printf("sheared the other way: %d crossings jammed at s < -s_lock\n", negative);
    Check("sheared the other way: crossings jammed at negative shear (0 = yes)", negative > 0 ? 0 : 1, 0);
    PetscCall(PetscArrayzero(K, 9 * NP * NP));
    PetscCall(DenseTangent(&p, &ShearTerm, x, full, K));
    CheckGradient(&p, &ShearTerm, x);
    CheckInstanceGradients(&p, &ShearTerm, x);
    CheckTangent(&p, &ShearTerm, x, K);
  }
  DistortedState(&p, x, 2024);
  Check("rich patch has contact, compression, de-crimping, table, beyond-table, broken segments, jammed and "
        "free crossings (0 = yes)",
        RichRegimes(&p, x), 0);
  for (int t = 0; t < INTERNAL_TERMS; t++) {
    PetscCall(PetscArrayzero(K, 9 * NP * NP));
    PetscCall(DenseTangent(&p, InternalTerms[t], x, full, K));
    CheckGradient(&p, InternalTerms[t], x);
    CheckInstanceGradients(&p, InternalTerms[t], x);
    CheckTangent(&p, InternalTerms[t], x, K);
  }
  PetscCall(PetscArrayzero(K, 9 * NP * NP));
  PetscCall(DenseTangent(&p, NULL, x, full, K));
  CheckGradient(&p, NULL, x);
  CheckInstanceGradients(&p, NULL, x);
  CheckTangent(&p, NULL, x, K);
  CheckConvexInstances(&p, x);
  PetscCall(CheckMat(&p, x, K));
  PetscCall(CheckPartition(&p, x, K));
  { /* a term switched off costs nothing: no energy, no blocks */
    int calls = 0;
    p.bending = PETSC_FALSE;
    PetscCall(TermTangent(&BendingTerm, &p, x, full, PETSC_FALSE, CountBlocks, &calls));
    Check("bending off: its energy and number of tangent blocks", TermEnergy(&BendingTerm, &p, x, full) + calls, 0);
  }
  PetscCall(PetscFree(K));
  PetscCall(PatchFree(&p));
  PetscCall(YarnLawDestroy(&warp));
  PetscFunctionReturn(0);
}

/* ======== (c), (d): the stable-step bound and the forces, bit for bit against the reference ======== */

static void RandomMasses(const Patch *p, double *inv_m)
{
  for (int lj = 0; lj < p->ym; lj++)
    for (int li = 0; li < p->xm; li++) {
      const int k = (p->ys - p->gys + lj) * p->gxm + p->xs - p->gxs + li, r = rand();
      inv_m[lj * p->xm + li] = !p->exists[k] || r % 7 == 0 ? 0.0 : 1.0 / (1e-6 * (1.0 + (double) r / RAND_MAX));
    }
}

/* the balance test's scale from the terms' instances: at each owned point the sum of |dE/dx| over
   the instances that contain it (the instances owned by the owned points and by their ghosts
   within 1 reach every owned point) */
static void RefMagnitudes(const Patch *p, const PetscReal *x, PetscReal *scale)
{
  TermInstance inst;

  for (int k = 0; k < p->xm * p->ym; k++) scale[k] = 0.0;
  for (int t = 0; t < INTERNAL_TERMS; t++) {
    if (!InternalTerms[t]->enabled(p)) continue;
    for (PetscInt j = PetscMax(p->ys - 1, 0); j < PetscMin(p->ys + p->ym + 1, p->ny); j++)
      for (PetscInt i = PetscMax(p->xs - 1, 0); i < PetscMin(p->xs + p->xm + 1, p->nx); i++)
        for (int k = 0; k < InternalTerms[t]->per_point; k++) {
          if (!InternalTerms[t]->instance(p, x, i, j, k, TERM_GRADIENT, &inst)) continue;
          for (PetscInt q = 0; q < inst.n; q++) {
            const PetscInt   iq = inst.i[q], jq = inst.j[q];
            const PetscReal *g  = inst.g + 3 * q;
            if (iq < p->xs || iq >= p->xs + p->xm || jq < p->ys || jq >= p->ys + p->ym) continue;
            scale[(jq - p->ys) * p->xm + (iq - p->xs)] += PetscSqrtReal(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
          }
        }
  }
}

/* BreakSegments as it was, segment by segment (the reference of BreakRatioRow's pass) */
static PetscInt RefBreakSegments(Patch *p, const PetscReal *x, BreakSite *site, PetscReal *load)
{
  PetscInt n = 0;

  site->ratio = *load = 0;
  site->dir = site->i = site->j = 0;
  for (int dir = 0; dir < 2; dir++) {
    const YarnLaw   *law    = dir == 0 ? p->warp : p->weft;
    const PetscReal  L0     = dir == 0 ? p->ax : p->ay;
    unsigned char   *broken = dir == 0 ? p->broken_x : p->broken_y;
    const PetscReal *eb     = dir == 0 ? p->break_x : p->break_y;
    if (!isfinite(law->break_e)) continue;
    for (PetscInt lj = 0; lj + (dir == 1) < p->gym; lj++)
      for (PetscInt li = 0; li + (dir == 0) < p->gxm; li++) {
        const PetscInt k = lj * p->gxm + li, k2 = k + (dir == 0 ? 1 : p->gxm);
        if (broken[k] || !p->exists[k] || !p->exists[k2]) continue;
        const PetscReal *a = x + 3 * k, *b = x + 3 * k2;
        const PetscReal  e_break = eb ? eb[k] : law->break_e;
        const PetscReal  e = PetscSqrtReal(PetscSqr(b[0] - a[0]) + PetscSqr(b[1] - a[1]) + PetscSqr(b[2] - a[2])) / L0 - 1.0;
        *load = PetscMax(*load, e / e_break);
        if (e <= e_break) continue;
        broken[k] = 1;
        {
          const PetscInt i = p->gxs + li, j = p->gys + lj;
          if (i < p->xs || i >= p->xs + p->xm || j < p->ys || j >= p->ys + p->ym) continue; /* not owned */
          n++;
          if (e / e_break > site->ratio) site->ratio = e / e_break, site->dir = dir, site->i = i, site->j = j;
        }
      }
  }
  return n;
}

/* BreakSegments against the reference on the patch's state x: breaking strains of the laws
   (ebw, ebf) or per segment (drawn around them); mode 1: one position NaN (its segments break,
   NaN past any breaking strain), mode 2: the hole's point far away (its segments, absent, must
   not count in the load); returns 1 if the broken segments, the count or the site differ in a
   bit, or nothing broke */
static int CompareBreaks(Patch *p, YarnLaw *warp, YarnLaw *weft, const double *x0, PetscReal ebw, PetscReal ebf,
                         int per_segment, int mode)
{
  double        x[3 * NP], bx[NP], by[NP];
  unsigned char keep_x[NP], keep_y[NP], ref_x[NP], ref_y[NP];
  BreakSite     s1, s2;
  PetscReal     load1, load2;
  PetscInt      n1, n2;
  int           bad;

  memcpy(x, x0, sizeof x);
  if (mode == 1) x[3 * (2 * NX + 5) + 1] = NAN;
  if (mode == 2) x[3 * (3 * NX + 4)] += 100.0 * p->ax;
  warp->break_e = ebw, weft->break_e = ebf;
  for (int k = 0; k < NP; k++) bx[k] = ebw * (0.8 + 0.4 * rand() / RAND_MAX), by[k] = ebf * (0.8 + 0.4 * rand() / RAND_MAX);
  p->break_x = per_segment ? bx : NULL, p->break_y = per_segment ? by : NULL;
  memcpy(keep_x, p->broken_x, NP), memcpy(keep_y, p->broken_y, NP);
  n2 = RefBreakSegments(p, x, &s2, &load2);
  memcpy(ref_x, p->broken_x, NP), memcpy(ref_y, p->broken_y, NP);
  memcpy(p->broken_x, keep_x, NP), memcpy(p->broken_y, keep_y, NP);
  { /* apply 0: the same largest ratio, nothing broken */
    BreakSite  s0;
    PetscReal  load0;
    const PetscInt n0 = BreakSegments(p, x, 0, &s0, &load0);
    bad               = n0 != 0 || memcmp(keep_x, p->broken_x, NP) != 0 || memcmp(keep_y, p->broken_y, NP) != 0 ||
          memcmp(&load0, &load2, sizeof load0) != 0;
  }
  n1  = BreakSegments(p, x, 1, &s1, &load1);
  bad |= n1 != n2 || memcmp(ref_x, p->broken_x, NP) != 0 || memcmp(ref_y, p->broken_y, NP) != 0 ||
        memcmp(&s1.ratio, &s2.ratio, sizeof s1.ratio) != 0 || memcmp(&load1, &load2, sizeof load1) != 0 ||
        s1.dir != s2.dir || s1.i != s2.i || s1.j != s2.j;
  bad |= n1 == 0; /* the case breaks some */
  memcpy(p->broken_x, keep_x, NP), memcpy(p->broken_y, keep_y, NP);
  p->break_x = p->break_y = NULL;
  warp->break_e = weft->break_e = INFINITY;
  return bad;
}

/* the bound and the reference agree to rounding: they find lambda_max of the 3x3 blocks by
   different methods (closed form, Jacobi rotations) */
static int Close(PetscReal a, PetscReal b)
{
  return PetscAbsReal(a - b) <= 1e-12 * PetscMax(PetscAbsReal(a), PetscAbsReal(b));
}

/* differences between the kernels and the reference at one state and switch setting: bad[0]
   bit differences in the forces (d), bad[1] in the window (bits) and the bound and its rows (to
   1e-12 relative) (c), bad[2] bit differences between StableOmega2 (and PullOmega2) and the
   terms' bound_row summed point by point (c), bad[3] differences between InternalForceMagnitudes
   and the instances' magnitudes (1e-12 of the point's, its forces to the bit) (d) */
/* refs: also against the reference pipeline and the reference bound (Jacobi's eigenvalues); 0: the
   window's range and the bound against the terms' own rows alone (a zero-length chord, which the
   references do not take as the kernels do) */
static void CompareWithReference(Patch *p, const double *x, const double *inv_m, int refs, int bad[4])
{
  const PetscReal windows[3] = {0.0, 0.02, 1.0}, contact[2] = {0.0, 2e3};
  double          f[3 * NP], g[3 * NP], inv1[NP];
  PetscInt        own[4], boxes[3][4];
  PetscReal       t1g;

  OwnedBox(p, own);
  for (int k = 0; k < 4; k++) boxes[0][k] = own[k];
  boxes[1][0] = own[0] + 1, boxes[1][1] = own[1] - 1, boxes[1][2] = own[2], boxes[1][3] = own[2] + 2;
  boxes[2][0] = own[0] + 2, boxes[2][1] = own[0] + 3, boxes[2][2] = own[3] - 1, boxes[2][3] = own[3];
  for (int b = 0; b < 3 * refs; b++) { /* (d) forces and the tension scale */
    PetscReal t1, t2;
    for (int k = 0; k < 3 * NP; k++) f[k] = g[k] = -12345.0;
    ComputeInternalForces(p, x, boxes[b], f, &t1);
    RefComputeInternalForces(p, x, boxes[b], g, &t2);
    bad[0] += memcmp(f, g, sizeof f) != 0 || memcmp(&t1, &t2, sizeof t1) != 0;
  }
  if (refs) { /* (d) the balance test's scale: the magnitudes of each point's force terms */
    double m1[NP], m2[NP];
    for (int k = 0; k < 3 * NP; k++) g[k] = -12345.0;
    ComputeInternalForces(p, x, own, f, &t1g);
    InternalForceMagnitudes(p, x, own, g, m1);
    RefMagnitudes(p, x, m2);
    bad[3] += memcmp(f, g, sizeof(double) * 3 * p->xm * p->ym) != 0;
    for (int k = 0; k < p->xm * p->ym; k++) bad[3] += !(PetscAbsReal(m1[k] - m2[k]) <= 1e-12 * m2[k]);
  }
  for (int w = 0; w < 6; w++) { /* (c) the window, the bound, and each row as the sum of the terms' rows */
    const PetscReal margin = windows[w % 3];
    const int       pull   = w / 3;
    PetscReal       o1, o2, p1, p2, r[5], lo[2], hi[2], s_hi;
    BoundRow        at;
    p->k_contact = contact[w % 2];
    p->ncb       = w % 2; /* with a sphere and a plane along their normals (ContactBoundRow) */
    if (p->ncb) {
      const PetscReal *x0 = RefPos(p, x, p->xs + 1, p->ys + 1);
      p->ncb              = 2;
      p->cb[0] = (ContactBound){0, PETSC_TRUE, 3e3, {x0[0], x0[1], x0[2] - 0.5 * p->ax}, {0, 0, 1}, w == 5 ? 0.3 * p->ax : 0};
      if (w == 3) /* the sphere's centre on a point: any direction there */
        for (int d = 0; d < 3; d++) p->cb[0].c[d] = x0[d];
      p->cb[1] = (ContactBound){1, PETSC_FALSE, 5e2, {0, 0, 0}, {0.6, 0, 0.8}, 0};
    }
    WindowRange(p, x, r);
    bad[1] += RefWindowRangeDiffers(p, x, r);
    WindowSet(p, r, margin);
    RefWindow(p, x, margin, lo, hi, &s_hi);
    bad[1] += memcmp(lo, p->win_lo, sizeof lo) != 0 || memcmp(hi, p->win_hi, sizeof hi) != 0 || s_hi != p->win_s;
    o1 = StableOmega2(p, x, inv_m, pull, &p1, &at);
    if (refs) {
      o2 = RefStableOmega2(p, x, inv_m, lo, hi, s_hi, pull, &p2);
      bad[1] += !Close(o1, o2) || !Close(p1, p2);
    }
    /* where it is set: that row, and each term's part of it */
    bad[1] += (at.i < 0) != (o1 == 0) || at.omega2 != o1 || !Close(at.part[0] + at.part[1] + at.part[2] + at.part[3], o1); /* none: no stiffness */
    if (at.i >= 0) {
      const PetscReal im = inv_m[(at.j - p->ys) * p->xm + (at.i - p->xs)];
      for (int t = 0; t < INTERNAL_TERMS; t++) {
        PetscReal rs = 0.0, rp = 0.0;
        if (InternalTerms[t]->enabled(p)) InternalTerms[t]->bound_row(p, x, at.i, at.j, pull, &rs, &rp);
        bad[1] += PetscAbsReal(rs * im - at.part[t]) > 1e-12 * o1; /* a difference of partial sums: to the row's */
      }
      bad[1] += PetscAbsReal(ContactBoundRow(p, x, at.i, at.j) * im - at.part[3]) > 1e-12 * o1;
    }
    { /* StableOmega2 evaluates each segment and crossing once: the same bits as the largest of the
         rows summed term by term (bound_row), the bound, the pull row and the row that sets it */
      PetscReal om = 0.0, pm = 0.0;
      PetscInt  ki = -1;
      for (int k = 0; k < p->xm * p->ym; k++) {
        const PetscInt i = p->xs + k % p->xm, j = p->ys + k / p->xm;
        PetscReal      rs = 0.0, rp = 0.0;
        if (inv_m[k] <= 0) continue;
        for (int t = 0; t < INTERNAL_TERMS; t++)
          if (InternalTerms[t]->enabled(p)) InternalTerms[t]->bound_row(p, x, i, j, pull, &rs, &rp);
        rs += ContactBoundRow(p, x, i, j);
        if (rs * inv_m[k] > om) ki = k;
        om = PetscMax(om, rs * inv_m[k]);
        pm = PetscMax(pm, rp * inv_m[k]);
      }
      bad[2] += memcmp(&om, &o1, sizeof om) != 0 || memcmp(&pm, &p1, sizeof pm) != 0 ||
                (ki < 0 ? at.i >= 0 : (at.i != p->xs + ki % p->xm || at.j != p->ys + ki / p->xm));
      pm = PullOmega2(p, x, inv_m, pull);
      bad[2] += memcmp(&pm, &p1, sizeof pm) != 0;
    }
    for (int k = 0; k < p->xm * p->ym * refs; k++) {
      const PetscInt i = p->xs + k % p->xm, j = p->ys + k / p->xm;
      PetscReal      rs = 0.0, rp = 0.0;
      if (inv_m[k] <= 0) continue;
      for (int q = 0; q < p->xm * p->ym; q++) inv1[q] = q == k;
      o2 = RefStableOmega2(p, x, inv1, lo, hi, s_hi, pull, &p2); /* row k of the reference */
      for (int t = 0; t < INTERNAL_TERMS; t++)
        if (InternalTerms[t]->enabled(p)) InternalTerms[t]->bound_row(p, x, i, j, pull, &rs, &rp);
      rs += ContactBoundRow(p, x, i, j);
      bad[1] += !Close(rs, o2) || !Close(rp, p2);
    }
  }
  p->ncb = 0, p->k_contact = 0.0;
}

static PetscErrorCode TestIdentity(const char *csv)
{
  YarnLaw warp = {0}, weft = {0};
  Patch   p;
  double  x[3 * NP], inv_m[NP];
  int     bad[4] = {0, 0, 0, 0}, cases = 0, bad_break = 0, breaks = 0;

  PetscFunctionBeginUser;
  PetscCall(LawsSetUp(&warp, &weft, csv));
  for (int offset = 0; offset < 4; offset++) {
    PetscCall(RichPatch(&p, &warp, &weft, offset));
    for (unsigned seed = 1; seed <= 4; seed++) {
      if (seed <= 3) {
        DistortedState(&p, x, seed);
        RandomMasses(&p, inv_m);
        for (int c = 0; c < 6; c++, breaks++) /* strains of the state: about -0.1 to 0.2 */
          bad_break += CompareBreaks(&p, &warp, &weft, x, c % 3 == 2 ? INFINITY : 0.06, c % 3 == 1 ? INFINITY : 0.02,
                                     c / 3 == 1, c == 0 ? 2 : 0);
        bad_break += CompareBreaks(&p, &warp, &weft, x, 10.0, 10.0, 0, 1), breaks++; /* only the NaN's segments break */
      } else RestState(&p, x); /* the bound and the window only */
      for (int mask = 0; mask < 8; mask++, cases++) { /* every combination of the switches */
        p.traction = mask & 1 ? PETSC_TRUE : PETSC_FALSE;
        p.bending  = mask & 2 ? PETSC_TRUE : PETSC_FALSE;
        p.shear    = mask & 4 ? PETSC_TRUE : PETSC_FALSE;
        CompareWithReference(&p, x, inv_m, seed <= 3, bad);
      }
    }
    PetscCall(PatchFree(&p));
  }
  printf("identity: %d cases (4 patches x 4 states, one at rest with a zero-length chord, x 8 switch settings; 3 "
         "boxes, 6 bound settings, every row)\n",
         cases);
  Check("(c) the window (bits), StableOmega2, the row that sets it and its terms' parts, and each row as the sum "
        "of the terms' bound_row (1e-12) vs the reference: differences",
        bad[1],
        0);
  printf("breaks: %d cases (4 patches x 3 states; both families, warp or weft alone; the laws' or each "
         "segment's breaking strain; a NaN position; an absent point far away)\n",
         breaks);
  Check("BreakSegments vs the reference, segment by segment: the broken segments, the count and the site (bits): "
        "cases that differ or break nothing",
        bad_break, 0);
  Check("(c) StableOmega2's bound, pull row and the row that sets it, and PullOmega2, vs the terms' bound_row summed "
        "at each point: bit differences",
        bad[2], 0);
  Check("(d) ComputeInternalForces (forces, tension_max) vs the reference pipeline: bit differences", bad[0], 0);
  Check("(d) InternalForceMagnitudes: the forces (bits) and each point's sum of its terms' force magnitudes vs the "
        "instances' (1e-12): differences",
        bad[3], 0);
  PetscCall(YarnLawDestroy(&warp));
  PetscFunctionReturn(0);
}

/* ===================================== the yarn table ===================================== */

static PetscErrorCode TestTable(const char *csv)
{
  YarnLaw           y = {0};
  double            es[64], fs[64], errmax = 0, tmax;
  size_t            n = 0;
  char              line[256];
  FILE             *fp;
  gsl_interp       *sp;
  gsl_interp_accel *acc;

  PetscFunctionBeginUser;
  y.name = "warp", y.crimp = 0.0, y.k_comp = 1e-3, y.e_contact = -0.5, y.tex = 20;
  PetscCall(PetscStrncpy(y.csv, csv, sizeof y.csv));
  PetscCall(YarnLawSetUp(&y, PETSC_COMM_SELF));
  fp = fopen(csv, "r");
  PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot open %s", csv);
  while (fgets(line, sizeof line, fp))
    if (line[0] != '#' && sscanf(line, "%lf,%lf", &es[n], &fs[n]) == 2) {
      es[n] /= 100, fs[n] /= 100;
      n++;
    }
  fclose(fp);
  sp  = gsl_interp_alloc(gsl_interp_steffen, n);
  acc = gsl_interp_accel_alloc();
  gsl_interp_init(sp, es, fs, n);
  tmax = fs[n - 1];
  for (int k = 0; k <= 10000; k++) {
    double e = es[n - 1] * k / 10000.0, d = fabs(YarnTension(&y, e) - gsl_interp_eval(sp, es, fs, e, acc));
    errmax = errmax > d ? errmax : d;
  }
  Check("fast yarn table vs GSL Steffen spline, max error / max tension", errmax / tmax, 1e-6);
  {
    double slope = gsl_interp_eval_deriv(sp, es, fs, es[n - 1], acc), e = es[n - 1] + 0.01;
    Check("linear extension past the table, relative error", fabs(YarnTension(&y, e) - (tmax + slope * 0.01)) / tmax,
          1e-9);
  }
  gsl_interp_accel_free(acc);
  gsl_interp_free(sp);
  PetscCall(YarnLawDestroy(&y));
  PetscFunctionReturn(0);
}

static void TestTangent(void)
{
  YarnLaw y = {0};
  y.EA = 52, y.crimp = 0.08, y.Ec = 2.6, y.k_comp = 1e-3, y.e_contact = -0.5, y.break_e = INFINITY;
  Check("tangent in compression window", fabs(ChordTangentMax(&y, -0.2, -0.1) - 52e-3), 1e-12);
  Check("tangent reaching yarn contact", fabs(ChordTangentMax(&y, -0.6, -0.1) - 52), 1e-12);
  Check("chord tension in contact", fabs(ChordTension(&y, -0.6) - (52e-3 * -0.5 + 52 * -0.1)), 1e-12);
  Check("tangent across the crimp start", fabs(ChordTangentMax(&y, -0.01, 0.01) - 2.6), 1e-12);
  Check("tangent across the knee", fabs(ChordTangentMax(&y, 0.07, 0.09) - 52 / 1.08), 1e-12);
  Check("chord tension in extension", fabs(ChordTension(&y, 0.1) - (2.6 * 0.08 + 52 * 0.02 / 1.08)), 1e-12);
}

/* Degenerate geometry (kernels.c): a crossing moved onto its neighbour (a zero-length chord) and a
   yarn folded back on itself (the warp tangent x(i+1) - x(i-1) of zero length) give finite forces
   and a finite stable-step bound: the degenerate chord and crossing carry no force. */
/* (e) the window check of the force pipeline: ComputeInternalForces flags a state outside the
   window the bound covers exactly when a segment or crossing that acts on a point of its box has
   left it: nothing at the state the window was taken at, a flag when a box point's segment is
   stretched past the window, and none when a point 3 away from the box moves anywhere */
static PetscErrorCode TestWindowFlag(const char *csv)
{
  YarnLaw   warp = {0}, weft = {0};
  Patch     p;
  double    x[3 * NP], f[3 * NP], tmax, r[5];
  PetscInt  box[4] = {3, 6, 3, 6};
  const int edge = 4 * NX + 5, far = 5 * NX; /* point (5,4) in the box; point (0,5), 3 to its left */
  int       flags[4];

  PetscFunctionBeginUser;
  PetscCall(LawsSetUp(&warp, &weft, csv));
  PetscCall(RichPatch(&p, &warp, &weft, 0));
  DistortedState(&p, x, 11);
  WindowRange(&p, x, r);
  WindowSet(&p, r, 0.01);
  ComputeInternalForces(&p, x, box, f, &tmax);
  flags[0] = p.left_window;
  x[3 * far] += 5.0 * p.ax, x[3 * far + 2] += 3.0 * p.ax; /* far away: no force on the box changes */
  ComputeInternalForces(&p, x, box, f, &tmax);
  flags[1] = p.left_window;
  x[3 * edge] += (p.win_hi[0] - p.win_lo[0] + 0.02) * p.ax; /* its warp segments out of the window */
  ComputeInternalForces(&p, x, box, f, &tmax);
  flags[2] = p.left_window;
  for (int d = 0; d < 2; d++) p.win_lo[d] = -1e300, p.win_hi[d] = 1e300; /* every strain inside: the shear alone */
  p.win_s = 0.0;
  ComputeInternalForces(&p, x, box, f, &tmax);
  flags[3] = p.left_window;
  Check("window check: flags at the window's state, after a far move, after a box point's segment left it, with "
        "a shear window of 0 (0, 0, 1, 1: differences)",
        (double) (flags[0] != 0) + (flags[1] != 0) + (flags[2] != 1) + (flags[3] != 1), 0.0);
  PetscCall(PatchFree(&p));
  PetscCall(YarnLawDestroy(&warp));
  PetscCall(YarnLawDestroy(&weft));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestDegenerate(const char *csv)
{
  YarnLaw   warp = {0}, weft = {0};
  Patch     p;
  double    x[3 * NP], f[3 * NP], tmax, o2, o2p, inv_m[NP];
  PetscInt  full[4] = {0, NX, 0, NY};
  int       finite  = 1;
  const int a = 3 * NX + 2, b = a + 1, c = 5 * NX + 5; /* chord a-b; crossing c: its warp neighbours meet */

  PetscFunctionBeginUser;
  PetscCall(LawsSetUp(&warp, &weft, csv));
  PetscCall(RichPatch(&p, &warp, &weft, 0));
  DistortedState(&p, x, 7);
  for (int d = 0; d < 3; d++) x[3 * b + d] = x[3 * a + d], x[3 * (c + 1) + d] = x[3 * (c - 1) + d];
  for (int k = 0; k < NP; k++) inv_m[k] = 1.0;
  ComputeInternalForces(&p, x, full, f, &tmax);
  for (int k = 0; k < 3 * NP; k++) finite = finite && isfinite(f[k]);
  {
    PetscReal r[5];
    WindowRange(&p, x, r);
    WindowSet(&p, r, 1.0);
  }
  o2 = StableOmega2(&p, x, inv_m, 0, &o2p, NULL);
  Check("degenerate chord and folded yarn: every force finite (0 = yes)", finite ? 0.0 : 1.0, 0.0);
  Check("degenerate chord and folded yarn: stable-step bound finite and positive (0 = yes)",
        isfinite(o2) && o2 > 0 && isfinite(o2p) ? 0.0 : 1.0, 0.0);
  PetscCall(PatchFree(&p));
  PetscCall(YarnLawDestroy(&warp));
  PetscCall(YarnLawDestroy(&weft));
  PetscFunctionReturn(0);
}

static double Norm3(const PetscReal v[3])
{
  return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* the penalty push k (reach - dist) n a point x feels from pedestal point q of TestBodies (top, edge, rim inside, rim
   outside, bottom inside, below the bottom), worked out apart from DiscContact: outside the cylinder from the
   nearest point of its surface, inside from the face named */
static void PedestalPushByHand(const Body *b, int q, const PetscReal x[3], PetscReal f[3])
{
  const PetscReal rho = sqrt(x[0] * x[0] + x[1] * x[1]), ux = x[0] / rho, uy = x[1] / rho;
  PetscReal       near[3] = {x[0], x[1], x[2]}, n[3] = {0, 0, 0}, dist;
  if (q == 1 || q == 3) near[0] = b->radius * ux, near[1] = b->radius * uy; /* the rounded edge, the rim */
  if (q == 0 || q == 1) near[2] = 0;                                          /* the top face's plane */
  if (q == 5) near[2] = -b->height;                                           /* the bottom face's plane */
  if (q == 2) dist = rho - b->radius, n[0] = ux, n[1] = uy; /* inside, out through the rim */
  else if (q == 4) dist = -(x[2] + b->height), n[2] = -1;   /* inside, out through the bottom */
  else {
    dist = sqrt(PetscSqr(x[0] - near[0]) + PetscSqr(x[1] - near[1]) + PetscSqr(x[2] - near[2]));
    for (int d = 0; d < 3; d++) n[d] = (x[d] - near[d]) / dist;
  }
  for (int d = 0; d < 3; d++) f[d] = b->k * (b->reach - dist) * n[d];
}

/* Rigid bodies (bodies.c): for a sphere, a plane and a pedestal (top face, rim, rounded edge),
   at points in contact (the pedestal's bottom face too: a point pushed deep into it, and one just below it):
   BodyContact's force = the push k (reach - dist) n worked out by hand (the sphere's and the tilted plane's
   in closed form, the pedestal's from the nearest point of its surface; 1e-12 relative), BodyEnergy's gradient
   is minus BodyContact's force (to 1e-12 relative), the
   energy's central differences give the gradient (1e-6 relative) and the gradient's give the
   Hessian (1e-6 relative to its largest entry). Friction (mu 0.5, each body moved by (3, -2, 1) mm, the
   point with it): a point displaced from its anchor along a tangent t (with x, y and z parts) by s feels
   -k s t when k s < mu fn (sticks: its anchor stays) and -mu fn t when k s > mu fn (slips: the anchor is
   dragged to mu fn / k behind it), to 1e-12 relative. */
static void TestBodies(void)
{
  const Body bodies[3] = {
      {BODY_SPHERE, {0, 0, -0.01}, {0, 0, 1}, 0.01, 0, 0.0102, 500.0, 0.0},
      {BODY_PLANE, {0, 0, 0}, {0.6, 0, 0.8}, 0, 0, 2e-4, 500.0, 0.0},
      {BODY_PEDESTAL, {0, 0, 0}, {0, 0, 0}, 0.01, 0.005, 2e-4, 500.0, 0.0},
  };
  const PetscReal pts[3][6][3] = {
      {{0.001, 0.002, -0.0001}, {0.003, -0.001, -0.0005}, {0, 0, 0.0001}, {0.02, 0, 0}, {0.03, 0, 0}, {0, 0, 0.01}},
      /* sphere */
      {{0.0001, 0, 0.0001}, {0.001, 0.003, -0.001}, {0.0065, 0, -0.00995}, {0, 0, 0.001}, {0, 0, 0.002}, {0, 0, 0.01}},
      /* plane */
      {{0.001, 0.002, 0.0001},
       {0.0101, 0.0001, 0.0001},
       {0.0099, 0.0, -0.001},
       {0.01015, 0.0005, -0.002},
       {0.001, 0.002, -0.0049},
       {0.001, 0.002, -0.00505}}, /* pedestal: top, edge, rim inside, rim outside, bottom (0.1 mm above it), 0.05 mm
                                     below the bottom */
  };
  double eg = 0, eK = 0, ef = 0, eh = 0, es = 0;
  int    contacts = 0;

  for (int b = 0; b < 3; b++)
    for (int q = 0; q < 6; q++) {
      PetscReal       c[3], g[3], K[9], f[3] = {0, 0, 0}, one = 1.0, gp[3], gm[3], Kd[9], fh[3];
      const PetscReal h = 1e-8;
      BodyPosition(&bodies[b], 0.0, c);
      if (!(BodyEnergy(&bodies[b], c, pts[b][q], g, K) > 0)) continue;
      contacts++;
      BodyContact(&bodies[b], c, 1, pts[b][q], &one, NULL, f);
      if (b == 2) PedestalPushByHand(&bodies[b], q, pts[b][q], fh);
      else { /* the sphere: along the radius, reach - r deep; the plane: along its normal, reach - (x - p0).n deep */
        PetscReal r[3], dist = 0, n[3];
        for (int d = 0; d < 3; d++) r[d] = pts[b][q][d] - c[d];
        if (b == 0) {
          dist = Norm3(r);
          for (int d = 0; d < 3; d++) n[d] = r[d] / dist;
        } else {
          for (int d = 0; d < 3; d++) n[d] = bodies[b].dir[d], dist += r[d] * n[d];
        }
        for (int d = 0; d < 3; d++) fh[d] = bodies[b].k * (bodies[b].reach - dist) * n[d];
      }
      for (int d = 0; d < 3; d++) eh = PetscMax(eh, fabs(f[d] - fh[d]) / Norm3(fh));
      /* friction: the body and the point moved by o; the point's anchor s back along a tangent t */
      for (int slip = 0; slip < 2; slip++) {
        Body            fb = bodies[b];
        const PetscReal o[3] = {0.003, -0.002, 0.001}, w[3] = {1, 2, 3}, fn = Norm3(fh);
        PetscReal       x[3], cf[3], n[3], t[3], tn = 0, a[3], ff[3] = {0, 0, 0}, s, want[3], aw[3];
        fb.mu = 0.5;
        for (int d = 0; d < 3; d++) fb.ref[d] += o[d], x[d] = pts[b][q][d] + o[d], n[d] = fh[d] / fn;
        BodyPosition(&fb, 0.0, cf);
        t[0] = n[1] * w[2] - n[2] * w[1], t[1] = n[2] * w[0] - n[0] * w[2], t[2] = n[0] * w[1] - n[1] * w[0];
        tn = Norm3(t);
        s  = (slip ? 3.0 : 0.5) * fb.mu * fn / fb.k; /* the stick spring's stretch: below and above mu fn / k */
        for (int d = 0; d < 3; d++) t[d] /= tn, a[d] = x[d] - cf[d] - s * t[d];
        BodyContact(&fb, cf, 1, x, &one, a, ff);
        for (int d = 0; d < 3; d++) {
          want[d] = fh[d] - (slip ? fb.mu * fn : fb.k * s) * t[d];
          aw[d]   = x[d] - cf[d] - (slip ? fb.mu * fn / fb.k : s) * t[d];
          es      = PetscMax(es, fabs(ff[d] - want[d]) / fn);
          es      = PetscMax(es, fabs(a[d] - aw[d]) / s);
        }
      }
      for (int d = 0; d < 3; d++) ef = PetscMax(ef, fabs(g[d] + f[d]) / PetscMax(1e-30, fabs(f[d]) + 1e-3 * Norm3(f)));
      for (int d = 0; d < 3; d++) {
        PetscReal xp[3] = {pts[b][q][0], pts[b][q][1], pts[b][q][2]},
                  xm[3] = {pts[b][q][0], pts[b][q][1], pts[b][q][2]};
        xp[d] += h, xm[d] -= h;
        const double Ep = BodyEnergy(&bodies[b], c, xp, gp, Kd), Em = BodyEnergy(&bodies[b], c, xm, gm, Kd);
        eg = PetscMax(eg, fabs((Ep - Em) / (2 * h) - g[d]) / Norm3(g));
        for (int e = 0; e < 3; e++) eK = PetscMax(eK, fabs((gp[e] - gm[e]) / (2 * h) - K[3 * e + d]) / MaxAbs(K, 9));
      }
    }
  Check("bodies: points in contact (count - 12, 0 = as placed: 3 sphere, 3 plane, 6 pedestal faces)",
        fabs(contacts - 12.0), 0.0);
  Check("bodies: BodyContact force = k (reach - dist) n by hand, max relative", eh, 1e-12);
  Check("bodies: friction = -k s t sticking, -mu fn t slipping, anchor kept or dragged, max relative", es, 1e-12);
  Check("bodies: BodyEnergy gradient = -BodyContact force, max relative", ef, 1e-12);
  Check("bodies: BodyEnergy gradient vs central differences of the energy, max relative", eg, 1e-6);
  Check("bodies: BodyEnergy Hessian vs central differences of the gradient, max / max entry", eK, 1e-6);
}

/* ============== the stable step's tangent covers the law; the blends join the law C1 ============== */

/* The stable-step bound's tangent (ChordTangentMax over a window of chord strains) is at least the
   law's slope (ChordTensionSlope) anywhere in the window (MODEL.md 7.3: a smaller one gives a te above
   the stable limit): over windows of 4 widths across every regime, sampled at 257 strains each (to
   1e-6: the bound samples each table cell's slope 5 times, each blend's 65 times with a 5 % margin); and,
   to 1e-9, at both ends of each table cell, for the window of that one cell (the bound's samples include
   the cell's ends). The smoothing blends join the law C1: each blend's cubic equals the piecewise law at
   both of its ends (1e-12 of the law's largest tension) and its slope the piecewise law's one-sided slope
   there (1e-5: a tabulated piece's slope is a forward difference of 1e-7); the linear law's slope past the
   crimp is EA/(1+c) exactly. Each blend lies on [e0 - d, e0 + d] about its kink, [0, 2d] at rest, d the
   smoothing, to 1e-15. */
static PetscErrorCode CheckLawCovered(const char *name, const YarnLaw *y)
{
  const double widths[4] = {5e-4, 3e-3, 2e-2, 1.5e-1};
  double       over = 0, cell = 0, jumpT = 0, jumpK = 0, Tbig = fabs(ChordTension(y, 0.3));
  YarnLaw      sharp = *y;
  char         what[256];

  PetscFunctionBeginUser;
  sharp.nblend = 0; /* the piecewise law, kinks and all */
  for (int w = 0; w < 4; w++)
    for (double a = -0.3; a + widths[w] <= 0.3; a += 0.00137) {
      const double b = a + widths[w], bound = ChordTangentMax(y, a, b);
      double       slope = 0;
      for (int q = 0; q <= 256; q++) slope = fmax(slope, fabs(ChordTensionSlope(y, a + (b - a) * q / 256.0)));
      over = fmax(over, (slope - bound) / slope);
    }
  for (PetscInt k = 0; k + 1 < y->ntab; k++) { /* each cell alone, its ends a hundredth of a cell inside */
    const double lo = y->crimp + (k + 0.01) * y->tab_h * (1 + y->crimp);
    const double hi = y->crimp + (k + 0.99) * y->tab_h * (1 + y->crimp), bound = ChordTangentMax(y, lo, hi);
    const double slope = fmax(ChordTensionSlope(y, lo), ChordTensionSlope(y, hi));
    cell = fmax(cell, (slope - bound) / slope);
  }
  for (PetscInt k = 0; k < y->nblend; k++) {
    const double ends[2] = {y->blend[k].lo, y->blend[k].hi};
    for (int side = 0; side < 2; side++) {
      const double e = ends[side], out = nextafter(e, side ? 1.0 : -1.0); /* just outside the blend */
      const double ks = ChordTensionSlope(&sharp, out), kb = ChordTensionSlope(y, e);
      jumpT = fmax(jumpT, fabs(ChordTension(y, e) - ChordTensionPiecewise(y, e)) / Tbig);
      jumpK = fmax(jumpK, fabs(kb - ks) / fmax(fabs(ks), fabs(kb)));
    }
  }
  { /* where the blends lie, d the smoothing (this test's kinks are far apart: no blend is narrowed): about the
       contact kink, at rest on the tension side (a fabric at rest is stress-free), about the crimp */
    const double d = y->smoothing, lo[3] = {y->e_contact - d, 0.0, y->crimp - d}, hi[3] = {y->e_contact + d, 2.0 * d, y->crimp + d};
    double       place = y->nblend == 3 ? 0 : 1.0;
    for (PetscInt b = 0; b < y->nblend && b < 3; b++)
      place = fmax(place, fmax(fabs(y->blend[b].lo - lo[b]), fabs(y->blend[b].hi - hi[b])));
    snprintf(what, sizeof what, "%s: 3 blends (%d), on [e_contact - d, e_contact + d], [0, 2d], [crimp - d, crimp + d]: "
             "largest misplacement of an end", name, (int) y->nblend);
    Check(what, place, 1e-15);
  }
  snprintf(what, sizeof what, "%s: ChordTangentMax over windows vs the largest slope in them, max shortfall / slope",
           name);
  Check(what, over, 1e-6);
  snprintf(what, sizeof what, "%s: ChordTangentMax of one table cell vs the slope at its ends, max shortfall / slope",
           name);
  Check(what, cell, 1e-9);
  snprintf(what, sizeof what, "%s: blends vs the piecewise law at their ends: tension jump / max tension", name);
  Check(what, jumpT, 1e-12);
  snprintf(what, sizeof what, "%s: blends vs the piecewise law at their ends: slope jump, relative", name);
  Check(what, jumpK, 1e-5);
  if (!y->ntab) {
    snprintf(what, sizeof what, "%s: linear law's slope past the crimp vs EA / (1 + c), relative", name);
    Check(what, fabs(ChordTensionSlope(&sharp, y->crimp + 0.1) - y->EA / (1 + y->crimp)) / y->EA, 1e-15);
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode TestLawCovered(const char *csv)
{
  YarnLaw warp = {0}, weft = {0};

  PetscFunctionBeginUser;
  PetscCall(LawsSetUp(&warp, &weft, csv));
  PetscCall(CheckLawCovered("warp law", &warp));
  PetscCall(CheckLawCovered("weft law", &weft));
  PetscCall(YarnLawDestroy(&warp));
  PetscCall(YarnLawDestroy(&weft));
  PetscFunctionReturn(0);
}

/* PointFields (the frames' fields) on a uniformly stretched and sheared grid, whose every warp chord has
   strain ex, every weft chord ey and every crossing the shear angle gamma (one-sided tangents at the
   edges give the same): the warp tension T_warp(ex), the weft tension T_weft(ey) (the mean of one or two
   equal segments: 1e-12 relative) and gamma in degrees (1e-9 degrees), at every crossing, edges included */
static PetscErrorCode TestPointFields(const char *csv)
{
  YarnLaw      warp = {0}, weft = {0};
  Patch        p    = {0};
  const double ex = 0.1, ey = 0.02, gamma = 12.5 * M_PI / 180; /* past the warp's crimp; the weft de-crimping */
  double       x[3 * NP], tw[NP], tf[NP], sh[NP], Tw, Tf, ew = 0, ef = 0, es = 0;

  PetscFunctionBeginUser;
  PetscCall(LawsSetUp(&warp, &weft, csv));
  p.nx = NX, p.ny = NY, p.xm = p.gxm = NX, p.ym = p.gym = NY;
  p.ax = 4.2e-4, p.ay = 3.9e-4, p.warp = &warp, p.weft = &weft, p.traction = PETSC_TRUE;
  PetscCall(PetscCalloc1(NP, &p.exists));
  PetscCall(PetscCalloc1(NP, &p.broken_x));
  PetscCall(PetscCalloc1(NP, &p.broken_y));
  for (int k = 0; k < NP; k++) p.exists[k] = 1;
  PetscCall(PatchSetUp(&p));
  for (int j = 0; j < NY; j++)
    for (int i = 0; i < NX; i++) {
      double *q = x + 3 * (j * NX + i);
      q[0] = i * p.ax * (1 + ex) + j * p.ay * (1 + ey) * sin(gamma), q[1] = j * p.ay * (1 + ey) * cos(gamma), q[2] = 0;
    }
  PointFields(&p, x, tw, tf, sh);
  Tw = ChordTension(&warp, ex), Tf = ChordTension(&weft, ey);
  for (int k = 0; k < NP; k++) {
    ew = fmax(ew, fabs(tw[k] - Tw) / Tw), ef = fmax(ef, fabs(tf[k] - Tf) / Tf);
    es = fmax(es, fabs(sh[k] - gamma * 180 / M_PI));
  }
  printf("point fields: warp %.6g N, weft %.6g N, shear %.6g deg\n", Tw, Tf, gamma * 180 / M_PI);
  Check("PointFields on a uniform sheared grid: warp tension vs T_warp(ex) at every crossing, max relative", ew, 1e-12);
  Check("PointFields on a uniform sheared grid: weft tension vs T_weft(ey) at every crossing, max relative", ef, 1e-12);
  Check("PointFields on a uniform sheared grid: shear angle vs gamma at every crossing, max error (deg)", es, 1e-9);
  PetscCall(PatchFree(&p));
  PetscCall(YarnLawDestroy(&warp));
  PetscCall(YarnLawDestroy(&weft));
  PetscFunctionReturn(0);
}

/* The quasi-static path's traction tangent (tension_field): every segment's Hessian is the convex one,
   k n n^T + max(T,0)/L (I - n n^T), bit for bit, and differs from the exact one at some compressed segment */
static PetscErrorCode TestTensionField(const char *csv)
{
  YarnLaw      warp = {0}, weft = {0};
  Patch        p;
  double       x[3 * NP];
  TermInstance a, b, c;
  int          differ = 0, compressed = 0, segments = 0;

  PetscFunctionBeginUser;
  PetscCall(LawsSetUp(&warp, &weft, csv));
  PetscCall(RichPatch(&p, &warp, &weft, 0));
  DistortedState(&p, x, 2024);
  for (int j = 0; j < NY; j++)
    for (int i = 0; i < NX; i++)
      for (int dir = 0; dir < 2; dir++) {
        p.tension_field = PETSC_TRUE;
        if (!TractionTerm.instance(&p, x, i, j, dir, TERM_HESSIAN | TERM_GRADIENT, &a)) continue;
        p.tension_field = PETSC_FALSE;
        TractionTerm.instance(&p, x, i, j, dir, TERM_HESSIAN | TERM_CONVEX | TERM_GRADIENT, &b);
        TractionTerm.instance(&p, x, i, j, dir, TERM_HESSIAN | TERM_GRADIENT, &c);
        segments++;
        differ += memcmp(a.K, b.K, 36 * sizeof(PetscReal)) != 0;
        /* the gradient on the second point is T n: compressed when it points back along the chord */
        {
          const PetscReal *xa = x + 3 * (j * NX + i), *xb = x + 3 * ((j + dir) * NX + i + !dir);
          double           dot = 0;
          for (int d = 0; d < 3; d++) dot += a.g[3 + d] * (xb[d] - xa[d]);
          if (dot < 0 && memcmp(a.K, c.K, 36 * sizeof(PetscReal))) compressed++;
        }
      }
  printf("tension field: %d segments, %d compressed with a tangent other than the exact one\n", segments, compressed);
  Check("tension_field: traction Hessian vs the convex one, segments that differ (bits)", differ, 0);
  Check("tension_field: some compressed segment's Hessian drops its geometric part (0 = yes)",
        compressed > 0 ? 0 : 1, 0);
  PetscCall(PatchFree(&p));
  PetscCall(YarnLawDestroy(&warp));
  PetscFunctionReturn(0);
}

/* A yarn that breaks at yarn strain break_ey (no scatter) breaks at chord strain c + break_ey (1 + c): the
   crimp is pulled out first (MODEL.md 5.1), and every segment draws that strain */
static PetscErrorCode TestBreakChordStrain(void)
{
  YarnLaw y = {0};

  PetscFunctionBeginUser;
  y.name = "warp", y.tex = 20, y.EA = 52, y.crimp = 0.08, y.Ec = 2.6, y.k_comp = 1e-3, y.e_contact = -0.08;
  y.break_ey = 0.065;
  PetscCall(YarnLawSetUp(&y, PETSC_COMM_SELF));
  PetscCall(YarnBreakSetUp(&y, 4.2e-4, PETSC_COMM_SELF));
  Check("breaking chord strain vs c + break_ey (1 + c) = 0.1502, error", fabs(y.break_e - 0.1502), 1e-15);
  Check("a segment's breaking strain without scatter vs the law's, error",
        fabs(SegmentBreakStrain(&y, 7, 0, 3, 4) - 0.1502), 1e-15);
  PetscCall(YarnLawDestroy(&y));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  char csv[PETSC_MAX_PATH_LEN] = "";

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-csv", csv, sizeof csv, NULL));
  PetscCall(TestForces(0));
  PetscCall(TestForces(1)); /* sheared the other way */
  PetscCall(TestLaw(csv));
  PetscCall(TestTerms(csv));
  TestPositivePart();
  PetscCall(TestIdentity(csv));
  if (csv[0]) PetscCall(TestTable(csv));
  TestTangent();
  TestBodies();
  PetscCall(TestWindowFlag(csv));
  PetscCall(TestDegenerate(csv));
  PetscCall(TestLawCovered(csv));
  PetscCall(TestPointFields(csv));
  PetscCall(TestTensionField(csv));
  PetscCall(TestBreakChordStrain());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
