/* integrate.h - explicit integration (MODEL.md 7): forces, the stable step, one te step (integrate.c). */
#ifndef FABRIC_INTEGRATE_H
#define FABRIC_INTEGRATE_H

#include "fabric.h"

/* internal forces at the current positions on the owned points of box (NULL: all), the point
   load and the rigid bodies' contact */
PetscErrorCode ComputeForces(Fabric fab, const PetscInt box[4], PetscReal *tension_max);
/* the same at positions X into F (vectors of the grid's DMDA): the quasi-static path's trial states */
PetscErrorCode ComputeForcesAt(Fabric fab, Vec X, Vec F, const PetscInt box[4], PetscReal *tension_max);
/* te from the stable bound over the window of the current state (StableOmega2); the damping of
   the slowest mode */
PetscErrorCode StableStep(Fabric fab);
/* the damping of the slowest mode alone, at the current state (te kept; with -te_measure the
   bound and the measured limit there are recorded too) */
PetscErrorCode StableDamping(Fabric fab);
/* the bound again at the current state within a load step (damping and FIRE's state kept, FIRE's
   step at most te): for a te step that left the window, and as a tear starts and ends (a tear
   runs the damped scheme, with its te safety and window) */
PetscErrorCode StableStepAgain(Fabric fab);
/* te's window margin doubles at most this many times within a load step (StableStepRebound) */
#define WINDOW_GROW_MAX 5
/* one te step: forces, integration, the balance test and the stability watch */
PetscErrorCode TimeStep(Fabric fab, StepStats *st);

#endif
