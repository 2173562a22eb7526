/* kernels.h - the internal force terms over one rank's patch (MODEL.md 5.1-5.3, 7.3, 14).
 *
 * Kernels take loop bounds and arrays only: no MPI, no options, no I/O.
 * The patch is the rank's ghosted part of the DMDA (box stencil, width 2).
 * Every rank computes the force on its own points from its ghosts ("gather"),
 * in a fixed order per point, so results do not depend on how the grid is split.
 *
 * Three terms, each switched by the patch (traction, bending, shear) and each described by a
 * ForceTerm: its energy, its forces, its tangent stiffness and its share of the stable-step
 * bound. The explicit path uses ComputeInternalForces (all terms fused in one row pipeline)
 * and StableOmega2; the quasi-static path uses TermEnergy, the forces and TermTangent.
 */
#ifndef FABRIC_KERNELS_H
#define FABRIC_KERNELS_H

/* FABRIC_WIDE: a hot loop nest built for x86-64-v4 (AVX-512), x86-64-v3 (AVX2) and the baseline,
   everything it calls inlined into each (flatten), the widest the CPU runs picked when the
   program loads (GCC's target_clones, an ifunc: x86-64 Linux). With no contraction into fused
   multiply-adds (CMakeLists.txt) every clone computes the same bits. -DFABRIC_CLONES=OFF: the
   baseline alone. */
#if defined(FABRIC_CLONES) && defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
  #define FABRIC_WIDE __attribute__((flatten, target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
  #define FABRIC_WIDE
#endif

#include <petscmat.h>
#include <stdint.h>
#include <string.h>

#include "material.h"

#define KERNEL_RING 4 /* rows kept by the row pipeline: y-segments j-2..j+1 */

/* the bits of |t| as a signed integer, ordered as |t| (a NaN above every number): a maximum of
   them is an integer max, which vectorises where a floating-point one does not */
static inline int64_t AbsBits(PetscReal t)
{
  const PetscReal a = PetscAbsReal(t);
  int64_t         b;
  memcpy(&b, &a, sizeof b);
  return b;
}

typedef struct {           /* a row of yarn segments */
  PetscReal *ux, *uy, *uz; /* unit chord (0 if the segment is absent or broken) */
  PetscReal *inv_len;      /* 1/L (0 if absent) */
  PetscReal *fx, *fy, *fz; /* T * unit chord: force on the segment's first point */
  PetscReal *T;            /* tension, N */
} SegmentRow;

typedef struct { /* bending centres of a row: kb * ds/de1 and kb * ds/de2 */
  PetscReal *g1x, *g1y, *g1z, *g2x, *g2y, *g2z;
} BendRow;

typedef struct { /* shear crossings of a row: E'(s) ds/dtw, E'(s) ds/dtf, one-sided self term */
  PetscReal *hwx, *hwy, *hwz, *hfx, *hfy, *hfz, *sx, *sy, *sz;
  PetscReal *as; /* |s| = |sin(shear angle)| (0 without shear) */
} ShearRow;

typedef struct {  /* a row of yarn segments as the stable-step bound sees them (StableOmega2) */
  PetscReal *L;    /* chord length, -1 if the segment is absent or broken */
  PetscReal *b[6]; /* its share of each end's 3x3 block {xx, yy, zz, xy, xz, yz} (TractionBoundRow) */
  PetscReal *pull; /* its share of each end's pull-direction row (PullSpringRow) */
} BoundSegRow;

/* A frictionless sphere or plane as the stable-step bound sees it (MODEL.md 7.3): its penalty's
   Hessian at a point is at most k n n^T, n the body's normal there (a sphere's tangential part,
   -k (reach - r)/r (I - n n^T), only lowers it), so the point's block takes k along n alone.
   A sphere that still moves by span within the load step (its ramp) turns the normal at a point
   at distance r from c by an angle theta with sin(theta) <= span / r, which moves the
   eigenvalue by at most k span / r: the row adds that too. */
#define CONTACT_BOUNDS_MAX 3
typedef struct {
  int       body;   /* its index among the scene's bodies */
  PetscBool sphere; /* n from the centre c to the point; else the plane's unit normal n */
  PetscReal k, c[3], n[3];
  PetscReal span; /* m: how far a sphere's centre moves from c up to the load step's end */
} ContactBound;

typedef struct {
  /* grid and patch, global indices */
  PetscInt       nx, ny;
  PetscInt       xs, ys, xm, ym;     /* owned */
  PetscInt       gxs, gys, gxm, gym; /* ghosted */
  PetscReal      ax, ay;             /* rest chords: x-segments (warp) and y-segments (weft), m */
  const YarnLaw *warp, *weft;        /* warp yarns run along x, weft along y */
  /* switches and constants */
  PetscBool traction, bending, shear;
  PetscReal kbx, kby;       /* B / L0 along x and y, N m */
  PetscReal Ks, Kj, s_lock; /* shear stiffness per crossing, jamming stiffness (N m), sin(gamma_lock) */
  PetscReal k_contact;      /* penalty stiffness of rigid-body contact in every direction (N/m): the bodies with
                               friction (the stick spring is tangential) and the pedestal; 0 = none */
  ContactBound cb[CONTACT_BOUNDS_MAX]; /* the other bodies: k along their normal at each point */
  int          ncb;
  /* the stable step's window (StableStep, MODEL.md 7.3): the chord strains of each family
     (0 warp, 1 weft) and the |sin(shear angle)| its bound covers; ComputeInternalForces sets
     left_window when a segment or crossing next to a point of its box is outside them */
  PetscReal win_lo[2], win_hi[2], win_s;
  PetscReal win_k[2]; /* the largest yarn tangent (N) within each family's window, over L0 (WindowSet) */
  int       left_window;
  PetscBool tension_field;  /* the traction tangent drops a compressed segment's geometric part, max(T,0)/L:
                               a positive semi-definite Newton matrix (set by the quasi-static path around its
                               tangent's assembly only); else exact */
  /* ghosted per-point and per-segment state */
  unsigned char *exists;              /* point exists (inside the shape), ghosted */
  unsigned char *broken_x, *broken_y; /* segment (i,j)-(i+1,j) / (i,j)-(i,j+1) broke */
  PetscReal     *break_x, *break_y;   /* their breaking chord strains (NULL: the laws' break_e) */
  /* work space of the row pipeline */
  SegmentRow     xs_row, ys_ring[KERNEL_RING];
  BendRow        by_ring[KERNEL_RING], bx_row;
  ShearRow       sh_ring[KERNEL_RING];
  /* work space of the stable-step bound: the x-segments of a row, the y-segments of rows
     j-2..j+1 and the shear crossings' rows j-1..j+1 (columns padded by 2 on each side) */
  BoundSegRow    bx_seg, by_seg[KERNEL_RING];
  PetscReal     *bsh_ring[KERNEL_RING];
  PetscReal     *bound_row[13]; /* the bound's scratch rows: strains, tensions, chords; bending centres */
  PetscReal     *bound_work;
  PetscReal     *zero_row;   /* 3*gxm zeros: positions of rows outside the patch */
  PetscReal     *strain_row; /* gxm: the chord strains of the segment row being computed */
  PetscReal     *break_row;  /* 2 gxm: BreakSegments' strains and a family's breaking strain */
  unsigned char *epad;     /* exists, padded by one absent point on every side */
  PetscReal     *work;
  PetscInt       chk[4]; /* the box being computed: local columns i0, i1 and global rows j0, j1 (window check) */
  /* traction energy of a tabulated yarn law (warp, weft): integral of Tyarn over the table's
     cells below each node (PatchSetUp; NULL for a linear law) */
  PetscReal *yarn_integral[2];
} Patch;

/* Allocates the pipeline's rows and the yarn integral tables: after YarnLawSetUp of both laws. */
PetscErrorCode PatchSetUp(Patch *p);
PetscErrorCode PatchDestroy(Patch *p);

/* Internal force (traction + bending + shear) on the owned points of box = {i0, i1, j0, j1}
   (global indices, half-open, inside the owned patch); points outside it are not touched.
   x: ghosted positions (3 per point), f: owned forces (3 per point).
   tension_max: largest |T| of a segment at a point of the box (the balance test's force scale). */
void ComputeInternalForces(Patch *p, const PetscReal *x, const PetscInt box[4], PetscReal *f, PetscReal *tension_max);
/* The same forces, and mag: at each owned point of box the sum of the magnitudes of the forces
   its terms put on it (each segment's |T|, each bending centre's and shear crossing's share; 0 at
   an absent point), the scale of the balance test per crossing (balance.c) */
void InternalForceMagnitudes(Patch *p, const PetscReal *x, const PetscInt box[4], PetscReal *f, PetscReal *mag);

/* cos of the warp/weft tangent angle at crossing (i,j) (global indices, within the ghosted
   patch) and the shorter tangent's length; 0 if the crossing has no shear */
int CrossingShear(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, PetscReal *s, PetscReal *tmin);

typedef struct {      /* the segment a break check found the most strained past its breaking strain */
  PetscReal ratio;     /* its chord strain over its breaking strain (0: none broke) */
  PetscInt  dir, i, j; /* family (0 warp: to (i+1,j), 1 weft: to (i,j+1)) and global first crossing */
} BreakSite;

/* Break the segments strained past their breaking strain (break_x/_y, else the law's): every
   segment of the ghosted patch, so that neighbouring ranks agree without messages. Returns the
   segments broken whose first crossing is owned; *site: the most overstrained of those; *load: the
   largest chord strain over breaking strain of any segment checked, broken or not. */
PetscInt BreakSegments(Patch *p, const PetscReal *x, int apply, BreakSite *site, PetscReal *load);

/* The range of the state a stable-step bound covers (MODEL.md 7.3): over the owned points'
   segments and crossings, r = {-min e_warp, max e_warp, -min e_weft, max e_weft, max |s|}
   (-PETSC_MAX_REAL where there is none), for a max-reduction; WindowSet then widens the reduced
   range by margin (chord strain, and sin(shear angle)) into the patch's window. */
void WindowRange(const Patch *p, const PetscReal *x, PetscReal r[5]);
void WindowSet(Patch *p, const PetscReal r[5], PetscReal margin);

typedef struct {    /* the point whose row sets the bound (the first in the patch's order) */
  PetscInt  i, j;    /* global crossing; -1 if no point has stiffness */
  PetscReal omega2;  /* its row times 1/m */
  PetscReal part[4]; /* of it, traction, bending, shear and contact */
} BoundRow;

/* Bound on omega_max^2 of M^-1 K over owned points with inv_m > 0 (MODEL.md 7.3), for any
   state within the patch's window: at each point, 2 lambda_max of the sum of its yarn
   segments' 3x3 blocks (yarn tangent maximised over the window, geometric part max(T,0)/L),
   plus the Gershgorin row sums of bending and shear (jamming counted if the window reaches the
   lock), plus the contact penalty (ContactBoundRow). omega2_pull: the same from the current
   tangent of the yarns along pull_dir (0: x, 1: y) alone: the highest frequency of the chain the
   damping is tuned to. at (or NULL): the point whose row sets the bound, and its terms' parts there.
   Each segment and crossing is evaluated once (rows in the patch's bound work space); each
   point's row takes the same values in the same order as the sum of the terms' bound_row and
   ContactBoundRow. */
PetscReal StableOmega2(Patch *p, const PetscReal *x, const PetscReal *inv_m, int pull_dir, PetscReal *omega2_pull,
                       BoundRow *at);
/* The rigid bodies' part of point (i,j)'s row: k_contact, plus what the frictionless bodies'
   k n n^T add to the yarns' blocks, lambda_max(2 B + sum k n n^T) - 2 lambda_max(B) (between 0
   and their sum of k), B the point's traction block (none without traction) */
PetscReal ContactBoundRow(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j);
/* omega2_pull of StableOmega2 alone */
PetscReal PullOmega2(Patch *p, const PetscReal *x, const PetscReal *inv_m, int pull_dir);

/* ---------------- force terms as plug-ins (MODEL.md 5.1-5.3, 7.3, 14) ---------------- */

#define TERM_MAX_POINTS 5 /* a shear crossing couples its centre and four neighbours */

/* what an instance computes; TERM_CONVEX (with TERM_HESSIAN): the Hessian's positive part
   instead, the second derivatives in the term's two tangents (a 6 x 6 matrix) with their
   negative eigenvalues set to 0 (bending, shear), or a yarn segment's geometric part max(T,0)/L
   (as with the patch's tension field), so that K is positive semi-definite and exceeds the
   Hessian by a positive semi-definite matrix */
enum { TERM_ENERGY = 1, TERM_GRADIENT = 2, TERM_HESSIAN = 4, TERM_CONVEX = 8 };

/* One instance of a term: a yarn segment (2 points), a bending centre (3) or a crossing
   (3 to 5 points). Every instance is owned by one point, so a sum over the owned points of
   all ranks counts each instance once. */
typedef struct {
  PetscInt  n;                                        /* points it couples */
  PetscInt  i[TERM_MAX_POINTS], j[TERM_MAX_POINTS];   /* their global indices */
  PetscReal E;                                        /* energy, J (TERM_ENERGY) */
  PetscReal g[3 * TERM_MAX_POINTS];                   /* dE/dx, 3 per point (TERM_GRADIENT) */
  PetscReal K[9 * TERM_MAX_POINTS * TERM_MAX_POINTS]; /* d2E/dx2, row-major 3n x 3n (TERM_HESSIAN) */
} TermInstance;

/* receives the 3n x 3n tangent K (row-major, 3x3 blocks) of the points (i[q], j[q]), q < n */
typedef PetscErrorCode (*TermBlocksFn)(void *ctx, PetscInt n, const PetscInt i[], const PetscInt j[],
                                       const PetscReal K[]);

typedef struct {
  const char *name;      /* "traction", "bending", "shear" */
  int         per_point; /* instances owned by a point: 2 (x and y) for traction and bending, 1 for shear */
  /* the patch's switch of the term: off, it is neither computed nor summed anywhere */
  PetscBool (*enabled)(const Patch *p);
  /* instance k (< per_point) owned by point (i,j) (global, owned or ghost within 1 of the owned
     patch): fills what want asks for and returns 1, or returns 0 if the instance does not exist
     (absent point, broken segment, crossing without a warp or weft neighbour) */
  int (*instance)(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, int k, int want, TermInstance *t);
  /* the forces of this term alone on the owned points of box (written, not added), by the row
     pipeline of ComputeInternalForces with the other terms off */
  void (*forces)(Patch *p, const PetscReal *x, const PetscInt box[4], PetscReal *f);
  /* adds the term's share of the bound at owned point (i,j) to *rs (and the pull-direction
     yarns' to *rp), as StableOmega2 sums them, for states within the patch's window (MODEL.md 7.3) */
  void (*bound_row)(const Patch *p, const PetscReal *x, PetscInt i, PetscInt j, int pull_dir, PetscReal *rs,
                    PetscReal *rp);
} ForceTerm;

extern const ForceTerm TractionTerm, BendingTerm, ShearTerm;
#define INTERNAL_TERMS 3
extern const ForceTerm *const InternalTerms[INTERNAL_TERMS]; /* traction, bending, shear */

/* energy of the instances owned by the points of box (global, half-open, owned): 0 if off */
PetscReal TermEnergy(const ForceTerm *t, const Patch *p, const PetscReal *x, const PetscInt box[4]);
/* the tangent of every instance owned by a point of box, one call of add per instance
   (its blocks reach ghost points within 1 of the box); nothing if the term is off. convex: each
   instance's positive part (TERM_CONVEX) */
PetscErrorCode TermTangent(const ForceTerm *t, const Patch *p, const PetscReal *x, const PetscInt box[4],
                           PetscBool convex, TermBlocksFn add, void *ctx);
/* the same summed over the three internal terms */
PetscReal      InternalEnergy(const Patch *p, const PetscReal *x, const PetscInt box[4]);
PetscErrorCode InternalTangent(const Patch *p, const PetscReal *x, const PetscInt box[4], PetscBool convex,
                               TermBlocksFn add, void *ctx);
/* the symmetric n x n matrix A (row-major, n <= 6) replaced by its positive part: its
   eigenvalues below 0 set to 0 (cyclic Jacobi rotations) */
void SymPositivePart(PetscInt n, PetscReal *A);
/* a TermBlocksFn for ctx = a Mat of the DMDA (DMCreateMatrix, dof 3, box stencil width 2):
   MatSetValuesBlockedStencil with ADD_VALUES (rows of ghost points go to their owners at assembly) */
PetscErrorCode TermBlocksAddToMat(void *ctx, PetscInt n, const PetscInt i[], const PetscInt j[], const PetscReal K[]);

/* The yarn law's derivative and integral (MODEL.md 5.1, 14). */
/* T[i] = ChordTension(y, e[i]), i < n, by the force rows' vectorised law (bit-identical to it), in
   the same clone as the force rows (FABRIC_WIDE: the widest the CPU runs) */
void ChordTensionLive(const YarnLaw *y, PetscInt n, const PetscReal *e, PetscReal *T);
/* dT/de of ChordTension: the blends' cubics, the pieces' slopes, the Hermite table's derivative */
PetscReal ChordTensionSlope(const YarnLaw *y, PetscReal e);
/* integral of ChordTension from 0 to e, exact (blends and Hermite cells integrate in closed form);
   integral: the law's table from PatchSetUp (Patch.yarn_integral), or NULL (slower: sums the cells) */
PetscReal ChordEnergy(const YarnLaw *y, const PetscReal *integral, PetscReal e);

/* the point fields of a frame on the owned points: mean warp and weft segment tension (N), shear angle (degrees) */
void PointFields(const Patch *p, const PetscReal *x, PetscReal *tw, PetscReal *tf, PetscReal *sh);

#endif
