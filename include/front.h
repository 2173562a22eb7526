/* front.h - rank propagation and sleeping (MODEL.md 9): which points a te step computes (front.c). */
#ifndef FABRIC_FRONT_H
#define FABRIC_FRONT_H

#include "fabric.h"

PetscErrorCode FrontSetUp(Fabric fab);
/* a load changed; predicted: the prediction moved every reachable point */
void FrontLoadChange(Fabric fab, PetscBool predicted);
void           FrontWakeAll(Fabric fab);
/* sleeping: the crossings in box (global) stay awake until FrontKeepReset (a new relaxation round). A
   crossing whose forces are small beside the largest tension falls asleep while its own balance still
   fails; the balance check per crossing finds it, and it then has the te steps it needs */
void FrontKeepAwake(Fabric fab, const PetscInt box[4]);
void FrontKeepReset(Fabric fab);
/* the box of points to compute this te step (global and owned), and how many points it holds */
PetscInt64 FrontStepBox(Fabric fab, PetscInt global[4], PetscInt local[4]);

#endif
