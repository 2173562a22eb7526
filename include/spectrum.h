/* spectrum.h - the true largest eigenvalue of M^-1 K at the current state (spectrum.c): the
 * measured stable limit that the bound of the stable step (MODEL.md 7.3) is checked
 * against. */
#ifndef FABRIC_SPECTRUM_H
#define FABRIC_SPECTRUM_H

#include "fabric.h"

/* omega_max^2 (rad^2/s^2): the largest eigenvalue of M^-1 K, K the tangent stiffness (the
   exact Hessian of the internal energy and the bodies' penalties) at the current positions
   between the free crossings (clamped, grip and absent ones held), by Lanczos on
   M^-1/2 K M^-1/2. The same bits on any number of ranks (exact sums). iterations: Lanczos
   steps taken (NULL: not wanted). */
PetscErrorCode TangentOmega2Max(Fabric fab, PetscReal *omega2, PetscInt *iterations);

/* -te_measure: measure the state StableStep has just bounded (te_prev: the te in use up to
   it) and keep it in fab->step's records, if this load step is due */
PetscErrorCode StableStepMeasure(Fabric fab, PetscReal te_prev);
PetscErrorCode StableStepMeasureLast(Fabric fab); /* -te_measure: the run's last state, the end of its last load step */

/* -te_measure with -info: the true limit at a tear's start or end (when), against the tear's te
   and bound, printed only (a tear is not a load step's record) */
PetscErrorCode StableStepMeasureTear(Fabric fab, const char *when);

#endif
