/* static_options.h - the quasi-static solver's own options, and the checks of PETSc's solver options
 * that a run cannot take, made before it writes anything (static_options.c). */
#ifndef FABRIC_STATIC_OPTIONS_H
#define FABRIC_STATIC_OPTIONS_H

#include <petscsys.h>

typedef struct {                          /* the solver's own options (StaticOptionsRead) */
  PetscReal shift_start, shift_carry; /* the shift of a load step's first Newton step: see StaticSolve */
  PetscInt  order;                    /* of the first guess's extrapolation */
  PetscBool line_smoother;            /* multigrid levels smoothed by block lines (LineSmoother) */
  PetscBool convex;                   /* the terms' and bodies' positive parts in the tangent (TERM_CONVEX) */
  PetscReal line_lump;                /* each fine line's diagonal carries this times its couplings outside the star */
  PetscBool tao;                      /* minimise Pi by TAO (-static_minimizer tao) instead of SNES */
  PetscInt  tangent;                  /* the tangent's storage: TANGENT_STENCIL or TANGENT_AIJ (-static_tangent) */
  PetscBool tangent_set;              /* given by the user */
  PetscInt  sequence;                 /* coarser fabrics a load step is solved on first (-static_sequence) */
  PetscReal exact_below;              /* the exact tangent once the balance ratio is below this (-static_exact_tangent) */
} StaticOptions;

enum { TANGENT_STENCIL, TANGENT_AIJ };

/* the solver's own options: their defaults, then the options database's values */
PetscErrorCode StaticOptionsRead(MPI_Comm comm, StaticOptions *o);
/* the tangent by stencil serves the multigrid with the line smoother (its -pc_type, under TAO's prefix too) */
PetscBool StaticOptionsStencilFits(const StaticOptions *o);
/* the solver's own options (-snes_shift_start, -snes_shift_carry, -snes_extrapolate,
   -mg_line_smoother, -mg_line_lump, -snes_convex_tangent, -static_*): listed under -help, and their values,
   with PETSc's solver options this path cannot run, checked before a run writes anything */
PetscErrorCode StaticOptionsCheck(MPI_Comm comm);

#endif
