/* kernels.c - internal forces of the crossing-point model and the stable-step bound.
 *
 * Forces are minus the gradient of the energies of MODEL.md 5.1-5.3:
 *  - traction, per yarn segment: force T d/L on its first point, -T d/L on its second
 *    (a broken segment carries nothing; BreakSegments breaks them between te sweeps);
 *  - bending, per yarn centre c with chords e1 (into c) and e2 (out of c):
 *      E = kb (1 - s), s = u1.u2, kb = B/L0; with g1 = (u2 - s u1)/|e1|, g2 = (u1 - s u2)/|e2|
 *      (evaluated as cross products, see ComputeBendRow)
 *      the force is -kb g1 on c-1, kb (g1 - g2) on c, kb g2 on c+1;
 *  - shear, per crossing c with warp tangent tw = x(c+ex) - x(c-ex) and weft tangent
 *    tf = x(c+ey) - x(c-ey) (one-sided at an edge): s = cos(tw,tf),
 *      E = Ks s^2/2 + Kj max(0,|s|-s_lock)^2/2; with Hw = E'(s) (uf - s uw)/|tw| the force
 *      is -Hw on the plus end of tw and +Hw on its minus end (likewise Hf for tf).
 *
 * The patch is swept row by row (a pipeline that keeps the y-segment, y-bending and shear
 * rows j-2..j+1 in a ring), so every term is evaluated once per step and the rows stay in
 * cache. Each owned point then sums its contributions in a fixed order: results do not
 * depend on the decomposition. A term that is switched off is neither computed nor summed.
 */
#include "kernels.h"

#include <math.h>
#include <string.h>

/* Rest chords computed from rest positions, (i+1) ax - i ax, differ from ax in the last
   bits: such strains are round-off, not load, and carry no tension, so that a fabric at rest
   is exactly force-free (rank propagation from rest is then exact). 1e-16 per segment over
   10^4 segments stays below this. */
#define STRAIN_ROUNDOFF 1e-12

#define SLOT(r) ((((r) % KERNEL_RING) + KERNEL_RING) % KERNEL_RING)

static PetscErrorCode YarnIntegralSetUp(const YarnLaw *y, PetscReal **integral);

static PetscErrorCode AllocRow(PetscInt n, PetscInt count, PetscReal *work, PetscReal **ptrs[])
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < count; k++) *ptrs[k] = work + k * (n + 2) + 1; /* index -1 and n are zero padding */
  PetscFunctionReturn(0);
}

PetscErrorCode PatchSetUp(Patch *p)
{
  PetscInt n = p->gxm, per_row = n + 2, rows = 0, k = 0;

  PetscFunctionBeginUser;
  rows = 8 + 8 * KERNEL_RING + 6 + 6 * KERNEL_RING + 9 * KERNEL_RING;
  PetscCall(PetscCalloc1((size_t)rows * per_row, &p->work));
  {
    SegmentRow *s = &p->xs_row;
    PetscReal **ptrs[] = {&s->ux, &s->uy, &s->uz, &s->inv_len, &s->fx, &s->fy, &s->fz, &s->T};
    PetscCall(AllocRow(n, 8, p->work + (k++) * 8 * per_row, ptrs));
  }
  for (PetscInt r = 0; r < KERNEL_RING; r++) {
    SegmentRow *s = &p->ys_ring[r];
    PetscReal **ptrs[] = {&s->ux, &s->uy, &s->uz, &s->inv_len, &s->fx, &s->fy, &s->fz, &s->T};
    PetscCall(AllocRow(n, 8, p->work + (k++) * 8 * per_row, ptrs));
  }
  {
    BendRow    *b = &p->bx_row;
    PetscReal **ptrs[] = {&b->g1x, &b->g1y, &b->g1z, &b->g2x, &b->g2y, &b->g2z};
    PetscCall(AllocRow(n, 6, p->work + k * 8 * per_row, ptrs));
  }
  {
    PetscReal *base = p->work + (k * 8 + 6) * per_row;
    for (PetscInt r = 0; r < KERNEL_RING; r++) {
      BendRow    *b = &p->by_ring[r];
      PetscReal **ptrs[] = {&b->g1x, &b->g1y, &b->g1z, &b->g2x, &b->g2y, &b->g2z};
      PetscCall(AllocRow(n, 6, base + r * 6 * per_row, ptrs));
    }
    base += 6 * KERNEL_RING * per_row;
    for (PetscInt r = 0; r < KERNEL_RING; r++) {
      ShearRow   *s = &p->sh_ring[r];
      PetscReal **ptrs[] = {&s->hwx, &s->hwy, &s->hwz, &s->hfx, &s->hfy, &s->hfz, &s->sx, &s->sy, &s->sz};
      PetscCall(AllocRow(n, 9, base + r * 9 * per_row, ptrs));
    }
  }
  PetscCall(PetscCalloc1(3 * (size_t)n, &p->zero_row));
  PetscCall(PetscCalloc1((size_t)(p->gym + 2) * per_row, &p->epad));
  for (PetscInt j = 0; j < p->gym; j++)
    for (PetscInt i = 0; i < p->gxm; i++) p->epad[(j + 1) * per_row + i + 1] = p->exists[j * p->gxm + i];
  PetscCall(YarnIntegralSetUp(p->warp, &p->yarn_integral[0]));
  PetscCall(YarnIntegralSetUp(p->weft, &p->yarn_integral[1]));
  PetscFunctionReturn(0);
}

PetscErrorCode PatchDestroy(Patch *p)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(p->work));
  PetscCall(PetscFree(p->zero_row));
  PetscCall(PetscFree(p->epad));
  PetscCall(PetscFree(p->yarn_integral[0]));
  PetscCall(PetscFree(p->yarn_integral[1]));
  PetscFunctionReturn(0);
}

/* ---------------- the yarn law's slope and integral (MODEL.md 5.1, 14) ---------------- */

/* dTyarn/dey at yarn strain ey >= 0: EA, or the derivative of the Hermite cell (material.h) */
static PetscReal YarnSlope(const YarnLaw *y, PetscReal ey)
{
  if (!y->ntab) return y->EA;
  const PetscReal s = ey * y->tab_inv_h;
  if (s >= (PetscReal)(y->ntab - 1)) return y->tab_dT[y->ntab - 1];
  const PetscInt  k = (PetscInt)s;
  const PetscReal t = s - (PetscReal)k;
  return 6.0 * t * (1.0 - t) * (y->tab_T[k + 1] - y->tab_T[k]) * y->tab_inv_h +
         (1.0 - 4.0 * t + 3.0 * t * t) * y->tab_dT[k] + (3.0 * t * t - 2.0 * t) * y->tab_dT[k + 1];
}

PetscReal ChordTensionSlope(const YarnLaw *y, PetscReal e)
{
  for (PetscInt k = 0; k < y->nblend; k++) /* the blends first, as ChordTension */
    if (e >= y->blend[k].lo && e <= y->blend[k].hi) {
      const PetscReal s = e - y->blend[k].lo;
      return y->blend[k].c1 + s * (2.0 * y->blend[k].c2 + 3.0 * s * y->blend[k].c3);
    }
  if (e <= y->e_contact) return y->EA;
  if (e <= 0.0) return y->k_comp * y->EA;
  if (e <= y->crimp) return y->Ec;
  return YarnSlope(y, (e - y->crimp) / (1.0 + y->crimp)) / (1.0 + y->crimp);
}

/* integral over [0, t] (t in [0,1]) of the Hermite cell k of the yarn table, in yarn strain:
   h * int (1+2u)(1-u)^2 T0 + u(1-u)^2 h dT0 + u^2(3-2u) T1 - u^2(1-u) h dT1 du */
static PetscReal HermiteCellIntegral(const YarnLaw *y, PetscInt k, PetscReal t)
{
  const PetscReal h = y->tab_h, t2 = t * t, t3 = t2 * t;
  return h * (y->tab_T[k] * t * (1.0 + t2 * (-1.0 + 0.5 * t)) +
              h * y->tab_dT[k] * t2 * (0.5 + t * (-2.0 / 3.0 + 0.25 * t)) + y->tab_T[k + 1] * t3 * (1.0 - 0.5 * t) +
              h * y->tab_dT[k + 1] * t3 * (-1.0 / 3.0 + 0.25 * t));
}

/* integral[k] = integral of Tyarn over the whole cells below node k */
static PetscErrorCode YarnIntegralSetUp(const YarnLaw *y, PetscReal **integral)
{
  PetscFunctionBeginUser;
  *integral = NULL;
  if (!y || !y->ntab) PetscFunctionReturn(0);
  PetscCall(PetscMalloc1(y->ntab, integral));
  (*integral)[0] = 0.0;
  for (PetscInt k = 0; k + 1 < y->ntab; k++) (*integral)[k + 1] = (*integral)[k] + HermiteCellIntegral(y, k, 1.0);
  PetscFunctionReturn(0);
}

static PetscReal YarnCellsBelow(const YarnLaw *y, const PetscReal *integral, PetscInt k)
{
  PetscReal sum = 0.0;
  if (integral) return integral[k];
  for (PetscInt q = 0; q < k; q++) sum += HermiteCellIntegral(y, q, 1.0); /* the table's order of summation */
  return sum;
}

/* integral of Tyarn from 0 to ey >= 0, exact: cells below, the partial cell, the linear extension */
static PetscReal YarnEnergy(const YarnLaw *y, const PetscReal *integral, PetscReal ey)
{
  if (!y->ntab) return 0.5 * y->EA * ey * ey;
  const PetscInt  last = y->ntab - 1;
  const PetscReal s    = ey * y->tab_inv_h;
  if (s >= (PetscReal)last) {
    const PetscReal d = ey - y->tab_end;
    return YarnCellsBelow(y, integral, last) + y->tab_T[last] * d + 0.5 * y->tab_dT[last] * d * d;
  }
  const PetscInt k = (PetscInt)s;
  return YarnCellsBelow(y, integral, k) + HermiteCellIntegral(y, k, s - (PetscReal)k);
}

/* integral from 0 to e of the piecewise law (ChordTensionPiecewise), MODEL.md 14 */
static PetscReal PiecewiseEnergy(const YarnLaw *y, const PetscReal *integral, PetscReal e)
{
  const PetscReal ec = y->e_contact, kEA = y->k_comp * y->EA, c = y->crimp;
  if (e <= ec) return 0.5 * kEA * ec * ec + kEA * ec * (e - ec) + 0.5 * y->EA * (e - ec) * (e - ec);
  if (e <= 0.0) return 0.5 * kEA * e * e;
  if (e <= c) return 0.5 * y->Ec * e * e;
  return 0.5 * y->Ec * c * c + y->Ec * c * (e - c) + (1.0 + c) * YarnEnergy(y, integral, (e - c) / (1.0 + c));
}

/* integral over [lo, z] of blend k's cubic minus the piecewise law it replaces */
static PetscReal BlendExcess(const YarnLaw *y, const PetscReal *integral, PetscInt k, PetscReal z)
{
  const PetscReal lo = y->blend[k].lo, s = z - lo;
  const PetscReal cubic =
    s * (y->blend[k].c0 + s * (0.5 * y->blend[k].c1 + s * (y->blend[k].c2 / 3.0 + s * 0.25 * y->blend[k].c3)));
  return cubic - (PiecewiseEnergy(y, integral, z) - PiecewiseEnergy(y, integral, lo));
}

/* integral of ChordTension from 0 to e: the piecewise law's, corrected on each blend's part of [0, e] */
PetscReal ChordEnergy(const YarnLaw *y, const PetscReal *integral, PetscReal e)
{
  PetscReal W = PiecewiseEnergy(y, integral, e);
  for (PetscInt k = 0; k < y->nblend; k++) {
    const PetscReal lo = y->blend[k].lo, hi = y->blend[k].hi;
    const PetscReal ze = PetscMin(PetscMax(e, lo), hi), z0 = PetscMin(PetscMax(0.0, lo), hi);
    if (ze != z0) W += BlendExcess(y, integral, k, ze) - BlendExcess(y, integral, k, z0);
  }
  return W;
}

/* padded existence of the point at local (li, lj); -1 and gxm/gym are absent */
static inline unsigned char Exists(const Patch *p, PetscInt li, PetscInt lj)
{
  return p->epad[(lj + 1) * (p->gxm + 2) + li + 1];
}

static void ZeroSegmentRow(SegmentRow *s, PetscInt c0, PetscInt c1)
{
  PetscReal *a[] = {s->ux, s->uy, s->uz, s->inv_len, s->fx, s->fy, s->fz, s->T};
  for (int k = 0; k < 8; k++) memset(a[k] + c0, 0, sizeof(PetscReal) * (size_t)(c1 - c0));
}

/* Segments a[i] -> b[i], c0 <= i < c1: chord and tension (MODEL.md 5.1). */
static void ComputeSegmentRow(const YarnLaw *law, PetscReal L0, PetscBool traction, PetscInt c0, PetscInt c1, const PetscReal *restrict xa, const PetscReal *restrict xb, const unsigned char *ea, const unsigned char *eb, const unsigned char *broken, SegmentRow *s)
{
  const PetscReal inv_L0 = 1.0 / L0;

  for (PetscInt i = c0; i < c1; i++) {
    const PetscReal dx = xb[3 * i] - xa[3 * i], dy = xb[3 * i + 1] - xa[3 * i + 1], dz = xb[3 * i + 2] - xa[3 * i + 2];
    const PetscReal L = PetscSqrtReal(dx * dx + dy * dy + dz * dz), e_raw = L * inv_L0 - 1.0;
    const PetscReal e = PetscAbsReal(e_raw) < STRAIN_ROUNDOFF ? 0.0 : e_raw;
    const int       alive = ea[i] && eb[i] && !broken[i];
    const PetscReal inv   = alive ? 1.0 / L : 0.0;
    const PetscReal T     = (alive && traction) ? ChordTension(law, e) : 0.0;
    s->ux[i] = dx * inv;
    s->uy[i] = dy * inv;
    s->uz[i] = dz * inv;
    s->inv_len[i] = inv;
    s->T[i]       = T;
    s->fx[i]      = T * dx * inv;
    s->fy[i]      = T * dy * inv;
    s->fz[i]      = T * dz * inv;
  }
}

/* Bending centres c0 <= i < c1 with incoming chord s1[i] and outgoing chord s2[i] (MODEL.md 5.2). */
static void ComputeBendRow(PetscReal kb, PetscInt c0, PetscInt c1, const PetscReal *u1x, const PetscReal *u1y, const PetscReal *u1z, const PetscReal *i1, const PetscReal *u2x, const PetscReal *u2y, const PetscReal *u2z, const PetscReal *i2, BendRow *b, PetscInt off)
{
  /* u2 - s u1 = (u1 x u2) x u1 and u1 - s u2 = u2 x (u1 x u2): the cross-product form has no
     cancellation for nearly straight yarns and is exactly zero for parallel chords */
  for (PetscInt i = c0; i < c1; i++) {
    const PetscReal cx = u1y[i] * u2z[i] - u1z[i] * u2y[i], cy = u1z[i] * u2x[i] - u1x[i] * u2z[i], cz = u1x[i] * u2y[i] - u1y[i] * u2x[i];
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
static void ComputeShearRow(const Patch *p, const PetscReal *x, PetscInt r, PetscInt c0, PetscInt c1, ShearRow *sh)
{
  const PetscInt   n = p->gxm, lr = r - p->gys;
  const PetscReal *xr = (lr >= 0 && lr < p->gym) ? x + 3 * lr * n : p->zero_row;
  const PetscReal *xd = (lr - 1 >= 0 && lr - 1 < p->gym) ? x + 3 * (lr - 1) * n : p->zero_row;
  const PetscReal *xu = (lr + 1 >= 0 && lr + 1 < p->gym) ? x + 3 * (lr + 1) * n : p->zero_row;
  const PetscReal  Ks = p->Ks, Kj = p->Kj, sl = p->s_lock;

  if (lr < 0 || lr >= p->gym) { /* no crossing outside the patch */
    PetscReal *a[] = {sh->hwx, sh->hwy, sh->hwz, sh->hfx, sh->hfy, sh->hfz, sh->sx, sh->sy, sh->sz};
    for (int k = 0; k < 9; k++) memset(a[k] + c0, 0, sizeof(PetscReal) * (size_t)(c1 - c0));
    return;
  }
  for (PetscInt li = c0; li < c1; li++) {
    const int      self = Exists(p, li, lr), hl = Exists(p, li - 1, lr), hr = Exists(p, li + 1, lr);
    const int      hd = Exists(p, li, lr - 1), hu = Exists(p, li, lr + 1);
    const PetscInt il = hl ? li - 1 : li, ir = hr ? li + 1 : li;
    const PetscReal *xp = xr + 3 * ir, *xm = xr + 3 * il, *yp = hu ? xu + 3 * li : xr + 3 * li, *ym = hd ? xd + 3 * li : xr + 3 * li;
    const PetscReal twx = xp[0] - xm[0], twy = xp[1] - xm[1], twz = xp[2] - xm[2];
    const PetscReal tfx = yp[0] - ym[0], tfy = yp[1] - ym[1], tfz = yp[2] - ym[2];
    const int       active = self && (hl || hr) && (hd || hu);
    const PetscReal iw = active ? 1.0 / PetscSqrtReal(twx * twx + twy * twy + twz * twz) : 0.0;
    const PetscReal jf = active ? 1.0 / PetscSqrtReal(tfx * tfx + tfy * tfy + tfz * tfz) : 0.0;
    const PetscReal uwx = twx * iw, uwy = twy * iw, uwz = twz * iw, ufx = tfx * jf, ufy = tfy * jf, ufz = tfz * jf;
    const PetscReal s = uwx * ufx + uwy * ufy + uwz * ufz, as = PetscAbsReal(s);
    const PetscReal jam = as > sl ? (s > 0 ? as - sl : sl - as) : 0.0;
    const PetscReal Ep = Ks * s + Kj * jam;
    const PetscReal cw = Ep * iw, cf = Ep * jf;
    const PetscReal hwx = cw * (ufx - s * uwx), hwy = cw * (ufy - s * uwy), hwz = cw * (ufz - s * uwz);
    const PetscReal hfx = cf * (uwx - s * ufx), hfy = cf * (uwy - s * ufy), hfz = cf * (uwz - s * ufz);
    const PetscReal aw = (PetscReal)(hr - hl), af = (PetscReal)(hu - hd);
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
static void YSegments(Patch *p, const PetscReal *x, PetscInt r, PetscInt c0, PetscInt c1)
{
  const PetscInt n = p->gxm, lr = r - p->gys;
  SegmentRow    *s = &p->ys_ring[SLOT(r)];

  if (lr < 0 || lr + 1 >= p->gym) {
    ZeroSegmentRow(s, c0, c1);
    return;
  }
  ComputeSegmentRow(p->weft, p->ay, p->traction, c0, c1, x + 3 * lr * n, x + 3 * (lr + 1) * n, p->exists + lr * n, p->exists + (lr + 1) * n, p->broken_y + lr * n, s);
}

/* y-bending centres of row r: chords y(r-1) and y(r) */
static void YBending(Patch *p, PetscInt r, PetscInt c0, PetscInt c1)
{
  const SegmentRow *a = &p->ys_ring[SLOT(r - 1)], *b = &p->ys_ring[SLOT(r)];
  ComputeBendRow(p->kby, c0, c1, a->ux, a->uy, a->uz, a->inv_len, b->ux, b->uy, b->uz, b->inv_len, &p->by_ring[SLOT(r)], 0);
}

void ComputeInternalForces(Patch *p, const PetscReal *x, const PetscInt box[4], PetscReal *f, PetscReal *tension_max)
{
  const PetscInt  n = p->gxm, i0 = box[0] - p->gxs, i1 = box[1] - p->gxs, j0 = box[2], j1 = box[3];
  const PetscInt  c0 = PetscMax(i0 - 2, 0), c1 = PetscMin(i1 + 2, n); /* columns the box's forces need */
  const PetscBool bend = p->bending, shear = p->shear;
  PetscReal       tmax = 0.0;

  *tension_max = 0.0;
  if (i1 <= i0 || j1 <= j0) return;
  /* prime the pipeline: rows below the first row of the box */
  for (PetscInt r = j0 - 2; r <= j0; r++) YSegments(p, x, r, c0, c1);
  if (bend)
    for (PetscInt r = j0 - 1; r <= j0; r++) YBending(p, r, c0, c1);
  if (shear)
    for (PetscInt r = j0 - 1; r <= j0; r++) ComputeShearRow(p, x, r, c0, c1, &p->sh_ring[SLOT(r)]);

  for (PetscInt j = j0; j < j1; j++) {
    const PetscInt lj = j - p->gys;
    SegmentRow    *xs = &p->xs_row;

    /* advance the pipeline by one row */
    YSegments(p, x, j + 1, c0, c1);
    if (bend) YBending(p, j + 1, c0, c1);
    if (shear) ComputeShearRow(p, x, j + 1, c0, c1, &p->sh_ring[SLOT(j + 1)]);
    ComputeSegmentRow(p->warp, p->ax, p->traction, c0, PetscMin(c1, n - 1), x + 3 * lj * n, x + 3 * lj * n + 3, p->exists + lj * n, p->exists + lj * n + 1, p->broken_x + lj * n, xs);
    if (bend) ComputeBendRow(p->kbx, c0, PetscMin(c1, n - 1) - 1, xs->ux, xs->uy, xs->uz, xs->inv_len, xs->ux + 1, xs->uy + 1, xs->uz + 1, xs->inv_len + 1, &p->bx_row, 1);

    /* gather: each point of row j in the box sums its terms in a fixed order */
    {
      const SegmentRow *yd = &p->ys_ring[SLOT(j - 1)], *yu = &p->ys_ring[SLOT(j)];
      PetscReal *restrict fr = f + 3 * (j - p->ys) * p->xm - 3 * (p->xs - p->gxs);
      for (PetscInt i = i0; i < i1; i++) {
        fr[3 * i]     = xs->fx[i] - xs->fx[i - 1] + yu->fx[i] - yd->fx[i];
        fr[3 * i + 1] = xs->fy[i] - xs->fy[i - 1] + yu->fy[i] - yd->fy[i];
        fr[3 * i + 2] = xs->fz[i] - xs->fz[i - 1] + yu->fz[i] - yd->fz[i];
        const PetscReal t = PetscMax(PetscMax(PetscAbsReal(xs->T[i]), PetscAbsReal(xs->T[i - 1])), PetscMax(PetscAbsReal(yu->T[i]), PetscAbsReal(yd->T[i])));
        tmax = PetscMax(tmax, t);
      }
      if (bend) {
        const BendRow *bx = &p->bx_row, *bd = &p->by_ring[SLOT(j - 1)], *bc = &p->by_ring[SLOT(j)], *bu = &p->by_ring[SLOT(j + 1)];
        for (PetscInt i = i0; i < i1; i++) {
          fr[3 * i] += bx->g2x[i - 1] + bx->g1x[i] - bx->g2x[i] - bx->g1x[i + 1] + bd->g2x[i] + bc->g1x[i] - bc->g2x[i] - bu->g1x[i];
          fr[3 * i + 1] += bx->g2y[i - 1] + bx->g1y[i] - bx->g2y[i] - bx->g1y[i + 1] + bd->g2y[i] + bc->g1y[i] - bc->g2y[i] - bu->g1y[i];
          fr[3 * i + 2] += bx->g2z[i - 1] + bx->g1z[i] - bx->g2z[i] - bx->g1z[i + 1] + bd->g2z[i] + bc->g1z[i] - bc->g2z[i] - bu->g1z[i];
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

/* Break every segment of the patch whose yarn strain exceeds the breaking strain
   (MODEL.md 5.1). Called on a balanced state: strains of the relaxation transient are
   artefacts of the load stepping. Returns 1 if a segment at an owned point broke. */
int BreakSegments(Patch *p, const PetscReal *x)
{
  int broke = 0;
  for (int dir = 0; dir < 2; dir++) {
    const YarnLaw  *law = dir == 0 ? p->warp : p->weft;
    const PetscReal L0 = dir == 0 ? p->ax : p->ay;
    unsigned char  *broken = dir == 0 ? p->broken_x : p->broken_y;
    if (!isfinite(law->break_e)) continue;
    for (PetscInt lj = 0; lj + (dir == 1) < p->gym; lj++)
      for (PetscInt li = 0; li + (dir == 0) < p->gxm; li++) {
        const PetscInt k = lj * p->gxm + li, k2 = k + (dir == 0 ? 1 : p->gxm);
        if (broken[k] || !p->exists[k] || !p->exists[k2]) continue;
        const PetscReal *a = x + 3 * k, *b = x + 3 * k2;
        const PetscReal  L = PetscSqrtReal(PetscSqr(b[0] - a[0]) + PetscSqr(b[1] - a[1]) + PetscSqr(b[2] - a[2]));
        if (L / L0 - 1.0 <= law->break_e) continue;
        broken[k] = 1;
        {
          const PetscInt i = p->gxs + li, j = p->gys + lj, i2 = i + (dir == 0), j2 = j + (dir == 1);
          const int own_a = i >= p->xs && i < p->xs + p->xm && j >= p->ys && j < p->ys + p->ym;
          const int own_b = i2 >= p->xs && i2 < p->xs + p->xm && j2 >= p->ys && j2 < p->ys + p->ym;
          if (own_a || own_b) broke = 1;
        }
      }
  }
  return broke;
}

/* ---------------- stable step: Gershgorin bound of the tangent stiffness ---------------- */

typedef struct {
  PetscReal L;   /* chord length */
  int       alive;
} Chord;

static inline const PetscReal *Pos(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j)
{
  return x + 3 * ((j - p->gys) * p->gxm + (i - p->gxs));
}

/* existence of the point at global (i, j); points beyond the ghosted patch (two or more
   crossings outside the grid, where the padding of epad ends) do not exist */
static inline int ExistsG(const Patch *p, PetscInt i, PetscInt j)
{
  const PetscInt li = i - p->gxs, lj = j - p->gys;
  if (li < -1 || li > p->gxm || lj < -1 || lj > p->gym) return 0;
  return Exists(p, li, lj);
}

/* chord from (i,j) along x (dir 0) or y (dir 1) */
static Chord ChordAt(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, int dir)
{
  Chord          c  = {0.0, 0};
  const PetscInt i2 = i + (dir == 0), j2 = j + (dir == 1);
  if (!ExistsG(p, i, j) || !ExistsG(p, i2, j2)) return c;
  const unsigned char *broken = dir == 0 ? p->broken_x : p->broken_y;
  if (broken[(j - p->gys) * p->gxm + (i - p->gxs)]) return c;
  const PetscReal *a = Pos(p, x, i, j), *b = Pos(p, x, i2, j2);
  c.L     = PetscSqrtReal(PetscSqr(b[0] - a[0]) + PetscSqr(b[1] - a[1]) + PetscSqr(b[2] - a[2]));
  c.alive = 1;
  return c;
}

/* The cosine s of the angle between crossing (i,j)'s warp tangent x(i+1,j) - x(i-1,j) and
   weft tangent x(i,j+1) - x(i,j-1), one-sided at an edge (MODEL.md 5.3), and the shorter
   tangent's length. 0 if the crossing has no shear (absent, or no warp or no weft neighbour). */
int CrossingShear(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, PetscReal *s, PetscReal *tmin)
{
  if (!ExistsG(p, i, j)) return 0;
  const int hl = ExistsG(p, i - 1, j), hr = ExistsG(p, i + 1, j), hd = ExistsG(p, i, j - 1), hu = ExistsG(p, i, j + 1);
  if (!(hl || hr) || !(hd || hu)) return 0;
  const PetscReal *xp = Pos(p, x, hr ? i + 1 : i, j), *xm = Pos(p, x, hl ? i - 1 : i, j);
  const PetscReal *yp = Pos(p, x, i, hu ? j + 1 : j), *ym = Pos(p, x, i, hd ? j - 1 : j);
  PetscReal        tw[3], tf[3];
  for (int d = 0; d < 3; d++) {
    tw[d] = xp[d] - xm[d];
    tf[d] = yp[d] - ym[d];
  }
  const PetscReal nw = PetscSqrtReal(tw[0] * tw[0] + tw[1] * tw[1] + tw[2] * tw[2]), nf = PetscSqrtReal(tf[0] * tf[0] + tf[1] * tf[1] + tf[2] * tf[2]);
  if (!(nw > 0 && nf > 0)) return 0;
  *s    = PetscMax(-1.0, PetscMin(1.0, (tw[0] * tf[0] + tw[1] * tf[1] + tw[2] * tf[2]) / (nw * nf)));
  *tmin = PetscMin(nw, nf);
  return 1;
}

/* Gershgorin contribution of crossing (i,j)'s shear energy to one of its points:
   |E''| |grad s|_a sum_b |grad s|_b + |E'| |hess s| row <= (Ks+Kj)(4 + 12|s|)/tmin^2 */
/* the jamming stiffness counts once the crossing is within the window of the lock (in
   s = sin(shear angle)); the default window (1) always counts it */
static PetscReal ShearRowBound(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, PetscReal window)
{
  PetscReal s, tmin;
  if (!CrossingShear(p, x, i, j, &s, &tmin)) return 0.0;
  return (p->Ks + (PetscAbsReal(s) + window >= p->s_lock ? p->Kj : 0.0)) * (4.0 + 12.0 * PetscAbsReal(s)) / (tmin * tmin);
}

PetscReal StableOmega2(const Patch *p, const PetscReal *x, const PetscReal *inv_m, PetscReal window, int pull_dir, PetscReal *omega2_pull)
{
  PetscReal omega2 = 0.0, pull2 = 0.0;

  for (PetscInt j = p->ys; j < p->ys + p->ym; j++) {
    for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
      const PetscReal im = inv_m[(j - p->ys) * p->xm + (i - p->xs)];
      PetscReal       rs = 0.0, rp = 0.0;
      if (im <= 0.0) continue;
      /* traction: a spring adds 2 max(dT/de / L0, T/L) to each end's row */
      for (int dir = 0; dir < 2; dir++) {
        const YarnLaw *law = dir == 0 ? p->warp : p->weft;
        const PetscReal L0 = dir == 0 ? p->ax : p->ay;
        for (int side = -1; side <= 0; side++) {
          const PetscInt ia = i + (dir == 0 ? side : 0), ja = j + (dir == 1 ? side : 0);
          const Chord    c  = ChordAt(p, x, ia, ja, dir);
          if (!c.alive || !p->traction) continue;
          const PetscReal e = c.L / L0 - 1.0, T = ChordTension(law, e);
          rs += 2.0 * PetscMax(ChordTangentMax(law, e - window, e + window) / L0, PetscAbsReal(T) / c.L);
          if (dir == pull_dir) rp += 2.0 * PetscMax(ChordTangentMax(law, e, e + 0.005) / L0, PetscAbsReal(T) / c.L); /* current stiffness, tension side */
        }
      }
      /* bending: centre c in {p-1, p, p+1}; row sums 12, 24, 12 times kb / Lmin^2, with
         Lmin no longer than the contact length (a chord can be squeezed that far in a step) */
      if (p->bending) {
        for (int dir = 0; dir < 2; dir++) {
          const PetscReal kb = dir == 0 ? p->kbx : p->kby;
          const PetscReal Lc = (1.0 + (dir == 0 ? p->warp : p->weft)->e_contact) * (dir == 0 ? p->ax : p->ay);
          for (int k = -1; k <= 1; k++) {
            const PetscInt ic = i + (dir == 0 ? k : 0), jc = j + (dir == 1 ? k : 0);
            const Chord    c1 = ChordAt(p, x, ic - (dir == 0), jc - (dir == 1), dir), c2 = ChordAt(p, x, ic, jc, dir);
            if (!c1.alive || !c2.alive) continue;
            const PetscReal Lmin = PetscMin(PetscMin(c1.L, c2.L), Lc);
            rs += kb * (k == 0 ? 24.0 : 12.0) / (Lmin * Lmin);
          }
        }
      }
      /* shear: the crossings that involve this point */
      if (p->shear) {
        rs += ShearRowBound(p, x, i - 1, j, window) + ShearRowBound(p, x, i + 1, j, window) + ShearRowBound(p, x, i, j - 1, window) + ShearRowBound(p, x, i, j + 1, window);
        if (!ExistsG(p, i - 1, j) || !ExistsG(p, i + 1, j) || !ExistsG(p, i, j - 1) || !ExistsG(p, i, j + 1)) rs += ShearRowBound(p, x, i, j, window);
      }
      rs += p->k_contact; /* a rigid body's penalty spring, whether in contact or not */
      omega2 = PetscMax(omega2, rs * im);
      pull2  = PetscMax(pull2, rp * im);
    }
  }
  *omega2_pull = pull2;
  return omega2;
}
