/* front.h - rank propagation and sleeping (MODEL.md 9): which points a te step computes (front.c). */
#ifndef FABRIC_FRONT_H
#define FABRIC_FRONT_H

#include "fabric.h"

PetscErrorCode FrontSetUp(Fabric fab);
void           FrontLoadChange(Fabric fab);
void           FrontWakeAll(Fabric fab);
/* the box of points to compute this te step (global and owned), and how many points it holds */
PetscInt64 FrontStepBox(Fabric fab, PetscInt global[4], PetscInt local[4]);

#endif
