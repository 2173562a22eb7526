/* kernels.c - the internal force terms of the crossing-point model and the stable-step bound.
 *
 * Each term derives from an energy (MODEL.md 5.1-5.3, 14); its force is minus the gradient:
 *  - traction, per yarn segment (2 points): E = L0 * integral_0^e T, force T d/L on its first
 *    point, -T d/L on its second (a broken segment carries nothing; BreakSegments breaks them);
 *  - bending, per yarn centre c with chords e1 (into c) and e2 (out of c) (3 points):
 *      E = kb (1 - s), s = u1.u2, kb = B/L0; with g1 = (u2 - s u1)/|e1|, g2 = (u1 - s u2)/|e2|
 *      (evaluated as cross products, see ComputeBendRow)
 *      the force is -kb g1 on c-1, kb (g1 - g2) on c, kb g2 on c+1;
 *  - shear, per crossing c with warp tangent tw = x(c+ex) - x(c-ex) and weft tangent
 *    tf = x(c+ey) - x(c-ey) (one-sided at an edge; 3 to 5 points): s = cos(tw,tf),
 *      E = Ks s^2/2 + Kj max(0,|s|-s_lock)^2/2; with Hw = E'(s) (uf - s uw)/|tw| the force
 *      is -Hw on the plus end of tw and +Hw on its minus end (likewise Hf for tf).
 *
 * The file has one section per term, each with: the row function of the force pipeline and
 * its gather, the instance (energy, gradient and dense Hessian of one segment, centre or
 * crossing, for the quasi-static path) and the term's share of the stable-step bound (MODEL.md 7.3).
 * Then: the fused row pipeline, the terms' descriptors with the loops over a box (energy,
 * tangent), and the stable-step bound.
 *
 * The pipeline sweeps the patch row by row (it keeps the y-segment, y-bending and shear rows
 * j-2..j+1 in a ring), so every term is evaluated once per step and the rows stay in cache.
 * Each owned point then sums its contributions in a fixed order: results do not depend on
 * the decomposition. A term that is switched off is neither computed nor summed.
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

/* ================================ the patch ================================ */

static PetscErrorCode AllocRow(PetscInt n, PetscInt count, PetscReal *work, PetscReal **ptrs[])
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < count; k++) *ptrs[k] = work + k * (n + 2) + 1; /* index -1 and n are zero padding */
  PetscFunctionReturn(0);
}

static PetscErrorCode YarnIntegralSetUp(const YarnLaw *y, PetscReal **integral);

static PetscErrorCode PatchAllocRows(Patch *p)
{
  PetscInt n = p->gxm, per_row = n + 2, rows = 0, k = 0;

  PetscFunctionBeginUser;
  rows = 8 + 8 * KERNEL_RING + 6 + 6 * KERNEL_RING + 10 * KERNEL_RING;
  PetscCall(PetscCalloc1((size_t) rows * per_row, &p->work));
  {
    SegmentRow *s      = &p->xs_row;
    PetscReal **ptrs[] = {&s->ux, &s->uy, &s->uz, &s->inv_len, &s->fx, &s->fy, &s->fz, &s->T};
    PetscCall(AllocRow(n, 8, p->work + (k++) * 8 * per_row, ptrs));
  }
  for (PetscInt r = 0; r < KERNEL_RING; r++) {
    SegmentRow *s      = &p->ys_ring[r];
    PetscReal **ptrs[] = {&s->ux, &s->uy, &s->uz, &s->inv_len, &s->fx, &s->fy, &s->fz, &s->T};
    PetscCall(AllocRow(n, 8, p->work + (k++) * 8 * per_row, ptrs));
  }
  {
    BendRow    *b      = &p->bx_row;
    PetscReal **ptrs[] = {&b->g1x, &b->g1y, &b->g1z, &b->g2x, &b->g2y, &b->g2z};
    PetscCall(AllocRow(n, 6, p->work + k * 8 * per_row, ptrs));
  }
  {
    PetscReal *base = p->work + (k * 8 + 6) * per_row;
    for (PetscInt r = 0; r < KERNEL_RING; r++) {
      BendRow    *b      = &p->by_ring[r];
      PetscReal **ptrs[] = {&b->g1x, &b->g1y, &b->g1z, &b->g2x, &b->g2y, &b->g2z};
      PetscCall(AllocRow(n, 6, base + r * 6 * per_row, ptrs));
    }
    base += 6 * KERNEL_RING * per_row;
    for (PetscInt r = 0; r < KERNEL_RING; r++) {
      ShearRow   *s      = &p->sh_ring[r];
      PetscReal **ptrs[] = {&s->hwx, &s->hwy, &s->hwz, &s->hfx, &s->hfy, &s->hfz, &s->sx, &s->sy, &s->sz, &s->as};
      PetscCall(AllocRow(n, 10, base + r * 10 * per_row, ptrs));
    }
  }
  PetscFunctionReturn(0);
}

/* the stable-step bound's rows: 8 arrays a segment row, 1 a shear row, 13 scratch rows, columns -2..gxm+1 */
static PetscErrorCode PatchAllocBoundRows(Patch *p)
{
  const PetscInt per_row = p->gxm + 4;
  PetscReal     *w;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1((size_t) (8 * (1 + KERNEL_RING) + KERNEL_RING + 13) * per_row, &p->bound_work));
  w = p->bound_work + 2;
  for (PetscInt r = -1; r < KERNEL_RING; r++) {
    BoundSegRow *s = r < 0 ? &p->bx_seg : &p->by_seg[r];
    s->L           = w, w += per_row;
    for (int q = 0; q < 6; q++) s->b[q] = w, w += per_row;
    s->pull = w, w += per_row;
  }
  for (PetscInt r = 0; r < KERNEL_RING; r++) p->bsh_ring[r] = w, w += per_row;
  for (int q = 0; q < 13; q++) p->bound_row[q] = w, w += per_row;
  PetscFunctionReturn(0);
}

PetscErrorCode PatchSetUp(Patch *p)
{
  PetscInt per_row = p->gxm + 2;

  PetscFunctionBeginUser;
  PetscCall(PatchAllocRows(p));
  PetscCall(PatchAllocBoundRows(p));
  for (int d = 0; d < 2; d++) p->win_lo[d] = -PETSC_MAX_REAL, p->win_hi[d] = PETSC_MAX_REAL; /* until a bound */
  p->win_s = PETSC_MAX_REAL;
  PetscCall(PetscCalloc1(3 * (size_t) p->gxm, &p->zero_row));
  PetscCall(PetscCalloc1((size_t) p->gxm, &p->strain_row));
  PetscCall(PetscCalloc1(2 * (size_t) p->gxm, &p->break_row));
  PetscCall(PetscCalloc1((size_t) (p->gym + 2) * per_row, &p->epad));
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
  PetscCall(PetscFree(p->bound_work));
  PetscCall(PetscFree(p->zero_row));
  PetscCall(PetscFree(p->strain_row));
  PetscCall(PetscFree(p->break_row));
  PetscCall(PetscFree(p->epad));
  PetscCall(PetscFree(p->yarn_integral[0]));
  PetscCall(PetscFree(p->yarn_integral[1]));
  PetscFunctionReturn(0);
}

/* padded existence of the point at local (li, lj); -1 and gxm/gym are absent */
static inline unsigned char Exists(const Patch *p, PetscInt li, PetscInt lj)
{
  return p->epad[(lj + 1) * (p->gxm + 2) + li + 1];
}

/* existence of the point at global (i, j); points beyond the ghosted patch (two or more
   crossings outside the grid, where the padding of epad ends) do not exist */
static inline int ExistsG(const Patch *p, PetscInt i, PetscInt j)
{
  const PetscInt li = i - p->gxs, lj = j - p->gys;
  if (li < -1 || li > p->gxm || lj < -1 || lj > p->gym) return 0;
  return Exists(p, li, lj);
}

static inline const PetscReal *Pos(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j)
{
  return x + 3 * ((j - p->gys) * p->gxm + (i - p->gxs));
}

/* the segment from (i,j) along x (dir 0) or y (dir 1): both ends exist and it is not broken */
static inline int SegmentAlive(const Patch *p, PetscInt i, PetscInt j, int dir)
{
  const unsigned char *broken = dir == 0 ? p->broken_x : p->broken_y;
  if (!ExistsG(p, i, j) || !ExistsG(p, i + (dir == 0), j + (dir == 1))) return 0;
  return !broken[(j - p->gys) * p->gxm + (i - p->gxs)];
}

typedef struct {
  PetscReal d[3]; /* chord vector, from (i,j) */
  PetscReal L;    /* chord length */
  int       alive;
} Chord;

/* chord from (i,j) along x (dir 0) or y (dir 1) */
static Chord ChordAt(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, int dir)
{
  Chord c = {{0.0, 0.0, 0.0}, 0.0, 0};
  if (!SegmentAlive(p, i, j, dir)) return c;
  const PetscReal *a = Pos(p, x, i, j), *b = Pos(p, x, i + (dir == 0), j + (dir == 1));
  for (int q = 0; q < 3; q++) c.d[q] = b[q] - a[q];
  c.L     = PetscSqrtReal(PetscSqr(c.d[0]) + PetscSqr(c.d[1]) + PetscSqr(c.d[2]));
  c.alive = 1;
  return c;
}

/* ======================= traction (MODEL.md 5.1, 7.3, 14) ======================= */

/* --- the yarn law's slope and integral --- */

/* dTyarn/dey at yarn strain ey >= 0: EA, or the derivative of the Hermite cell (material.h) */
static PetscReal YarnSlope(const YarnLaw *y, PetscReal ey)
{
  if (!y->ntab) return y->EA;
  const PetscReal s = ey * y->tab_inv_h;
  if (s >= (PetscReal) (y->ntab - 1)) return y->tab_dT[y->ntab - 1];
  const PetscInt  k = (PetscInt) s;
  const PetscReal t = s - (PetscReal) k;
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
  if (s >= (PetscReal) last) {
    const PetscReal d = ey - y->tab_end;
    return YarnCellsBelow(y, integral, last) + y->tab_T[last] * d + 0.5 * y->tab_dT[last] * d * d;
  }
  const PetscInt k = (PetscInt) s;
  return YarnCellsBelow(y, integral, k) + HermiteCellIntegral(y, k, s - (PetscReal) k);
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

/* --- force rows --- */

static void ZeroSegmentRow(SegmentRow *s, PetscInt c0, PetscInt c1)
{
  PetscReal *a[] = {s->ux, s->uy, s->uz, s->inv_len, s->fx, s->fy, s->fz, s->T};
  for (int k = 0; k < 8; k++) memset(a[k] + c0, 0, sizeof(PetscReal) * (size_t) (c1 - c0));
}

/* Chords a[i] -> b[i], c0 <= i < c1: unit chord and 1/L (0 for an absent, broken or zero-length
   segment: a zero-length chord has no direction, no force), the strain parked in e and the chord
   in d (every array a parameter of its own, restrict: the loop vectorises) */
static void ChordRowKernel(PetscReal inv_L0, PetscInt c0, PetscInt c1, const PetscReal *restrict xa,
                           const PetscReal *restrict xb, const unsigned char *restrict ea,
                           const unsigned char *restrict eb, const unsigned char *restrict broken,
                           PetscReal *restrict ux, PetscReal *restrict uy, PetscReal *restrict uz,
                           PetscReal *restrict inv_len, PetscReal *restrict e, PetscReal *restrict dxr,
                           PetscReal *restrict dyr, PetscReal *restrict dzr)
{
  for (PetscInt i = c0; i < c1; i++) {
    const PetscReal dx = xb[3 * i] - xa[3 * i], dy = xb[3 * i + 1] - xa[3 * i + 1], dz = xb[3 * i + 2] - xa[3 * i + 2];
    const PetscReal L = PetscSqrtReal(dx * dx + dy * dy + dz * dz), e_raw = L * inv_L0 - 1.0;
    const int       alive = (ea[i] != 0) & (eb[i] != 0) & (broken[i] == 0) & (L > 0);
    const PetscReal q = 1.0 / (L > 0 ? L : 1.0), inv = alive ? q : 0.0; /* 1/L of a safe divisor, dropped if dead */
    ux[i]                 = dx * inv;
    uy[i]                 = dy * inv;
    uz[i]                 = dz * inv;
    inv_len[i]            = inv;
    e[i]                  = PetscAbsReal(e_raw) < STRAIN_ROUNDOFF ? 0.0 : e_raw;
    dxr[i]                = dx;
    dyr[i]                = dy;
    dzr[i]                = dz;
  }
}

/* f = T d / L, in place over d */
static void SegmentForceKernel(PetscInt c0, PetscInt c1, const PetscReal *restrict T, const PetscReal *restrict inv_len,
                               PetscReal *restrict fx, PetscReal *restrict fy, PetscReal *restrict fz)
{
  for (PetscInt i = c0; i < c1; i++) {
    fx[i] = T[i] * fx[i] * inv_len[i];
    fy[i] = T[i] * fy[i] * inv_len[i];
    fz[i] = T[i] * fz[i] * inv_len[i];
  }
}

/* T[i] = ChordTension(y, e[i]) for the live segments (alive: both ends exist, not broken), 0 for
   the others, c0 <= i < c1. Every piece of the law is evaluated on the whole row and the right one
   selected, so that the loops vectorise and a row whose strains straddle a kink (a slack net)
   costs no mispredicted branches; a tabulated yarn law's tension piece (a table lookup: the
   cell's nodes gathered) runs on the rows with a segment past the crimp. Each value is
   ChordTension's own expression, the blends taken first (the last pass, from the last blend to
   the first): bit-identical to it at every strain (NaN gives NaN in both). */
static void ChordTensionRow(const YarnLaw *y, PetscInt c0, PetscInt c1, const PetscReal *restrict e,
                            const unsigned char *restrict ea, const unsigned char *restrict eb,
                            const unsigned char *restrict broken, PetscReal *restrict T)
{
  const PetscReal ec = y->e_contact, EA = y->EA, kEA = y->k_comp * y->EA, Ec = y->Ec, c = y->crimp;
  const PetscReal Tcontact = kEA * ec, Tcrimp = Ec * c, c1p = 1.0 + c;

  for (PetscInt i = c0; i < c1; i++) { /* ChordTensionPiecewise, YarnTension of a linear law */
    const PetscReal x = e[i];
    const PetscReal contact = Tcontact + EA * (x - ec), comp = kEA * x, decrimp = Ec * x,
                    tension = Tcrimp + EA * ((x - c) / c1p);
    T[i] = x <= ec ? contact : x <= 0.0 ? comp : x <= c ? decrimp : tension;
  }
  int past = 0; /* a segment past the crimp: the table's piece */
  if (y->ntab)
    for (PetscInt i = c0; i < c1; i++) past |= e[i] > c;
  if (past) { /* YarnTension on the segments past the crimp, as selects (the cells' nodes gathered) */
    const PetscReal *restrict tT = y->tab_T, *restrict tdT = y->tab_dT;
    const PetscReal inv_h = y->tab_inv_h, h = y->tab_h, end = y->tab_end, last = (PetscReal) (y->ntab - 1);
    const PetscReal Tend = tT[y->ntab - 1], dTend = tdT[y->ntab - 1];
    for (PetscInt i = c0; i < c1; i++) {
      const PetscReal x = e[i], ey = (x - c) / c1p, s = ey * inv_h;
      const PetscReal sc = (s >= 0.0) & (s < last) ? s : 0.0; /* a cell of the table, or any (not selected) */
      const int       k = (int) sc;
      const PetscReal t = sc - PetscFloorReal(sc), u = 1.0 - t; /* sc - k: floor is k exactly (sc >= 0) */
      const PetscReal cell = (1.0 + 2.0 * t) * u * u * tT[k] + t * u * u * h * tdT[k] +
                             t * t * (3.0 - 2.0 * t) * tT[k + 1] - t * t * u * h * tdT[k + 1];
      const PetscReal ty = s >= last ? Tend + dTend * (ey - end) : cell;
      T[i]               = x > c ? Tcrimp + ty : T[i];
    }
  }
  for (PetscInt k = y->nblend - 1; k >= 0; k--) {
    const PetscReal lo = y->blend[k].lo, hi = y->blend[k].hi, b0 = y->blend[k].c0, b1 = y->blend[k].c1,
                    b2 = y->blend[k].c2, b3 = y->blend[k].c3;
    for (PetscInt i = c0; i < c1; i++) {
      const PetscReal x = e[i], s = x - lo, cubic = b0 + s * (b1 + s * (b2 + s * b3));
      T[i]                = (x >= lo) & (x <= hi) ? cubic : T[i];
    }
  }
  for (PetscInt i = c0; i < c1; i++) T[i] = (ea[i] != 0) & (eb[i] != 0) & (broken[i] == 0) ? T[i] : 0.0;
}

FABRIC_WIDE void ChordTensionLive(const YarnLaw *y, PetscInt n, const PetscReal *e, PetscReal *T)
{
  unsigned char one[64], none[64];
  memset(one, 1, sizeof one);
  memset(none, 0, sizeof none);
  for (PetscInt i0 = 0; i0 < n; i0 += 64) ChordTensionRow(y, 0, PetscMin(64, n - i0), e + i0, one, one, none, T + i0);
}

/* Segments a[i] -> b[i], c0 <= i < c1: chord and tension (MODEL.md 5.1). The chords are
   computed even with traction off: bending needs them. Three passes, so that the geometry and
   the forces vectorise: chords and strains (the strain in the scratch row e, the chord parked in
   f), the chord law (ChordTensionRow), then f = T d / L. Each value is the same expression as in
   one pass, so the results do not depend on the split. The segments in [k0, k1) are checked
   against the window [lo, hi] of their family's chord strain (left: set if one is outside). */
static void ComputeSegmentRow(const YarnLaw *law, PetscReal L0, PetscBool traction, PetscReal lo, PetscReal hi,
                              PetscInt c0, PetscInt c1, PetscInt k0, PetscInt k1, const PetscReal *xa,
                              const PetscReal *xb, const unsigned char *ea, const unsigned char *eb,
                              const unsigned char *broken, PetscReal *restrict e, SegmentRow *s, int *left)
{
  PetscReal *restrict T = s->T;
  int                 out = 0;

  ChordRowKernel(1.0 / L0, c0, c1, xa, xb, ea, eb, broken, s->ux, s->uy, s->uz, s->inv_len, e, s->fx, s->fy, s->fz);
  if (traction) {
    for (PetscInt i = c0; i < c1; i++)
      out |= (ea[i] != 0) & (eb[i] != 0) & (broken[i] == 0) & (i >= k0) & (i < k1) & ((e[i] < lo) | (e[i] > hi));
    ChordTensionRow(law, c0, c1, e, ea, eb, broken, T);
  } else
    for (PetscInt i = c0; i < c1; i++) T[i] = 0.0;
  *left |= out;
  SegmentForceKernel(c0, c1, T, s->inv_len, s->fx, s->fy, s->fz);
}

/* traction on the points i0 <= i < i1 of row j (written: the first term of the sum), from the
   x-segments of the row and the y-segments below (yd) and above (yu); returns the largest |T| */
static PetscReal GatherTraction(const SegmentRow *xs, const SegmentRow *yd, const SegmentRow *yu, PetscInt i0,
                                PetscInt i1, PetscReal *restrict fr, PetscReal tmax)
{
  int64_t top = AbsBits(tmax); /* the largest |T| as its bits (integer max: the loop vectorises) */
  for (PetscInt i = i0; i < i1; i++) {
    fr[3 * i]     = xs->fx[i] - xs->fx[i - 1] + yu->fx[i] - yd->fx[i];
    fr[3 * i + 1] = xs->fy[i] - xs->fy[i - 1] + yu->fy[i] - yd->fy[i];
    fr[3 * i + 2] = xs->fz[i] - xs->fz[i - 1] + yu->fz[i] - yd->fz[i];
    const int64_t a = AbsBits(xs->T[i]), b = AbsBits(xs->T[i - 1]), c = AbsBits(yu->T[i]), d = AbsBits(yd->T[i]);
    const int64_t ab = a > b ? a : b, cd = c > d ? c : d, t = ab > cd ? ab : cd;
    top              = t > top ? t : top;
  }
  memcpy(&tmax, &top, sizeof tmax);
  return tmax;
}

/* --- instance: energy, gradient and Hessian of segment (i,j) -> (i,j) + e_dir --- */

/* K = (dT/dL) n n^T + (T/L)(I - n n^T), dT/dL = T'(e)/L0, on [a a; a b; b a; b b] with signs + - - + */
static void SegmentHessian(PetscReal kn, PetscReal kg, const PetscReal n[3], PetscReal K[36])
{
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) {
      const PetscReal k = (kn - kg) * n[r] * n[c] + (r == c ? kg : 0.0);
      K[r * 6 + c] = K[(r + 3) * 6 + c + 3] = k;
      K[r * 6 + c + 3] = K[(r + 3) * 6 + c] = -k;
    }
}

static int TractionInstance(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, int dir, int want,
                            TermInstance *t)
{
  const YarnLaw  *law = dir == 0 ? p->warp : p->weft;
  const PetscReal L0  = dir == 0 ? p->ax : p->ay;
  const PetscInt  i2 = i + (dir == 0), j2 = j + (dir == 1);
  PetscReal       d[3], n[3];

  if (!SegmentAlive(p, i, j, dir)) return 0;
  const PetscReal *a = Pos(p, x, i, j), *b = Pos(p, x, i2, j2);
  for (int q = 0; q < 3; q++) d[q] = b[q] - a[q];
  const PetscReal L = PetscSqrtReal(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), e_raw = L / L0 - 1.0;
  const PetscReal e = PetscAbsReal(e_raw) < STRAIN_ROUNDOFF ? 0.0 : e_raw; /* as the force rows */
  const PetscReal T = ChordTension(law, e);
  for (int q = 0; q < 3; q++) n[q] = d[q] / L;
  t->n    = 2;
  t->i[0] = i, t->j[0] = j, t->i[1] = i2, t->j[1] = j2;
  if (want & TERM_ENERGY) t->E = L0 * ChordEnergy(law, p->yarn_integral[dir], e);
  if (want & TERM_GRADIENT)
    for (int q = 0; q < 3; q++) t->g[q] = -T * n[q], t->g[3 + q] = T * n[q];
  if (want & TERM_HESSIAN)
    SegmentHessian(ChordTensionSlope(law, e) / L0, (p->tension_field || (want & TERM_CONVEX) ? PetscMax(T, 0) : T) / L,
                   n, t->K);
  return 1;
}

/* --- stable-step bound: the yarn segments' 3x3 blocks at a point --- */

/* the largest eigenvalue of the symmetric 3x3 matrix b = {xx, yy, zz, xy, xz, yz}: the
   trigonometric solution of its characteristic cubic (the roots are real) */
static PetscReal SymMaxEig3(const PetscReal b[6])
{
  const PetscReal off = b[3] * b[3] + b[4] * b[4] + b[5] * b[5];
  const PetscReal q   = (b[0] + b[1] + b[2]) / 3.0;
  if (off == 0.0) return PetscMax(PetscMax(b[0], b[1]), b[2]);
  const PetscReal a0 = b[0] - q, a1 = b[1] - q, a2 = b[2] - q;
  const PetscReal pp = PetscSqrtReal((a0 * a0 + a1 * a1 + a2 * a2 + 2.0 * off) / 6.0);
  /* det((b - q I) / pp) / 2 */
  const PetscReal r = (a0 * (a1 * a2 - b[5] * b[5]) - b[3] * (b[3] * a2 - b[5] * b[4]) + b[4] * (b[3] * b[5] - a1 * b[4])) /
                      (2.0 * pp * pp * pp);
  const PetscReal phi = PetscAcosReal(PetscMin(PetscMax(r, -1.0), 1.0)) / 3.0;
  return q + 2.0 * pp * PetscCosReal(phi);
}

/* a pull-direction segment's share of its ends' rows for the damping: its current stiffness,
   tension side (no window) */
static inline PetscReal PullSpringRow(const YarnLaw *law, PetscReal L0, PetscReal e, PetscReal T, PetscReal L)
{
  return 2.0 * PetscMax(ChordTangentMax(law, e, e + 0.005) / L0, L > 0 ? PetscAbsReal(T) / L : 0.0);
}

/* a segment's block A_s = k n n^T + g (I - n n^T), g = max(T,0)/L, as k_g d d^T + g I with
   k_g = (k - g)/L^2: b = {xx, yy, zz, xy, xz, yz} (L > 0) */
static inline void SegmentBlock(PetscReal k, PetscReal T, PetscReal L, const PetscReal d[3], PetscReal b[6])
{
  const PetscReal g = PetscMax(T, 0.0) / L, kg = (k - g) / (L * L);
  b[0] = kg * d[0] * d[0] + g, b[1] = kg * d[1] * d[1] + g, b[2] = kg * d[2] * d[2] + g;
  b[3] = kg * d[0] * d[1], b[4] = kg * d[0] * d[2], b[5] = kg * d[1] * d[2];
}

/* Traction's share at point p: v^T K v = sum_s (v_a - v_b)^T A_s (v_a - v_b) <= sum_s 2 (v_a^T A_s v_a
   + v_b^T A_s v_b) with A_s = k n n^T + g (I - n n^T) >= the segment's tangent, k the yarn tangent's
   largest value in the family's window over L0, g = max(T,0)/L (a compressed segment's negative
   geometric stiffness only lowers K); so the point's row is 2 lambda_max(sum of its segments' A_s). */
static void TractionBlock(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, int pull_dir, PetscReal B[6],
                          PetscReal *rp)
{
  for (int dir = 0; dir < 2; dir++) {
    const YarnLaw  *law = dir == 0 ? p->warp : p->weft;
    const PetscReal L0  = dir == 0 ? p->ax : p->ay;
    const PetscReal k   = p->win_k[dir];
    for (int side = -1; side <= 0; side++) {
      const Chord c = ChordAt(p, x, i + (dir == 0 ? side : 0), j + (dir == 1 ? side : 0), dir);
      if (!c.alive) continue;
      const PetscReal *d = c.d;
      const PetscReal  L = c.L, e = L / L0 - 1.0, T = ChordTension(law, e);
      if (L > 0) {
        PetscReal b[6];
        SegmentBlock(k, T, L, d, b);
        for (int q = 0; q < 6; q++) B[q] += b[q];
      } else /* a zero-length chord: the yarn stiffness in any direction */
        B[0] += k, B[1] += k, B[2] += k;
      if (dir == pull_dir) *rp += PullSpringRow(law, L0, e, T, L);
    }
  }
}

static void TractionBoundRow(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, int pull_dir, PetscReal *rs,
                             PetscReal *rp)
{
  PetscReal B[6] = {0, 0, 0, 0, 0, 0};

  TractionBlock(p, x, i, j, pull_dir, B, rp);
  *rs += 2.0 * SymMaxEig3(B);
}

/* The rigid bodies at a point: v^T K v <= v^T (k_contact I + sum_b k_b n_b n_b^T) v, so the
   frictionless bodies join the traction row's eigenvalue, lambda_max(2 B + sum_b k_b n_b n_b^T),
   and the rest add k_contact (ContactBound). Where the yarns run across the normal (along a
   sphere's surface) the bodies add little to the row; along it, their k. xp: the point. */
static PetscReal ContactPart(const Patch *p, const PetscReal xp[3], const PetscReal B[6], PetscReal tr)
{
  PetscReal C[6], ksum = 0.0, turn = 0.0;

  if (!p->ncb) return p->k_contact;
  for (int q = 0; q < 6; q++) C[q] = B[q];
  for (int q = 0; q < p->ncb; q++) {
    const ContactBound *b = &p->cb[q];
    const PetscReal     h = 0.5 * b->k; /* C is half the row's matrix, as B is */
    PetscReal           n[3] = {b->n[0], b->n[1], b->n[2]};
    ksum += b->k;
    if (b->sphere) {
      const PetscReal d[3] = {xp[0] - b->c[0], xp[1] - b->c[1], xp[2] - b->c[2]};
      const PetscReal r    = PetscSqrtReal(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      if (!(r > 0)) { /* at the centre: any direction */
        C[0] += h, C[1] += h, C[2] += h;
        continue;
      }
      for (int k = 0; k < 3; k++) n[k] = d[k] / r;
      turn += b->k * PetscMin(b->span / r, 1.0); /* the normal as the centre moves on (ContactBound) */
    }
    C[0] += h * n[0] * n[0], C[1] += h * n[1] * n[1], C[2] += h * n[2] * n[2];
    C[3] += h * n[0] * n[1], C[4] += h * n[0] * n[2], C[5] += h * n[1] * n[2];
  }
  return p->k_contact + PetscMin(PetscMax(2.0 * SymMaxEig3(C) - tr, 0.0) + turn, ksum);
}

PetscReal ContactBoundRow(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j)
{
  PetscReal B[6] = {0, 0, 0, 0, 0, 0}, rp = 0.0, tr = 0.0;

  if (p->traction) {
    TractionBlock(p, x, i, j, 0, B, &rp);
    tr = 2.0 * SymMaxEig3(B);
  }
  return ContactPart(p, x + 3 * ((j - p->gys) * p->gxm + (i - p->gxs)), B, tr);
}

/* chords a[i] -> b[i], a <= i < b, as ChordAt takes them and TractionBlock their strain: the chord
   (d), its length (L: -1 if a point is absent or the segment broken) and its strain L/L0 - 1 (e)
   (the same expressions: a change there is a change here) */
static void BoundChordRow(PetscReal L0, PetscInt a, PetscInt b, const PetscReal *restrict xa,
                          const PetscReal *restrict xb, const unsigned char *restrict ea,
                          const unsigned char *restrict eb, const unsigned char *restrict broken,
                          PetscReal *restrict dx, PetscReal *restrict dy, PetscReal *restrict dz,
                          PetscReal *restrict Lr, PetscReal *restrict e)
{
  for (PetscInt i = a; i < b; i++) {
    const PetscReal d0 = xb[3 * i] - xa[3 * i], d1 = xb[3 * i + 1] - xa[3 * i + 1], d2 = xb[3 * i + 2] - xa[3 * i + 2];
    const PetscReal L = PetscSqrtReal(PetscSqr(d0) + PetscSqr(d1) + PetscSqr(d2));
    dx[i] = d0, dy[i] = d1, dz[i] = d2;
    Lr[i] = (ea[i] != 0) & (eb[i] != 0) & (broken[i] == 0) ? L : -1.0;
    e[i]  = L / L0 - 1.0;
  }
}

/* SegmentBlock of the chords a <= i < b into the rows bq (any value where L <= 0: not read) */
static void BoundBlockRow(PetscReal k, PetscInt a, PetscInt b, const PetscReal *restrict T,
                          const PetscReal *restrict Lr, const PetscReal *restrict dx, const PetscReal *restrict dy,
                          const PetscReal *restrict dz, PetscReal *restrict b0, PetscReal *restrict b1,
                          PetscReal *restrict b2, PetscReal *restrict b3, PetscReal *restrict b4,
                          PetscReal *restrict b5)
{
  for (PetscInt i = a; i < b; i++) {
    const PetscReal L = Lr[i] > 0 ? Lr[i] : 1.0; /* a safe divisor where the block is not read */
    const PetscReal g = PetscMax(T[i], 0.0) / L, kg = (k - g) / (L * L);
    b0[i] = kg * dx[i] * dx[i] + g, b1[i] = kg * dy[i] * dy[i] + g, b2[i] = kg * dz[i] * dz[i] + g;
    b3[i] = kg * dx[i] * dy[i], b4[i] = kg * dx[i] * dz[i], b5[i] = kg * dy[i] * dz[i];
  }
}

/* The bound's view of the segments from (gxs + li, j) along dir, li in [c0, c1) (-2 <= c0,
   c1 <= gxm + 2): their length (-1 if absent or broken) and, with traction, their share of each
   end's block as TractionBoundRow adds it (blocks, L > 0) and of the pull-direction row (dir ==
   pull_dir) */
static void BoundSegmentRow(const Patch *p, const PetscReal *x, PetscInt j, int dir, int pull_dir, int blocks,
                            PetscInt c0, PetscInt c1, BoundSegRow *s)
{
  const YarnLaw  *law = dir == 0 ? p->warp : p->weft;
  const PetscReal L0  = dir == 0 ? p->ax : p->ay;
  const PetscInt  n = p->gxm, lj = j - p->gys, lk = lj + (dir == 1);
  /* the segments whose two ends are in the ghosted patch; the others have an absent end */
  const PetscInt a = PetscMax(c0, 0), b = PetscMin(c1, n - (dir == 0));
  PetscReal *e = p->bound_row[0], *T = p->bound_row[1], *dx = p->bound_row[2], *dy = p->bound_row[3],
            *dz = p->bound_row[4];

  for (PetscInt li = c0; li < c1; li++) s->L[li] = -1.0;
  if (lj < 0 || lk >= p->gym || a >= b) return;
  const unsigned char *ea = p->exists + lj * n, *eb = p->exists + lk * n + (dir == 0);
  const unsigned char *broken = (dir == 0 ? p->broken_x : p->broken_y) + lj * n;
  BoundChordRow(L0, a, b, x + 3 * lj * n, x + 3 * (lk * n + (dir == 0)), ea, eb, broken, dx, dy, dz, s->L, e);
  if (!p->traction) return;
  ChordTensionRow(law, a, b, e, ea, eb, broken, T);
  if (blocks)
    BoundBlockRow(p->win_k[dir], a, b, T, s->L, dx, dy, dz, s->b[0], s->b[1], s->b[2], s->b[3], s->b[4], s->b[5]);
  if (dir == pull_dir)
    for (PetscInt li = a; li < b; li++)
      if (!(s->L[li] < 0)) s->pull[li] = PullSpringRow(law, L0, e[li], T[li], s->L[li]);
}

/* adds segment li of row s to the block B (and its pull share to *rp) as TractionBoundRow does */
static inline void BoundSegmentAdd(const BoundSegRow *s, PetscInt li, PetscReal k, int pull, PetscReal B[6],
                                   PetscReal *rp)
{
  const PetscReal L = s->L[li];
  if (L < 0) return;
  if (L > 0)
    for (int q = 0; q < 6; q++) B[q] += s->b[q][li];
  else
    B[0] += k, B[1] += k, B[2] += k;
  if (pull) *rp += s->pull[li];
}

FABRIC_WIDE PetscReal PullOmega2(Patch *p, const PetscReal *x, const PetscReal *inv_m, int pull_dir)
{
  const PetscInt c0 = p->xs - p->gxs, c1 = c0 + p->xm;
  PetscReal      pull2 = 0.0;

  if (!p->traction) return 0.0;
  if (pull_dir == 1) BoundSegmentRow(p, x, p->ys - 1, 1, 1, 0, c0, c1, &p->by_seg[SLOT(p->ys - 1)]);
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++) {
    const BoundSegRow *a = pull_dir == 0 ? &p->bx_seg : &p->by_seg[SLOT(j - 1)];
    const BoundSegRow *b = pull_dir == 0 ? &p->bx_seg : &p->by_seg[SLOT(j)];
    if (pull_dir == 0) BoundSegmentRow(p, x, j, 0, 0, 0, c0 - 1, c1, &p->bx_seg);
    else BoundSegmentRow(p, x, j, 1, 1, 0, c0, c1, &p->by_seg[SLOT(j)]);
    for (PetscInt li = c0; li < c1; li++) {
      const PetscReal im = inv_m[(j - p->ys) * p->xm + (li - c0)];
      const PetscInt  la = pull_dir == 0 ? li - 1 : li;
      PetscReal       rp = 0.0;
      if (im <= 0.0) continue;
      if (!(a->L[la] < 0)) rp += a->pull[la]; /* as BoundSegmentAdd: only an absent or broken one is left out */
      if (!(b->L[li] < 0)) rp += b->pull[li];
      pull2 = PetscMax(pull2, rp * im);
    }
  }
  return pull2;
}

/* The chord strains e[i] of the segments a[i] -> b[i], i < n, and over the live ones (both ends
   exist, not broken): the largest ratio to the breaking strain eb[i] (as the bits of a value >= 0,
   ordered as the value: 0 if none is above 0, a NaN skipped, as PetscMax skips it) and whether one
   is past its breaking strain or NaN (*past). Each strain is BreakSegments' own expression; in one
   pass of selects and integer maxima, so that it vectorises. */
FABRIC_WIDE static int64_t BreakRatioRow(PetscInt n, PetscReal L0, const PetscReal *restrict a,
                                         const PetscReal *restrict b, const unsigned char *restrict ea,
                                         const unsigned char *restrict eb_, const unsigned char *restrict broken,
                                         const PetscReal *restrict eb, PetscReal *restrict e, int *past)
{
  int64_t top = 0;
  int     any = 0;

  for (PetscInt i = 0; i < n; i++) {
    const PetscReal dx = b[3 * i] - a[3 * i], dy = b[3 * i + 1] - a[3 * i + 1], dz = b[3 * i + 2] - a[3 * i + 2];
    const PetscReal ei = PetscSqrtReal(dx * dx + dy * dy + dz * dz) / L0 - 1.0, r = ei / eb[i];
    const int       live = (ea[i] != 0) & (eb_[i] != 0) & (broken[i] == 0);
    const PetscReal q    = live & (r > 0) ? r : 0.0;
    const int64_t   bq   = AbsBits(q);
    top                  = bq > top ? bq : top;
    any |= live & !(ei <= eb[i]);
    e[i] = ei;
  }
  *past = any;
  return top;
}

/* Break every segment of the patch whose yarn strain exceeds its breaking strain
   (MODEL.md 5.1). Called on a balanced state, or within a tear after every te step: each row's
   strains and largest ratio in a pass that vectorises (BreakRatioRow), the rows with a segment
   past its breaking strain then segment by segment. apply 0: the largest ratio only, nothing breaks. */
PetscInt BreakSegments(Patch *p, const PetscReal *x, int apply, BreakSite *site, PetscReal *load)
{
  PetscReal *e = p->break_row, *ebc = p->break_row + p->gxm; /* the strains; a family's constant breaking strain */
  PetscInt   n = 0;
  int64_t    top = 0; /* the largest ratio's bits */

  site->ratio = 0;
  site->dir = site->i = site->j = 0;
  for (int dir = 0; dir < 2; dir++) {
    const YarnLaw   *law    = dir == 0 ? p->warp : p->weft;
    const PetscReal  L0     = dir == 0 ? p->ax : p->ay;
    unsigned char   *broken = dir == 0 ? p->broken_x : p->broken_y;
    const PetscReal *eb     = dir == 0 ? p->break_x : p->break_y;
    const PetscInt   step = dir == 0 ? 1 : p->gxm, len = p->gxm - (dir == 0);
    if (!isfinite(law->break_e)) continue;
    if (!eb)
      for (PetscInt li = 0; li < len; li++) ebc[li] = law->break_e;
    for (PetscInt lj = 0; lj + (dir == 1) < p->gym; lj++) {
      const PetscInt   k0  = lj * p->gxm;
      const PetscReal *ebr = eb ? eb + k0 : ebc; /* the row's breaking strains */
      int              past;
      const int64_t    t = BreakRatioRow(len, L0, x + 3 * k0, x + 3 * (k0 + step), p->exists + k0,
                                        p->exists + k0 + step, broken + k0, ebr, e, &past);
      top                = t > top ? t : top;
      if (!past || !apply) continue;
      for (PetscInt li = 0; li < len; li++) {
        const PetscInt k = k0 + li;
        if (broken[k] || !p->exists[k] || !p->exists[k + step] || e[li] <= ebr[li]) continue;
        broken[k] = 1;
        {
          const PetscInt i = p->gxs + li, j = p->gys + lj;
          if (i < p->xs || i >= p->xs + p->xm || j < p->ys || j >= p->ys + p->ym) continue; /* not owned */
          n++;
          if (e[li] / ebr[li] > site->ratio) site->ratio = e[li] / ebr[li], site->dir = dir, site->i = i, site->j = j;
        }
      }
    }
  }
  memcpy(load, &top, sizeof top);
  return n;
}

/* ============ the angle between two tangents: bending and shear (MODEL.md 5, 14) ============ */

/* s = a.b/(|a||b|) and its derivatives: ga = ds/da = (b^ - s a^)/|a|, gb = (a^ - s b^)/|b|,
   Haa = -(a^ ga^T + ga a^T)/|a| - s (I - a^ a^T)/|a|^2, Hab = ((I - b^ b^T)/|b| - a^ gb^T)/|a|,
   Hbb as Haa with a and b swapped (a^ = a/|a|) */
typedef struct {
  PetscReal s, ga[3], gb[3], Haa[9], Hab[9], Hbb[9];
} Cosine;

static void CosineDerivatives(const PetscReal a[3], const PetscReal b[3], int hessian, Cosine *c)
{
  const PetscReal A = PetscSqrtReal(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  const PetscReal B = PetscSqrtReal(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
  PetscReal       ua[3], ub[3];

  for (int q = 0; q < 3; q++) ua[q] = a[q] / A, ub[q] = b[q] / B;
  c->s = ua[0] * ub[0] + ua[1] * ub[1] + ua[2] * ub[2];
  for (int q = 0; q < 3; q++) c->ga[q] = (ub[q] - c->s * ua[q]) / A, c->gb[q] = (ua[q] - c->s * ub[q]) / B;
  if (!hessian) return;
  for (int r = 0; r < 3; r++)
    for (int q = 0; q < 3; q++) {
      const PetscReal id = r == q ? 1.0 : 0.0;
      c->Haa[3 * r + q]  = -(ua[r] * c->ga[q] + c->ga[r] * ua[q]) / A - c->s * (id - ua[r] * ua[q]) / (A * A);
      c->Hbb[3 * r + q]  = -(ub[r] * c->gb[q] + c->gb[r] * ub[q]) / B - c->s * (id - ub[r] * ub[q]) / (B * B);
      c->Hab[3 * r + q]  = ((id - ub[r] * ub[q]) / B - ua[r] * c->gb[q]) / A;
    }
}

void SymPositivePart(PetscInt n, PetscReal *A)
{
  PetscReal V[36], scale = 0;

  for (PetscInt r = 0; r < n; r++)
    for (PetscInt q = 0; q < n; q++) V[n * r + q] = r == q ? 1.0 : 0.0, scale += A[n * r + q] * A[n * r + q];
  for (int sweep = 0; sweep < 30; sweep++) {
    PetscReal off = 0;
    for (PetscInt r = 0; r < n; r++)
      for (PetscInt q = r + 1; q < n; q++) off += A[n * r + q] * A[n * r + q];
    if (!(off > 1e-32 * scale)) break;
    for (PetscInt a = 0; a < n; a++)
      for (PetscInt b = a + 1; b < n; b++) { /* the rotation that zeroes A[a][b] */
        const PetscReal apq = A[n * a + b];
        if (apq == 0) continue;
        const PetscReal th = (A[n * b + b] - A[n * a + a]) / (2.0 * apq);
        const PetscReal t  = (th >= 0 ? 1.0 : -1.0) / (PetscAbsReal(th) + PetscSqrtReal(th * th + 1.0));
        const PetscReal cs = 1.0 / PetscSqrtReal(t * t + 1.0), sn = t * cs;
        for (PetscInt k = 0; k < n; k++) { /* columns a and b */
          const PetscReal ka = A[n * k + a], kb = A[n * k + b];
          A[n * k + a] = cs * ka - sn * kb, A[n * k + b] = sn * ka + cs * kb;
        }
        for (PetscInt k = 0; k < n; k++) { /* rows a and b */
          const PetscReal ak = A[n * a + k], bk = A[n * b + k];
          A[n * a + k] = cs * ak - sn * bk, A[n * b + k] = sn * ak + cs * bk;
        }
        for (PetscInt k = 0; k < n; k++) {
          const PetscReal va = V[n * k + a], vb = V[n * k + b];
          V[n * k + a] = cs * va - sn * vb, V[n * k + b] = sn * va + cs * vb;
        }
      }
  }
  {
    PetscReal lam[6];
    for (PetscInt k = 0; k < n; k++) lam[k] = PetscMax(A[n * k + k], 0.0);
    for (PetscInt r = 0; r < n; r++)
      for (PetscInt q = r; q < n; q++) {
        PetscReal v = 0;
        for (PetscInt k = 0; k < n; k++) v += V[n * r + k] * lam[k] * V[n * q + k];
        A[n * r + q] = A[n * q + r] = v;
      }
  }
}

/* Gradient and Hessian of E = phi(s) over n points, with the tangents a = sum_q ca[q] x_q and
   b = sum_q cb[q] x_q; dphi = phi'(s), d2phi = phi''(s) (chain rule). */
static void CosineTermDerivatives(const Cosine *c, PetscReal dphi, PetscReal d2phi, PetscInt n, const PetscReal ca[],
                                  const PetscReal cb[], int want, TermInstance *t)
{
  const PetscInt ld = 3 * n;
  PetscReal      Maa[9], Mab[9], Mbb[9];

  if (want & TERM_GRADIENT)
    for (PetscInt q = 0; q < n; q++)
      for (int d = 0; d < 3; d++) t->g[3 * q + d] = dphi * (ca[q] * c->ga[d] + cb[q] * c->gb[d]);
  if (!(want & TERM_HESSIAN)) return;
  for (int r = 0; r < 3; r++) /* second derivatives of E in the tangents */
    for (int q = 0; q < 3; q++) {
      Maa[3 * r + q] = d2phi * c->ga[r] * c->ga[q] + dphi * c->Haa[3 * r + q];
      Mab[3 * r + q] = d2phi * c->ga[r] * c->gb[q] + dphi * c->Hab[3 * r + q];
      Mbb[3 * r + q] = d2phi * c->gb[r] * c->gb[q] + dphi * c->Hbb[3 * r + q];
    }
  if (want & TERM_CONVEX) { /* the positive part of [Maa Mab; Mab^T Mbb] */
    PetscReal M[36];
    for (int r = 0; r < 3; r++)
      for (int q = 0; q < 3; q++) {
        M[6 * r + q]           = Maa[3 * r + q];
        M[6 * r + 3 + q]       = Mab[3 * r + q];
        M[6 * (3 + r) + q]     = Mab[3 * q + r];
        M[6 * (3 + r) + 3 + q] = Mbb[3 * r + q];
      }
    SymPositivePart(6, M);
    for (int r = 0; r < 3; r++)
      for (int q = 0; q < 3; q++) {
        Maa[3 * r + q] = M[6 * r + q];
        Mab[3 * r + q] = M[6 * r + 3 + q];
        Mbb[3 * r + q] = M[6 * (3 + r) + 3 + q];
      }
  }
  for (PetscInt P = 0; P < n; P++)
    for (PetscInt Q = 0; Q < n; Q++)
      for (int r = 0; r < 3; r++)
        for (int q = 0; q < 3; q++)
          t->K[(3 * P + r) * ld + 3 * Q + q] = ca[P] * ca[Q] * Maa[3 * r + q] + ca[P] * cb[Q] * Mab[3 * r + q] +
                                               cb[P] * ca[Q] * Mab[3 * q + r] + cb[P] * cb[Q] * Mbb[3 * r + q];
}

/* ======================= bending (MODEL.md 5.2, 7.3, 14) ======================= */

/* Bending centres c0 <= i < c1 with incoming chord s1[i] and outgoing chord s2[i] (MODEL.md 5.2),
   into g1 and g2 (every array a parameter of its own, restrict: the loop vectorises). */
static void BendRowKernel(PetscReal kb, PetscInt c0, PetscInt c1, const PetscReal *restrict u1x,
                          const PetscReal *restrict u1y, const PetscReal *restrict u1z, const PetscReal *restrict i1,
                          const PetscReal *restrict u2x, const PetscReal *restrict u2y, const PetscReal *restrict u2z,
                          const PetscReal *restrict i2, PetscReal *restrict g1x, PetscReal *restrict g1y,
                          PetscReal *restrict g1z, PetscReal *restrict g2x, PetscReal *restrict g2y,
                          PetscReal *restrict g2z)
{
  /* u2 - s u1 = (u1 x u2) x u1 and u1 - s u2 = u2 x (u1 x u2): the cross-product form has no
     cancellation for nearly straight yarns and is exactly zero for parallel chords */
  for (PetscInt i = c0; i < c1; i++) {
    const PetscReal cx = u1y[i] * u2z[i] - u1z[i] * u2y[i], cy = u1z[i] * u2x[i] - u1x[i] * u2z[i];
    const PetscReal cz = u1x[i] * u2y[i] - u1y[i] * u2x[i];
    const PetscReal c1 = kb * i1[i], c2 = kb * i2[i];
    g1x[i]             = c1 * (cy * u1z[i] - cz * u1y[i]);
    g1y[i]             = c1 * (cz * u1x[i] - cx * u1z[i]);
    g1z[i]             = c1 * (cx * u1y[i] - cy * u1x[i]);
    g2x[i]             = c2 * (u2y[i] * cz - u2z[i] * cy);
    g2y[i]             = c2 * (u2z[i] * cx - u2x[i] * cz);
    g2z[i]             = c2 * (u2x[i] * cy - u2y[i] * cx);
  }
}

/* the same into row b, centre i stored at i + off */
static void ComputeBendRow(PetscReal kb, PetscInt c0, PetscInt c1, const PetscReal *u1x, const PetscReal *u1y,
                           const PetscReal *u1z, const PetscReal *i1, const PetscReal *u2x, const PetscReal *u2y,
                           const PetscReal *u2z, const PetscReal *i2, BendRow *b, PetscInt off)
{
  BendRowKernel(kb, c0, c1, u1x, u1y, u1z, i1, u2x, u2y, u2z, i2, b->g1x + off, b->g1y + off, b->g1z + off,
                b->g2x + off, b->g2y + off, b->g2z + off);
}

/* bending on the points i0 <= i < i1 of row j, added: x-centres i-1, i, i+1 of the row (bx)
   and y-centres of rows j-1 (bd), j (bc), j+1 (bu) */
static void GatherBending(const BendRow *bx, const BendRow *bd, const BendRow *bc, const BendRow *bu, PetscInt i0,
                          PetscInt i1, PetscReal *restrict fr)
{
  for (PetscInt i = i0; i < i1; i++) {
    fr[3 * i] +=
        bx->g2x[i - 1] + bx->g1x[i] - bx->g2x[i] - bx->g1x[i + 1] + bd->g2x[i] + bc->g1x[i] - bc->g2x[i] - bu->g1x[i];
    fr[3 * i + 1] +=
        bx->g2y[i - 1] + bx->g1y[i] - bx->g2y[i] - bx->g1y[i + 1] + bd->g2y[i] + bc->g1y[i] - bc->g2y[i] - bu->g1y[i];
    fr[3 * i + 2] +=
        bx->g2z[i - 1] + bx->g1z[i] - bx->g2z[i] - bx->g1z[i + 1] + bd->g2z[i] + bc->g1z[i] - bc->g2z[i] - bu->g1z[i];
  }
}

/* --- instance: centre (i,j) of the yarn along x (dir 0) or y (dir 1): E = kb (1 - s) --- */
static int BendingInstance(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, int dir, int want,
                           TermInstance *t)
{
  static const PetscReal ca[3] = {-1.0, 1.0, 0.0}, cb[3] = {0.0, -1.0, 1.0}; /* e1 = x1 - x0, e2 = x2 - x1 */
  const PetscInt         di = dir == 0, dj = dir == 1;
  const PetscReal        kb = dir == 0 ? p->kbx : p->kby;
  PetscReal              e1[3], e2[3];
  Cosine                 c;

  if (!SegmentAlive(p, i - di, j - dj, dir) || !SegmentAlive(p, i, j, dir)) return 0;
  for (int q = 0; q < 3; q++) {
    t->i[q] = i + (q - 1) * di;
    t->j[q] = j + (q - 1) * dj;
  }
  t->n = 3;
  {
    const PetscReal *x0 = Pos(p, x, t->i[0], t->j[0]), *x1 = Pos(p, x, i, j), *x2 = Pos(p, x, t->i[2], t->j[2]);
    for (int q = 0; q < 3; q++) e1[q] = x1[q] - x0[q], e2[q] = x2[q] - x1[q];
  }
  CosineDerivatives(e1, e2, want & TERM_HESSIAN, &c);
  if (want & TERM_ENERGY) t->E = kb * (1.0 - c.s);
  CosineTermDerivatives(&c, -kb, 0.0, 3, ca, cb, want, t);
  return 1;
}

/* --- stable-step bound: centre c in {p-1, p, p+1}; row sums 12, 24, 12 times kb / Lmin^2, with
   Lmin no longer than the contact length (a chord can be squeezed that far in a step) --- */
/* adds the rows of the bending centres k = -1, 0, 1 around a point along one yarn, from the lengths
   L[q] of its chords from point q - 2 to q - 1 (-1: absent or broken) */
static inline void BendingBoundAdd(PetscReal kb, PetscReal Lc, const PetscReal L[4], PetscReal *rs)
{
  for (int k = -1; k <= 1; k++) { /* the bending centre at k: chords k-1 and k */
    const PetscReal L1 = L[k + 1], L2 = L[k + 2];
    if (L1 < 0 || L2 < 0) continue;
    const PetscReal Lmin = PetscMin(PetscMin(L1, L2), Lc);
    if (!(Lmin > 0)) continue; /* a zero-length chord has no direction: no bending force */
    *rs += kb * (k == 0 ? 24.0 : 12.0) / (Lmin * Lmin);
  }
}

static void BendingBoundRow(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, int pull_dir, PetscReal *rs,
                            PetscReal *rp)
{
  for (int dir = 0; dir < 2; dir++) {
    const PetscReal Lc = (1.0 + (dir == 0 ? p->warp : p->weft)->e_contact) * (dir == 0 ? p->ax : p->ay);
    PetscReal       L[4]; /* the chords from point q to q + 1 along dir, q = -2..1 from (i,j) */
    for (int q = -2; q <= 1; q++) {
      const Chord c = ChordAt(p, x, i + (dir == 0 ? q : 0), j + (dir == 1 ? q : 0), dir);
      L[q + 2]      = c.alive ? c.L : -1.0;
    }
    BendingBoundAdd(dir == 0 ? p->kbx : p->kby, Lc, L, rs);
  }
}

/* ===================== shear and jamming (MODEL.md 5.3, 7.3, 14) ===================== */

/* Shear crossings li in [c0, c1) of local row lr (inside the patch), point by point: the
   columns at the patch's edges, where a neighbour's position may lie outside the row
   (MODEL.md 5.3). xr, xd, xu: the row and the rows below and above (zero rows outside). */
static void ShearRowEdge(const Patch *p, PetscInt lr, PetscInt c0, PetscInt c1, const PetscReal *xr,
                         const PetscReal *xd, const PetscReal *xu, ShearRow *sh)
{
  const PetscReal Ks = p->Ks, Kj = p->Kj, sl = p->s_lock;

  for (PetscInt li = c0; li < c1; li++) {
    const int        self = Exists(p, li, lr), hl = Exists(p, li - 1, lr), hr = Exists(p, li + 1, lr);
    const int        hd = Exists(p, li, lr - 1), hu = Exists(p, li, lr + 1);
    const PetscInt   il = hl ? li - 1 : li, ir = hr ? li + 1 : li;
    const PetscReal *xp = xr + 3 * ir, *xm = xr + 3 * il;
    const PetscReal *yp = hu ? xu + 3 * li : xr + 3 * li, *ym = hd ? xd + 3 * li : xr + 3 * li;
    const PetscReal  twx = xp[0] - xm[0], twy = xp[1] - xm[1], twz = xp[2] - xm[2];
    const PetscReal  tfx = yp[0] - ym[0], tfy = yp[1] - ym[1], tfz = yp[2] - ym[2];
    const int        active = self && (hl || hr) && (hd || hu);
    const PetscReal  nw2 = twx * twx + twy * twy + twz * twz, nf2 = tfx * tfx + tfy * tfy + tfz * tfz;
    /* a yarn folded back on itself (a tangent of zero length) has no shear angle: no shear force */
    const PetscReal iw  = (active && nw2 > 0 && nf2 > 0) ? 1.0 / PetscSqrtReal(nw2) : 0.0;
    const PetscReal jf  = (active && nw2 > 0 && nf2 > 0) ? 1.0 / PetscSqrtReal(nf2) : 0.0;
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
    sh->as[li]  = as;
  }
}

/* The same on interior columns (1 <= c0, c1 <= gxm - 1: both neighbours' positions lie in the
   row), in a form that vectorises: every position is loaded, and an absent neighbour's is
   replaced by the crossing's own by a select, as ShearRowEdge points at it; each value is the
   expression ShearRowEdge computes. er, ed, eu: existence of the row and of the rows below and
   above, padded (er[-1] and er[gxm] exist as array elements). */
static void ShearRowKernel(PetscReal Ks, PetscReal Kj, PetscReal sl, PetscInt c0, PetscInt c1,
                           const PetscReal *restrict xr, const PetscReal *restrict xd, const PetscReal *restrict xu,
                           const unsigned char *restrict er, const unsigned char *restrict ed,
                           const unsigned char *restrict eu, PetscReal *restrict hwx_, PetscReal *restrict hwy_,
                           PetscReal *restrict hwz_, PetscReal *restrict hfx_, PetscReal *restrict hfy_,
                           PetscReal *restrict hfz_, PetscReal *restrict sx_, PetscReal *restrict sy_,
                           PetscReal *restrict sz_, PetscReal *restrict as_)
{
  for (PetscInt li = c0; li < c1; li++) {
    const int       self = er[li] != 0, hl = er[li - 1] != 0, hr = er[li + 1] != 0, hd = ed[li] != 0, hu = eu[li] != 0;
    const PetscReal cx = xr[3 * li], cy = xr[3 * li + 1], cz = xr[3 * li + 2];
    const PetscReal lx = xr[3 * li - 3], ly = xr[3 * li - 2], lz = xr[3 * li - 1];
    const PetscReal rx = xr[3 * li + 3], ry = xr[3 * li + 4], rz = xr[3 * li + 5];
    const PetscReal dx = xd[3 * li], dy = xd[3 * li + 1], dz = xd[3 * li + 2];
    const PetscReal ux = xu[3 * li], uy = xu[3 * li + 1], uz = xu[3 * li + 2];
    const PetscReal twx = (hr ? rx : cx) - (hl ? lx : cx), twy = (hr ? ry : cy) - (hl ? ly : cy);
    const PetscReal twz = (hr ? rz : cz) - (hl ? lz : cz);
    const PetscReal tfx = (hu ? ux : cx) - (hd ? dx : cx), tfy = (hu ? uy : cy) - (hd ? dy : cy);
    const PetscReal tfz = (hu ? uz : cz) - (hd ? dz : cz);
    const PetscReal nw2 = twx * twx + twy * twy + twz * twz, nf2 = tfx * tfx + tfy * tfy + tfz * tfz;
    /* a yarn folded back on itself (a tangent of zero length) has no shear angle: no shear force */
    const int       ok  = self & (hl | hr) & (hd | hu) & (nw2 > 0) & (nf2 > 0);
    const PetscReal qw = 1.0 / PetscSqrtReal(nw2 > 0 ? nw2 : 1.0), qf = 1.0 / PetscSqrtReal(nf2 > 0 ? nf2 : 1.0);
    const PetscReal iw = ok ? qw : 0.0, jf = ok ? qf : 0.0;
    const PetscReal uwx = twx * iw, uwy = twy * iw, uwz = twz * iw, ufx = tfx * jf, ufy = tfy * jf, ufz = tfz * jf;
    const PetscReal s = uwx * ufx + uwy * ufy + uwz * ufz, as = PetscAbsReal(s);
    const PetscReal jam = as > sl ? (s > 0 ? as - sl : sl - as) : 0.0;
    const PetscReal Ep  = Ks * s + Kj * jam;
    const PetscReal cw = Ep * iw, cf = Ep * jf;
    const PetscReal hwx = cw * (ufx - s * uwx), hwy = cw * (ufy - s * uwy), hwz = cw * (ufz - s * uwz);
    const PetscReal hfx = cf * (uwx - s * ufx), hfy = cf * (uwy - s * ufy), hfz = cf * (uwz - s * ufz);
    const PetscReal aw = (PetscReal) (hr - hl), af = (PetscReal) (hu - hd);
    hwx_[li] = hwx;
    hwy_[li] = hwy;
    hwz_[li] = hwz;
    hfx_[li] = hfx;
    hfy_[li] = hfy;
    hfz_[li] = hfz;
    sx_[li]  = aw * hwx + af * hfx;
    sy_[li]  = aw * hwy + af * hfy;
    sz_[li]  = aw * hwz + af * hfz;
    as_[li]  = as;
  }
}

/* ShearRowKernel where the crossings and all four neighbours exist (the inside of a rectangle):
   every select takes the neighbour, the one-sided weights hr - hl and hu - hd are 0 */
static void ShearRowFull(PetscReal Ks, PetscReal Kj, PetscReal sl, PetscInt c0, PetscInt c1,
                         const PetscReal *restrict xr, const PetscReal *restrict xd, const PetscReal *restrict xu,
                         PetscReal *restrict hwx_, PetscReal *restrict hwy_, PetscReal *restrict hwz_,
                         PetscReal *restrict hfx_, PetscReal *restrict hfy_, PetscReal *restrict hfz_,
                         PetscReal *restrict sx_, PetscReal *restrict sy_, PetscReal *restrict sz_,
                         PetscReal *restrict as_)
{
  for (PetscInt li = c0; li < c1; li++) {
    const PetscReal twx = xr[3 * li + 3] - xr[3 * li - 3], twy = xr[3 * li + 4] - xr[3 * li - 2];
    const PetscReal twz = xr[3 * li + 5] - xr[3 * li - 1];
    const PetscReal tfx = xu[3 * li] - xd[3 * li], tfy = xu[3 * li + 1] - xd[3 * li + 1];
    const PetscReal tfz = xu[3 * li + 2] - xd[3 * li + 2];
    const PetscReal nw2 = twx * twx + twy * twy + twz * twz, nf2 = tfx * tfx + tfy * tfy + tfz * tfz;
    const int       ok  = (nw2 > 0) & (nf2 > 0);
    const PetscReal qw = 1.0 / PetscSqrtReal(nw2 > 0 ? nw2 : 1.0), qf = 1.0 / PetscSqrtReal(nf2 > 0 ? nf2 : 1.0);
    const PetscReal iw = ok ? qw : 0.0, jf = ok ? qf : 0.0;
    const PetscReal uwx = twx * iw, uwy = twy * iw, uwz = twz * iw, ufx = tfx * jf, ufy = tfy * jf, ufz = tfz * jf;
    const PetscReal s = uwx * ufx + uwy * ufy + uwz * ufz, as = PetscAbsReal(s);
    const PetscReal jam = as > sl ? (s > 0 ? as - sl : sl - as) : 0.0;
    const PetscReal Ep  = Ks * s + Kj * jam;
    const PetscReal cw = Ep * iw, cf = Ep * jf;
    const PetscReal hwx = cw * (ufx - s * uwx), hwy = cw * (ufy - s * uwy), hwz = cw * (ufz - s * uwz);
    const PetscReal hfx = cf * (uwx - s * ufx), hfy = cf * (uwy - s * ufy), hfz = cf * (uwz - s * ufz);
    hwx_[li] = hwx;
    hwy_[li] = hwy;
    hwz_[li] = hwz;
    hfx_[li] = hfx;
    hfy_[li] = hfy;
    hfz_[li] = hfz;
    sx_[li]  = 0.0 * hwx + 0.0 * hfx; /* aw hw + af hf with aw = af = 0, signed zeros included */
    sy_[li]  = 0.0 * hwy + 0.0 * hfy;
    sz_[li]  = 0.0 * hwz + 0.0 * hfz;
    as_[li]  = as;
  }
}

/* the n bytes from e on are all non-zero */
static inline int AllExist(const unsigned char *e, PetscInt n)
{
  return n <= 0 || !memchr(e, 0, (size_t) n);
}

/* Shear crossings of row r (global), local columns [c0, c1) (MODEL.md 5.3): the edge columns
   point by point, the others by the vector kernel. */
static void ComputeShearRow(Patch *p, const PetscReal *x, PetscInt r, PetscInt c0, PetscInt c1, ShearRow *sh)
{
  const PetscInt   n = p->gxm, lr = r - p->gys, a = PetscMax(c0, 1), b = PetscMin(c1, n - 1);
  const PetscReal *xr = (lr >= 0 && lr < p->gym) ? x + 3 * lr * n : p->zero_row;
  const PetscReal *xd = (lr - 1 >= 0 && lr - 1 < p->gym) ? x + 3 * (lr - 1) * n : p->zero_row;
  const PetscReal *xu = (lr + 1 >= 0 && lr + 1 < p->gym) ? x + 3 * (lr + 1) * n : p->zero_row;
  const unsigned char *er = p->epad + (lr + 1) * (n + 2) + 1;

  if (lr < 0 || lr >= p->gym) { /* no crossing outside the patch */
    PetscReal *z[] = {sh->hwx, sh->hwy, sh->hwz, sh->hfx, sh->hfy, sh->hfz, sh->sx, sh->sy, sh->sz, sh->as};
    for (int k = 0; k < 10; k++) memset(z[k] + c0, 0, sizeof(PetscReal) * (size_t) (c1 - c0));
    return;
  }
  if (a >= b)
    ShearRowEdge(p, lr, c0, c1, xr, xd, xu, sh);
  else {
    ShearRowEdge(p, lr, c0, a, xr, xd, xu, sh);
    if (AllExist(er + a - 1, b - a + 2) && AllExist(er - (n + 2) + a, b - a) && AllExist(er + (n + 2) + a, b - a))
      ShearRowFull(p->Ks, p->Kj, p->s_lock, a, b, xr, xd, xu, sh->hwx, sh->hwy, sh->hwz, sh->hfx, sh->hfy, sh->hfz,
                   sh->sx, sh->sy, sh->sz, sh->as);
    else
      ShearRowKernel(p->Ks, p->Kj, p->s_lock, a, b, xr, xd, xu, er, er - (n + 2), er + (n + 2), sh->hwx, sh->hwy,
                     sh->hwz, sh->hfx, sh->hfy, sh->hfz, sh->sx, sh->sy, sh->sz, sh->as);
    ShearRowEdge(p, lr, b, c1, xr, xd, xu, sh);
  }
  if (r >= p->chk[2] - 1 && r <= p->chk[3]) { /* checked: the crossings within 1 of a box point */
    const PetscInt k0 = PetscMax(c0, p->chk[0] - 1), k1 = PetscMin(c1, p->chk[1] + 1);
    int            out = 0;
    for (PetscInt li = k0; li < k1; li++) out |= sh->as[li] > p->win_s;
    p->left_window |= out;
  }
}

/* shear on the points i0 <= i < i1 of row j, added: crossings i-1, i+1 of the row (sc), below
   (sd) and above (su), and the point's own crossing where it is a tangent's end (one-sided) */
static void GatherShear(const ShearRow *sd, const ShearRow *sc, const ShearRow *su, PetscInt i0, PetscInt i1,
                        PetscReal *restrict fr)
{
  for (PetscInt i = i0; i < i1; i++) {
    fr[3 * i] += sc->hwx[i + 1] - sc->hwx[i - 1] + su->hfx[i] - sd->hfx[i] + sc->sx[i];
    fr[3 * i + 1] += sc->hwy[i + 1] - sc->hwy[i - 1] + su->hfy[i] - sd->hfy[i] + sc->sy[i];
    fr[3 * i + 2] += sc->hwz[i + 1] - sc->hwz[i - 1] + su->hfz[i] - sd->hfz[i] + sc->sz[i];
  }
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
  const PetscReal nw = PetscSqrtReal(tw[0] * tw[0] + tw[1] * tw[1] + tw[2] * tw[2]);
  const PetscReal nf = PetscSqrtReal(tf[0] * tf[0] + tf[1] * tf[1] + tf[2] * tf[2]);
  if (!(nw > 0 && nf > 0)) return 0;
  *s    = PetscMax(-1.0, PetscMin(1.0, (tw[0] * tf[0] + tw[1] * tf[1] + tw[2] * tf[2]) / (nw * nf)));
  *tmin = PetscMin(nw, nf);
  return 1;
}

/* --- instance: crossing (i,j), E = Ks s^2/2 + Kj max(0,|s|-s_lock)^2/2; points: the crossing,
   then its neighbours left, right, below, above that exist (tw = x(right) - x(left), the
   crossing itself standing for an absent end; likewise tf) --- */
static int ShearInstance(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, int k, int want, TermInstance *t)
{
  PetscReal ca[TERM_MAX_POINTS], cb[TERM_MAX_POINTS], a[3] = {0, 0, 0}, b[3] = {0, 0, 0};
  Cosine    c;

  if (!ExistsG(p, i, j)) return 0;
  const int has[4] = {ExistsG(p, i - 1, j), ExistsG(p, i + 1, j), ExistsG(p, i, j - 1), ExistsG(p, i, j + 1)};
  if (!(has[0] || has[1]) || !(has[2] || has[3])) return 0;
  const PetscInt  di[4] = {-1, 1, 0, 0}, dj[4] = {0, 0, -1, 1};
  const PetscReal wa[4] = {-1, 1, 0, 0}, wb[4] = {0, 0, -1, 1};
  t->n    = 1;
  t->i[0] = i, t->j[0] = j;
  ca[0] = (PetscReal) (has[0] - has[1]), cb[0] = (PetscReal) (has[2] - has[3]);
  for (int q = 0; q < 4; q++)
    if (has[q]) {
      t->i[t->n] = i + di[q], t->j[t->n] = j + dj[q];
      ca[t->n] = wa[q], cb[t->n] = wb[q];
      t->n++;
    }
  for (PetscInt q = 0; q < t->n; q++) {
    const PetscReal *xq = Pos(p, x, t->i[q], t->j[q]);
    for (int d = 0; d < 3; d++) a[d] += ca[q] * xq[d], b[d] += cb[q] * xq[d];
  }
  CosineDerivatives(a, b, want & TERM_HESSIAN, &c);
  {
    const PetscReal s = c.s, as = PetscAbsReal(s), over = as > p->s_lock ? as - p->s_lock : 0.0;
    if (want & TERM_ENERGY) t->E = 0.5 * p->Ks * s * s + 0.5 * p->Kj * over * over;
    CosineTermDerivatives(&c, p->Ks * s + p->Kj * (s > 0 ? over : -over), p->Ks + (over > 0 ? p->Kj : 0.0), t->n, ca,
                          cb, want, t);
  }
  return 1;
}

/* --- stable-step bound --- */

/* Gershgorin contribution of crossing (i,j)'s shear energy to one of its points:
   |E''| |grad s|_a sum_b |grad s|_b + |E'| |hess s| row <= (Ks+Kj)(4 + 12|s|)/tmin^2, for any
   |s| up to the window's win_s; the jamming stiffness counts once the window reaches the lock */
/* the numerator of ShearCrossingBound, the same at every crossing */
static inline PetscReal ShearBoundFactor(const Patch *p)
{
  return (p->Ks + (p->win_s >= p->s_lock ? p->Kj : 0.0)) * (4.0 + 12.0 * PetscMin(p->win_s, 1.0));
}
static PetscReal ShearCrossingBound(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j)
{
  PetscReal s, tmin;
  if (!CrossingShear(p, x, i, j, &s, &tmin)) return 0.0;
  return ShearBoundFactor(p) / (tmin * tmin);
}

/* the crossings that involve point (i,j): its four neighbours', and its own at an edge */
/* adds the crossings' bounds s = {left, right, below, above, own} to point (i,j)'s row: its own
   only at an edge */
static inline void ShearBoundAdd(const Patch *p, PetscInt i, PetscInt j, const PetscReal s[5], PetscReal *rs)
{
  *rs += s[0] + s[1] + s[2] + s[3];
  if (!ExistsG(p, i - 1, j) || !ExistsG(p, i + 1, j) || !ExistsG(p, i, j - 1) || !ExistsG(p, i, j + 1)) *rs += s[4];
}

static void ShearBoundRow(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, int pull_dir, PetscReal *rs,
                          PetscReal *rp)
{
  const PetscReal s[5] = {ShearCrossingBound(p, x, i - 1, j), ShearCrossingBound(p, x, i + 1, j),
                          ShearCrossingBound(p, x, i, j - 1), ShearCrossingBound(p, x, i, j + 1),
                          ShearCrossingBound(p, x, i, j)};
  ShearBoundAdd(p, i, j, s, rs);
}

/* ============================ the fused row pipeline ============================ */

/* y-segments between rows r and r+1, local columns [c0, c1) */
static void YSegments(Patch *p, const PetscReal *x, PetscInt r, PetscInt c0, PetscInt c1)
{
  const PetscInt n = p->gxm, lr = r - p->gys;
  SegmentRow    *s = &p->ys_ring[SLOT(r)];

  if (lr < 0 || lr + 1 >= p->gym) {
    ZeroSegmentRow(s, c0, c1);
    return;
  }
  { /* checked: the segments from a box point to the one above it, or from below into the box */
    const int in = r >= p->chk[2] - 1 && r < p->chk[3];
    ComputeSegmentRow(p->weft, p->ay, p->traction, p->win_lo[1], p->win_hi[1], c0, c1, in ? p->chk[0] : 0,
                      in ? p->chk[1] : 0, x + 3 * lr * n, x + 3 * (lr + 1) * n, p->exists + lr * n,
                      p->exists + (lr + 1) * n, p->broken_y + lr * n, p->strain_row, s, &p->left_window);
  }
}

/* y-bending centres of row r: chords y(r-1) and y(r) */
static void YBending(Patch *p, PetscInt r, PetscInt c0, PetscInt c1)
{
  const SegmentRow *a = &p->ys_ring[SLOT(r - 1)], *b = &p->ys_ring[SLOT(r)];
  ComputeBendRow(p->kby, c0, c1, a->ux, a->uy, a->uz, a->inv_len, b->ux, b->uy, b->uz, b->inv_len, &p->by_ring[SLOT(r)],
                 0);
}

/* advance the pipeline to row j: y-rows j+1 into the ring, x-segments and x-bending of row j */
static void AdvancePipeline(Patch *p, const PetscReal *x, PetscInt j, PetscInt c0, PetscInt c1)
{
  const PetscInt n = p->gxm, lj = j - p->gys, cx = PetscMin(c1, n - 1);
  SegmentRow    *xs = &p->xs_row;

  YSegments(p, x, j + 1, c0, c1);
  if (p->bending) YBending(p, j + 1, c0, c1);
  if (p->shear) ComputeShearRow(p, x, j + 1, c0, c1, &p->sh_ring[SLOT(j + 1)]);
  /* checked: the segments that end at a box point of row j */
  ComputeSegmentRow(p->warp, p->ax, p->traction, p->win_lo[0], p->win_hi[0], c0, cx, p->chk[0] - 1, p->chk[1],
                    x + 3 * lj * n, x + 3 * lj * n + 3, p->exists + lj * n, p->exists + lj * n + 1,
                    p->broken_x + lj * n, p->strain_row, xs, &p->left_window);
  if (p->bending)
    ComputeBendRow(p->kbx, c0, cx - 1, xs->ux, xs->uy, xs->uz, xs->inv_len, xs->ux + 1, xs->uy + 1, xs->uz + 1,
                   xs->inv_len + 1, &p->bx_row, 1);
}

/* |(x, y, z)| */
static inline PetscReal Norm3(PetscReal x, PetscReal y, PetscReal z)
{
  return PetscSqrtReal(x * x + y * y + z * z);
}

/* the magnitudes of the forces the terms put on the points i0 <= i < i1 of row j, added to sr
   (rows as the gathers above take them): each segment's |T|, each bending centre's and shear
   crossing's share at the point (the balance test per crossing, balance.c) */
static void MagnitudeTraction(const SegmentRow *xs, const SegmentRow *yd, const SegmentRow *yu, PetscInt i0,
                              PetscInt i1, PetscReal *restrict sr)
{
  for (PetscInt i = i0; i < i1; i++)
    sr[i] += Norm3(xs->fx[i], xs->fy[i], xs->fz[i]) + Norm3(xs->fx[i - 1], xs->fy[i - 1], xs->fz[i - 1]) +
             Norm3(yu->fx[i], yu->fy[i], yu->fz[i]) + Norm3(yd->fx[i], yd->fy[i], yd->fz[i]);
}

static void MagnitudeBending(const BendRow *bx, const BendRow *bd, const BendRow *bc, const BendRow *bu, PetscInt i0,
                             PetscInt i1, PetscReal *restrict sr)
{
  for (PetscInt i = i0; i < i1; i++)
    sr[i] += Norm3(bx->g2x[i - 1], bx->g2y[i - 1], bx->g2z[i - 1]) +
             Norm3(bx->g1x[i] - bx->g2x[i], bx->g1y[i] - bx->g2y[i], bx->g1z[i] - bx->g2z[i]) +
             Norm3(bx->g1x[i + 1], bx->g1y[i + 1], bx->g1z[i + 1]) + Norm3(bd->g2x[i], bd->g2y[i], bd->g2z[i]) +
             Norm3(bc->g1x[i] - bc->g2x[i], bc->g1y[i] - bc->g2y[i], bc->g1z[i] - bc->g2z[i]) +
             Norm3(bu->g1x[i], bu->g1y[i], bu->g1z[i]);
}

static void MagnitudeShear(const ShearRow *sd, const ShearRow *sc, const ShearRow *su, PetscInt i0, PetscInt i1,
                           PetscReal *restrict sr)
{
  for (PetscInt i = i0; i < i1; i++)
    sr[i] += Norm3(sc->hwx[i + 1], sc->hwy[i + 1], sc->hwz[i + 1]) +
             Norm3(sc->hwx[i - 1], sc->hwy[i - 1], sc->hwz[i - 1]) + Norm3(su->hfx[i], su->hfy[i], su->hfz[i]) +
             Norm3(sd->hfx[i], sd->hfy[i], sd->hfz[i]) + Norm3(sc->sx[i], sc->sy[i], sc->sz[i]);
}

/* The row pipeline over box: forces into f and, with mag, the magnitudes of each point's force
   terms into mag (owned points, written) */
static inline void InternalPipeline(Patch *p, const PetscReal *x, const PetscInt box[4], PetscReal *f, PetscReal *mag,
                                    PetscReal *tension_max)
{
  const PetscInt  n = p->gxm, i0 = box[0] - p->gxs, i1 = box[1] - p->gxs, j0 = box[2], j1 = box[3];
  const PetscInt  c0 = PetscMax(i0 - 2, 0), c1 = PetscMin(i1 + 2, n); /* columns the box's forces need */
  const PetscBool bend = p->bending, shear = p->shear;
  PetscReal       tmax = 0.0;

  *tension_max   = 0.0;
  p->left_window = 0;
  if (i1 <= i0 || j1 <= j0) return;
  p->chk[0] = i0, p->chk[1] = i1, p->chk[2] = j0, p->chk[3] = j1;
  /* prime the pipeline: rows below the first row of the box */
  for (PetscInt r = j0 - 2; r <= j0; r++) YSegments(p, x, r, c0, c1);
  if (bend)
    for (PetscInt r = j0 - 1; r <= j0; r++) YBending(p, r, c0, c1);
  if (shear)
    for (PetscInt r = j0 - 1; r <= j0; r++) ComputeShearRow(p, x, r, c0, c1, &p->sh_ring[SLOT(r)]);

  for (PetscInt j = j0; j < j1; j++) {
    /* gather: each point of row j in the box sums its terms in a fixed order */
    PetscReal *restrict fr = f + 3 * (j - p->ys) * p->xm - 3 * (p->xs - p->gxs);
    AdvancePipeline(p, x, j, c0, c1);
    tmax = GatherTraction(&p->xs_row, &p->ys_ring[SLOT(j - 1)], &p->ys_ring[SLOT(j)], i0, i1, fr, tmax);
    if (bend)
      GatherBending(&p->bx_row, &p->by_ring[SLOT(j - 1)], &p->by_ring[SLOT(j)], &p->by_ring[SLOT(j + 1)], i0, i1, fr);
    if (shear) GatherShear(&p->sh_ring[SLOT(j - 1)], &p->sh_ring[SLOT(j)], &p->sh_ring[SLOT(j + 1)], i0, i1, fr);
    if (mag) {
      PetscReal *restrict sr = mag + (j - p->ys) * p->xm - (p->xs - p->gxs);
      for (PetscInt i = i0; i < i1; i++) sr[i] = 0.0;
      MagnitudeTraction(&p->xs_row, &p->ys_ring[SLOT(j - 1)], &p->ys_ring[SLOT(j)], i0, i1, sr);
      if (bend)
        MagnitudeBending(&p->bx_row, &p->by_ring[SLOT(j - 1)], &p->by_ring[SLOT(j)], &p->by_ring[SLOT(j + 1)], i0, i1,
                         sr);
      if (shear) MagnitudeShear(&p->sh_ring[SLOT(j - 1)], &p->sh_ring[SLOT(j)], &p->sh_ring[SLOT(j + 1)], i0, i1, sr);
      for (PetscInt i = i0; i < i1; i++) /* an absent point has no terms (a one-sided tangent reaches past it) */
        if (!Exists(p, i, j - p->gys)) sr[i] = 0.0;
    }
  }
  *tension_max = tmax;
}

FABRIC_WIDE void ComputeInternalForces(Patch *p, const PetscReal *x, const PetscInt box[4], PetscReal *f,
                                       PetscReal *tension_max)
{
  InternalPipeline(p, x, box, f, NULL, tension_max);
}

FABRIC_WIDE void InternalForceMagnitudes(Patch *p, const PetscReal *x, const PetscInt box[4], PetscReal *f,
                                         PetscReal *mag)
{
  PetscReal tmax;
  InternalPipeline(p, x, box, f, mag, &tmax);
}

/* ======================= the terms as plug-ins (MODEL.md 14) ======================= */

/* the pipeline with only the given terms left on (those the patch has on) */
static void SoloForces(Patch *p, const PetscReal *x, const PetscInt box[4], PetscReal *f, PetscBool traction,
                       PetscBool bending, PetscBool shear)
{
  const PetscBool keep[3] = {p->traction, p->bending, p->shear};
  PetscReal       tmax;

  p->traction = traction && keep[0] ? PETSC_TRUE : PETSC_FALSE;
  p->bending  = bending && keep[1] ? PETSC_TRUE : PETSC_FALSE;
  p->shear    = shear && keep[2] ? PETSC_TRUE : PETSC_FALSE;
  ComputeInternalForces(p, x, box, f, &tmax);
  p->traction = keep[0], p->bending = keep[1], p->shear = keep[2];
}

static void TractionForces(Patch *p, const PetscReal *x, const PetscInt box[4], PetscReal *f)
{
  SoloForces(p, x, box, f, PETSC_TRUE, PETSC_FALSE, PETSC_FALSE);
}
static void BendingForces(Patch *p, const PetscReal *x, const PetscInt box[4], PetscReal *f)
{
  SoloForces(p, x, box, f, PETSC_FALSE, PETSC_TRUE, PETSC_FALSE);
}
static void ShearForces(Patch *p, const PetscReal *x, const PetscInt box[4], PetscReal *f)
{
  SoloForces(p, x, box, f, PETSC_FALSE, PETSC_FALSE, PETSC_TRUE);
}

static PetscBool TractionEnabled(const Patch *p)
{
  return p->traction;
}
static PetscBool BendingEnabled(const Patch *p)
{
  return p->bending;
}
static PetscBool ShearEnabled(const Patch *p)
{
  return p->shear;
}

const ForceTerm TractionTerm = {"traction", 2, TractionEnabled, TractionInstance, TractionForces, TractionBoundRow};
const ForceTerm BendingTerm  = {"bending", 2, BendingEnabled, BendingInstance, BendingForces, BendingBoundRow};
const ForceTerm ShearTerm    = {"shear", 1, ShearEnabled, ShearInstance, ShearForces, ShearBoundRow};
const ForceTerm *const InternalTerms[INTERNAL_TERMS] = {&TractionTerm, &BendingTerm, &ShearTerm};

PetscReal TermEnergy(const ForceTerm *t, const Patch *p, const PetscReal *x, const PetscInt box[4])
{
  PetscReal    E = 0.0;
  TermInstance inst;

  if (!t->enabled(p)) return 0.0;
  for (PetscInt j = box[2]; j < box[3]; j++)
    for (PetscInt i = box[0]; i < box[1]; i++)
      for (int k = 0; k < t->per_point; k++)
        if (t->instance(p, x, i, j, k, TERM_ENERGY, &inst)) E += inst.E;
  return E;
}

PetscErrorCode TermTangent(const ForceTerm *t, const Patch *p, const PetscReal *x, const PetscInt box[4],
                           PetscBool convex, TermBlocksFn add, void *ctx)
{
  const int    want = TERM_HESSIAN | (convex ? TERM_CONVEX : 0);
  TermInstance inst;

  PetscFunctionBeginUser;
  if (!t->enabled(p)) PetscFunctionReturn(0);
  for (PetscInt j = box[2]; j < box[3]; j++)
    for (PetscInt i = box[0]; i < box[1]; i++)
      for (int k = 0; k < t->per_point; k++)
        if (t->instance(p, x, i, j, k, want, &inst)) PetscCall(add(ctx, inst.n, inst.i, inst.j, inst.K));
  PetscFunctionReturn(0);
}

PetscReal InternalEnergy(const Patch *p, const PetscReal *x, const PetscInt box[4])
{
  PetscReal E = 0.0;
  for (int t = 0; t < INTERNAL_TERMS; t++) E += TermEnergy(InternalTerms[t], p, x, box);
  return E;
}

PetscErrorCode InternalTangent(const Patch *p, const PetscReal *x, const PetscInt box[4], PetscBool convex,
                               TermBlocksFn add, void *ctx)
{
  PetscFunctionBeginUser;
  for (int t = 0; t < INTERNAL_TERMS; t++) PetscCall(TermTangent(InternalTerms[t], p, x, box, convex, add, ctx));
  PetscFunctionReturn(0);
}

PetscErrorCode TermBlocksAddToMat(void *ctx, PetscInt n, const PetscInt i[], const PetscInt j[], const PetscReal K[])
{
  Mat        A = (Mat) ctx;
  MatStencil s[TERM_MAX_POINTS];

  PetscFunctionBeginUser;
  for (PetscInt q = 0; q < n; q++) {
    s[q].k = 0;
    s[q].j = j[q];
    s[q].i = i[q];
    s[q].c = 0;
  }
  PetscCall(MatSetValuesBlockedStencil(A, n, s, n, s, K, ADD_VALUES));
  PetscFunctionReturn(0);
}

/* ============== stable step: a bound on the tangent stiffness over a window of states (MODEL.md 7.3) ============== */

/* the columns [*a, *b) of [c0, c1) in row j (global) whose crossings and their four neighbours
   all exist, so that their shear tangents are x(i+1,j) - x(i-1,j) and x(i,j+1) - x(i,j-1): 1 if
   there are any */
static int ShearInterior(const Patch *p, PetscInt j, PetscInt c0, PetscInt c1, PetscInt *a, PetscInt *b)
{
  const PetscInt n = p->gxm, lj = j - p->gys, w = n + 2;
  *a = PetscMax(c0, 1), *b = PetscMin(c1, n - 1);
  return lj >= 1 && lj + 1 < p->gym && *a < *b && AllExist(p->epad + (lj + 1) * w + *a, *b - *a + 2) &&
         AllExist(p->epad + lj * w + *a + 1, *b - *a) && AllExist(p->epad + (lj + 2) * w + *a + 1, *b - *a);
}

/* CrossingShear on row j's interior crossings, local columns [a, b) (ShearInterior), by its own
   expressions (a change there is a change here): the tangents' lengths nw, nf and the cosine s
   (the crossing has no shear unless nw > 0 and nf > 0) */
static void ShearInteriorRow(const Patch *p, const PetscReal *x, PetscInt j, PetscInt a, PetscInt b,
                             PetscReal *restrict nw, PetscReal *restrict nf, PetscReal *restrict s)
{
  const PetscInt n = p->gxm, lj = j - p->gys;
  const PetscReal *restrict xr = x + 3 * lj * n, *restrict xd = xr - 3 * n, *restrict xu = xr + 3 * n;
  for (PetscInt li = a; li < b; li++) {
    const PetscReal wx = xr[3 * li + 3] - xr[3 * li - 3], wy = xr[3 * li + 4] - xr[3 * li - 2],
                    wz = xr[3 * li + 5] - xr[3 * li - 1];
    const PetscReal fx = xu[3 * li] - xd[3 * li], fy = xu[3 * li + 1] - xd[3 * li + 1], fz = xu[3 * li + 2] - xd[3 * li + 2];
    nw[li] = PetscSqrtReal(wx * wx + wy * wy + wz * wz), nf[li] = PetscSqrtReal(fx * fx + fy * fy + fz * fz);
    s[li]  = PetscMax(-1.0, PetscMin(1.0, (wx * fx + wy * fy + wz * fz) / (nw[li] * nf[li])));
  }
}

/* row by row: the chords and the interior crossings' cosines by loops that vectorise (in the
   patch's scratch rows: one call at a time on a patch), the maxima taken in the order of the
   crossings (as one loop over them) */
FABRIC_WIDE void WindowRange(const Patch *p, const PetscReal *x, PetscReal r[5])
{
  const PetscInt n = p->gxm, c0 = p->xs - p->gxs, c1 = c0 + p->xm;
  PetscReal     *e = p->bound_row[0], *L = p->bound_row[1], *dx = p->bound_row[2], *dy = p->bound_row[3],
            *dz = p->bound_row[4];

  for (int k = 0; k < 5; k++) r[k] = -PETSC_MAX_REAL;
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++) {
    const PetscInt lj = j - p->gys;
    for (int dir = 0; dir < 2; dir++) { /* the segments from the owned crossings; those past the patch are absent */
      const PetscInt  lk = lj + (dir == 1), b = PetscMin(c1, n - (dir == 0));
      const PetscReal L0 = dir == 0 ? p->ax : p->ay;
      if (lk >= p->gym || c0 >= b) continue;
      BoundChordRow(L0, c0, b, x + 3 * lj * n, x + 3 * (lk * n + (dir == 0)), p->exists + lj * n,
                    p->exists + lk * n + (dir == 0), (dir == 0 ? p->broken_x : p->broken_y) + lj * n, dx, dy, dz, L, e);
      for (PetscInt li = c0; li < b; li++) { /* selects, not branches: an absent or broken one gives -PETSC_MAX_REAL */
        const int alive = !(L[li] < 0);
        r[2 * dir]      = PetscMax(r[2 * dir], alive ? -e[li] : -PETSC_MAX_REAL);
        r[2 * dir + 1]  = PetscMax(r[2 * dir + 1], alive ? e[li] : -PETSC_MAX_REAL);
      }
    }
    if (p->shear) {
      PetscReal s, tmin;
      PetscInt  a, b;
      if (!ShearInterior(p, j, c0, c1, &a, &b)) a = b = c1;
      for (PetscInt li = c0; li < a; li++)
        if (CrossingShear(p, x, p->gxs + li, j, &s, &tmin)) r[4] = PetscMax(r[4], PetscAbsReal(s));
      ShearInteriorRow(p, x, j, a, b, dx, dy, e); /* the scratch rows take nw, nf and s here */
      for (PetscInt li = a; li < b; li++) r[4] = PetscMax(r[4], dx[li] > 0 && dy[li] > 0 ? PetscAbsReal(e[li]) : -PETSC_MAX_REAL);
      for (PetscInt li = PetscMax(a, b); li < c1; li++)
        if (CrossingShear(p, x, p->gxs + li, j, &s, &tmin)) r[4] = PetscMax(r[4], PetscAbsReal(s));
    }
  }
}

void WindowSet(Patch *p, const PetscReal r[5], PetscReal margin)
{
  for (int dir = 0; dir < 2; dir++) {
    const int none = r[2 * dir + 1] == -PETSC_MAX_REAL; /* no live segment: none can come back */
    p->win_lo[dir] = none ? 0.0 : -r[2 * dir] - margin;
    p->win_hi[dir] = none ? 0.0 : r[2 * dir + 1] + margin;
    p->win_k[dir]  = ChordTangentMax(dir == 0 ? p->warp : p->weft, p->win_lo[dir], p->win_hi[dir]) /
                    (dir == 0 ? p->ax : p->ay);
  }
  p->win_s = PetscMax(r[4], 0.0) + margin;
}

/* the shear crossings' bounds (ShearCrossingBound) of row j, local columns [c0, c1): on the
   row's interior (ShearInterior) by ShearInteriorRow and a loop over the row, elsewhere crossing
   by crossing */
static void BoundShearRow(const Patch *p, const PetscReal *x, PetscInt j, PetscInt c0, PetscInt c1, PetscReal *sh)
{
  PetscReal *nw = p->bound_row[0], *nf = p->bound_row[1], *cs = p->bound_row[2];
  PetscInt   a, b;

  if (!ShearInterior(p, j, c0, c1, &a, &b)) a = b = c1;
  for (PetscInt li = c0; li < a; li++) sh[li] = ShearCrossingBound(p, x, p->gxs + li, j);
  if (a < b) {
    const PetscReal K = ShearBoundFactor(p);
    ShearInteriorRow(p, x, j, a, b, nw, nf, cs);
    for (PetscInt li = a; li < b; li++) {
      const PetscReal tmin = PetscMin(nw[li], nf[li]);
      sh[li]               = nw[li] > 0 && nf[li] > 0 ? K / (tmin * tmin) : 0.0;
    }
  }
  for (PetscInt li = PetscMax(a, b); li < c1; li++) sh[li] = ShearCrossingBound(p, x, p->gxs + li, j);
}

/* the bending centres' rows (BendingBoundAdd) of one yarn family, centres a <= i < b, from the
   lengths of their chords before (L1) and after (L2) them: kb 12 / Lmin^2 into v12 and kb 24 /
   Lmin^2 into v24, 0 where BendingBoundAdd adds nothing (a row sum is >= +0, so adding +0 leaves
   it as it is) */
static void BoundBendRow(PetscReal kb, PetscReal Lc, PetscInt a, PetscInt b, const PetscReal *restrict L1,
                         const PetscReal *restrict L2, PetscReal *restrict v12, PetscReal *restrict v24)
{
  for (PetscInt i = a; i < b; i++) {
    const PetscReal Lmin = PetscMin(PetscMin(L1[i], L2[i]), Lc);
    const int       on   = !(L1[i] < 0) & !(L2[i] < 0) & (Lmin > 0);
    const PetscReal d    = on ? Lmin * Lmin : 1.0;
    v12[i]               = on ? kb * 12.0 / d : 0.0;
    v24[i]               = on ? kb * 24.0 / d : 0.0;
  }
}

/* The rows of StableOmega2, one patch row at a time: the x-segments of row j, the y-segments of
   rows j-2..j+1 and the shear crossings of rows j-1..j+1 are each evaluated once, and each point
   adds their shares as TractionBoundRow, BendingBoundRow and ShearBoundRow do (the same values in
   the same order: unit_kernels (c) checks the bits). */
FABRIC_WIDE PetscReal StableOmega2(Patch *p, const PetscReal *x, const PetscReal *inv_m, int pull_dir, PetscReal *omega2_pull,
                       BoundRow *at)
{
  const PetscInt c0 = p->xs - p->gxs, c1 = c0 + p->xm; /* owned local columns */
  const int      segs = p->traction || p->bending;
  PetscReal      omega2 = 0.0, pull2 = 0.0;
  BoundRow       best = {-1, -1, 0.0, {0, 0, 0, 0}};
  /* the bending centres' rows: along x (row j), along y (rows j - 1, j, j + 1) */
  PetscReal *bx12 = p->bound_row[5], *bx24 = p->bound_row[6], *by12[3] = {p->bound_row[7], p->bound_row[8], p->bound_row[9]},
            *by24[3] = {p->bound_row[10], p->bound_row[11], p->bound_row[12]};
  const PetscReal Lcx = (1.0 + p->warp->e_contact) * p->ax, Lcy = (1.0 + p->weft->e_contact) * p->ay;

  if (segs)
    for (PetscInt r = p->ys - 2; r < p->ys + 1; r++)
      BoundSegmentRow(p, x, r, 1, pull_dir, 1, c0, c1, &p->by_seg[SLOT(r)]);
  if (p->shear)
    for (PetscInt r = p->ys - 1; r < p->ys + 1; r++) BoundShearRow(p, x, r, c0 - 1, c1 + 1, p->bsh_ring[SLOT(r)]);
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++) {
    const BoundSegRow *xr = &p->bx_seg, *yd = &p->by_seg[SLOT(j - 1)], *yc = &p->by_seg[SLOT(j)];
    const PetscReal   *sd = p->bsh_ring[SLOT(j - 1)], *sc = p->bsh_ring[SLOT(j)], *su = p->bsh_ring[SLOT(j + 1)];
    if (segs) {
      BoundSegmentRow(p, x, j, 0, pull_dir, 1, c0 - 2, c1 + 2, &p->bx_seg);
      BoundSegmentRow(p, x, j + 1, 1, pull_dir, 1, c0, c1, &p->by_seg[SLOT(j + 1)]);
    }
    if (p->shear) BoundShearRow(p, x, j + 1, c0 - 1, c1 + 1, p->bsh_ring[SLOT(j + 1)]);
    if (p->bending) {
      BoundBendRow(p->kbx, Lcx, c0 - 1, c1 + 1, xr->L - 1, xr->L, bx12, bx24);
      for (int k = -1; k <= 1; k++)
        BoundBendRow(p->kby, Lcy, c0, c1, p->by_seg[SLOT(j + k - 1)].L, p->by_seg[SLOT(j + k)].L, by12[k + 1],
                     by24[k + 1]);
    }
    for (PetscInt li = c0; li < c1; li++) {
      const PetscInt  i  = p->gxs + li;
      const PetscReal im = inv_m[(j - p->ys) * p->xm + (li - c0)];
      PetscReal       rs = 0.0, rp = 0.0, upto[3], kc, B[6] = {0, 0, 0, 0, 0, 0};
      if (im <= 0.0) continue;
      if (p->traction) { /* TractionBoundRow */
        BoundSegmentAdd(xr, li - 1, p->win_k[0], pull_dir == 0, B, &rp);
        BoundSegmentAdd(xr, li, p->win_k[0], pull_dir == 0, B, &rp);
        BoundSegmentAdd(yd, li, p->win_k[1], pull_dir == 1, B, &rp);
        BoundSegmentAdd(yc, li, p->win_k[1], pull_dir == 1, B, &rp);
        rs += 2.0 * SymMaxEig3(B);
      }
      upto[0] = rs;
      if (p->bending) { /* BendingBoundRow: the centres k = -1, 0, 1 along x, then along y */
        rs += bx12[li - 1], rs += bx24[li], rs += bx12[li + 1];
        rs += by12[0][li], rs += by24[1][li], rs += by12[2][li];
      }
      upto[1] = rs;
      if (p->shear) { /* ShearBoundRow */
        const PetscReal s[5] = {sc[li - 1], sc[li + 1], sd[li], su[li], sc[li]};
        ShearBoundAdd(p, i, j, s, &rs);
      }
      upto[2] = rs;
      kc = ContactPart(p, x + 3 * ((j - p->gys) * p->gxm + li), B, upto[0]); /* ContactBoundRow */
      rs += kc;
      if (rs * im > best.omega2)
        best = (BoundRow){
          i, j, rs * im, {upto[0] * im, (upto[1] - upto[0]) * im, (upto[2] - upto[1]) * im, kc * im}
        };
      omega2 = PetscMax(omega2, rs * im);
      pull2  = PetscMax(pull2, rp * im);
    }
  }
  *omega2_pull = pull2;
  if (at) *at = best;
  return omega2;
}

/* ------------------------------------------------------------------ point fields */

static inline PetscReal SegmentTension(const Patch *p, const PetscReal *x, PetscInt ka, PetscInt kb, const YarnLaw *law,
                                       PetscReal L0)
{
  const PetscReal *a = x + 3 * ka, *b = x + 3 * kb;
  const PetscReal  L = PetscSqrtReal(PetscSqr(b[0] - a[0]) + PetscSqr(b[1] - a[1]) + PetscSqr(b[2] - a[2]));
  return p->traction ? ChordTension(law, L / L0 - 1.0) : 0.0;
}

/* The point fields of a frame (fabric.h5) on the owned points: the mean tension of the warp and of
   the weft segments at each crossing (N) and its shear angle asin(cos(angle(tw, tf))) (degrees). */
void PointFields(const Patch *p, const PetscReal *x, PetscReal *tw, PetscReal *tf, PetscReal *sh)
{
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
    for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
      const PetscInt q = (j - p->ys) * p->xm + (i - p->xs), k = (j - p->gys) * p->gxm + (i - p->gxs), w = p->gxm;
      const int      self = p->exists[k];
      const int      hl = self && i > 0 && p->exists[k - 1], hr = self && i < p->nx - 1 && p->exists[k + 1];
      const int      hd = self && j > 0 && p->exists[k - w], hu = self && j < p->ny - 1 && p->exists[k + w];
      PetscReal      sum = 0;
      int            n   = 0;

      /* warp: segments (i-1,j)-(i,j) and (i,j)-(i+1,j); weft: (i,j-1)-(i,j) and (i,j)-(i,j+1) */
      if (hl && !p->broken_x[k - 1]) sum += SegmentTension(p, x, k - 1, k, p->warp, p->ax), n++;
      if (hr && !p->broken_x[k]) sum += SegmentTension(p, x, k, k + 1, p->warp, p->ax), n++;
      tw[q] = n ? sum / n : 0.0;
      sum = 0, n = 0;
      if (hd && !p->broken_y[k - w]) sum += SegmentTension(p, x, k - w, k, p->weft, p->ay), n++;
      if (hu && !p->broken_y[k]) sum += SegmentTension(p, x, k, k + w, p->weft, p->ay), n++;
      tf[q] = n ? sum / n : 0.0;

      /* shear angle from the tangents of MODEL.md 5.3, one-sided at an edge */
      {
        PetscReal c, tmin;
        sh[q] = CrossingShear(p, x, i, j, &c, &tmin) ? PetscAsinReal(c) * 180.0 / PETSC_PI : 0.0;
      }
    }
}
