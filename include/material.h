/* material.h - the yarn tension law in chord strain (MODEL.md 5.1) and its fast form.
 *
 * A yarn segment between two crossings has rest chord L0 and crimp c: the yarn
 * length between the crossings is (1+c) L0. With chord strain e = L/L0 - 1 the
 * tension is
 *   e <= e_cont : T = k_comp*EA*e_cont + EA*(e - e_cont)   (crossings touch: yarn contact)
 *   e <= 0      : T = k_comp * EA * e            (yarns buckle rather than carry compression)
 *   0 < e <= c  : T = Ec * e                      (de-crimping)
 *   e > c       : T = Ec*c + Tyarn(ey),  ey = (1+e)/(1+c) - 1   (yarn extension)
 * Each kink is smoothed over +-smoothing by a cubic (ChordTension).
 * Tyarn is linear (EA*ey) or a table read from CSV, interpolated with GSL's
 * Steffen (monotone) spline. Evaluating a GSL spline per segment per step is too
 * slow, so at load time the spline is resampled on a uniform grid of yarn strain
 * (value and slope at each node) and evaluated as a cubic Hermite in O(1).
 */
#ifndef FABRIC_MATERIAL_H
#define FABRIC_MATERIAL_H

#include <petscsys.h>

#define YARN_TABLE_NODES 4097 /* uniform nodes of the fast yarn table */

typedef struct {
  const char *name;          /* "warp" or "weft": names the options in messages */
  PetscReal   tex;           /* linear density, g/km (input unit) */
  PetscReal   bundle;        /* the fabric's yarns a grid yarn stands for (0 or 1: one; -static_sequence's
                                coarse fabrics: 2, 4 ...): scales a table's forces */
  PetscReal   mu;            /* linear density, kg/m */
  PetscReal   crimp;         /* c, fraction */
  PetscReal   EA;            /* yarn stiffness, N per unit yarn strain (table: its largest slope) */
  PetscReal   Ec;            /* de-crimping stiffness, N per unit chord strain (decrimp_ratio EA) */
  PetscReal   decrimp_ratio; /* Ec / EA (a table: its largest slope) */
  PetscReal   k_comp;        /* compression stiffness as a fraction of EA */
  PetscReal   e_contact;     /* chord strain (< 0) at which neighbouring crossings touch */
  PetscReal   smoothing;     /* half-width (chord strain) of the C1 blends at the law's kinks */
  PetscInt    nblend;        /* blends: cubic Hermite on [lo, hi], T = c0 + s (c1 + s (c2 + s c3)), s = e - lo */
  struct {
    PetscReal lo, hi, c0, c1, c2, c3, slope_max;
  } blend[3];
  PetscReal bending;  /* bending rigidity B, N m^2 */
  PetscReal break_ey; /* mean yarn strain at break (at the yarn test's gauge); <= 0: never breaks */
  PetscReal break_e;  /* the same as chord strain (INFINITY if none) */
  /* scatter of the breaking strain (YarnBreakSetUp): each segment's yarn breaking strain is drawn
     from a Weibull distribution of shape break_k and scale break_scale; cv 0: every segment breaks
     at break_ey */
  PetscReal break_cv;    /* coefficient of variation at the yarn test's gauge, fraction */
  PetscReal break_gauge; /* the yarn test's gauge length that break_ey and break_cv hold for, m */
  PetscReal break_k, break_scale;
  /* fast form of a tabulated law (ntab == 0: linear law) */
  PetscInt    ntab;
  PetscReal   tab_h, tab_inv_h, tab_end; /* node spacing and last node, in yarn strain */
  PetscReal  *tab_T, *tab_dT;            /* tension (N) and slope (N) at the nodes */
  PetscInt    nlev;                      /* range-max table of the slope per cell */
  PetscReal **tab_slope_max;
  char        csv[PETSC_MAX_PATH_LEN];
} YarnLaw;

/* Tyarn(ey), ey >= 0 (NaN: NaN, past the table's end rather than a cell indexed by it) */
static inline PetscReal YarnTension(const YarnLaw *y, PetscReal ey)
{
  if (!y->ntab) return y->EA * ey;
  PetscReal s = ey * y->tab_inv_h;
  if (!(s < (PetscReal) (y->ntab - 1))) return y->tab_T[y->ntab - 1] + y->tab_dT[y->ntab - 1] * (ey - y->tab_end);
  PetscInt  k = (PetscInt) s;
  PetscReal t = s - (PetscReal) k, u = 1.0 - t, h = y->tab_h;
  return (1.0 + 2.0 * t) * u * u * y->tab_T[k] + t * u * u * h * y->tab_dT[k] +
         t * t * (3.0 - 2.0 * t) * y->tab_T[k + 1] - t * t * u * h * y->tab_dT[k + 1];
}

/* the piecewise law of MODEL.md 5.1 as written, with kinks */
static inline PetscReal ChordTensionPiecewise(const YarnLaw *y, PetscReal e)
{
  if (e <= y->e_contact) return y->k_comp * y->EA * y->e_contact + y->EA * (e - y->e_contact);
  if (e <= 0.0) return y->k_comp * y->EA * e;
  if (e <= y->crimp) return y->Ec * e;
  return y->Ec * y->crimp + YarnTension(y, (e - y->crimp) / (1.0 + y->crimp));
}

/* T(e): the law with each kink replaced, over +-smoothing, by the cubic that matches both
   pieces' values and slopes. Explicit central differences pump energy into a chain whose
   stiffness jumps (20x at the crimp knee, 1000x at yarn contact); a C1 law does not. */
static inline PetscReal ChordTension(const YarnLaw *y, PetscReal e)
{
  for (PetscInt k = 0; k < y->nblend; k++)
    if (e >= y->blend[k].lo && e <= y->blend[k].hi) {
      const PetscReal s = e - y->blend[k].lo;
      return y->blend[k].c0 + s * (y->blend[k].c1 + s * (y->blend[k].c2 + s * y->blend[k].c3));
    }
  return ChordTensionPiecewise(y, e);
}

PetscErrorCode YarnLawSetUp(YarnLaw *y, MPI_Comm comm);
/* the Weibull scatter of the breaking strain for segments of rest chord L0 (after YarnLawSetUp) */
PetscErrorCode YarnBreakSetUp(YarnLaw *y, PetscReal L0, MPI_Comm comm);
/* breaking chord strain of the segment of family dir (0 warp, 1 weft) starting at global crossing
   (i,j), drawn from its seed and global index alone: the same on any number of ranks */
PetscReal SegmentBreakStrain(const YarnLaw *y, PetscInt64 seed, int dir, PetscInt i, PetscInt j);
/* Weibull shape whose coefficient of variation is cv (0 < cv < 1) */
PetscReal WeibullShape(PetscReal cv);
PetscErrorCode YarnLawDestroy(YarnLaw *y);
/* largest dTyarn/dey over yarn strains [lo, hi], lo >= 0 */
static inline PetscReal YarnSlopeMax(const YarnLaw *y, PetscReal lo, PetscReal hi)
{
  PetscInt  ncell = y->ntab - 1, k0, k1;
  PetscReal m     = 0.0;

  if (!y->ntab) return y->EA;
  if (hi >= y->tab_end) m = y->tab_dT[y->ntab - 1]; /* linear extension */
  if (lo >= y->tab_end) return m;
  k0 = (PetscInt) (lo * y->tab_inv_h);
  k1 = PetscMin((PetscInt) (hi * y->tab_inv_h), ncell - 1);
  if (k1 < k0) k1 = k0;
  {
    PetscInt len = k1 - k0 + 1, l = 0;
    while ((2 << l) <= len) l++;
    m = PetscMax(m, PetscMax(y->tab_slope_max[l][k0], y->tab_slope_max[l][k1 - (1 << l) + 1]));
  }
  return m;
}

/* largest dT/de over chord strains [a,b]: the tangent used by the stable-step bound (inline: the
   bound's rows call it for every segment along the pull) */
static inline PetscReal ChordTangentMax(const YarnLaw *y, PetscReal a, PetscReal b)
{
  const PetscReal c = y->crimp;
  PetscReal       m = 0.0;

  if (a <= y->e_contact) m = y->EA;
  if (a <= 0.0 && b > y->e_contact) m = PetscMax(m, y->k_comp * y->EA);
  if (a < c && b > 0.0) m = PetscMax(m, y->Ec);
  if (b > c) {
    PetscReal lo = (PetscMax(a, c) - c) / (1.0 + c), hi = (b - c) / (1.0 + c);
    m = PetscMax(m, YarnSlopeMax(y, lo, hi) / (1.0 + c));
  }
  for (PetscInt k = 0; k < y->nblend; k++)
    if (a <= y->blend[k].hi && b >= y->blend[k].lo) m = PetscMax(m, y->blend[k].slope_max);
  return m;
}

#endif
