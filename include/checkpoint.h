/* checkpoint.h - checkpoint and restart: a run killed at a wall-time limit continues exactly (checkpoint.c). */
#ifndef FABRIC_CHECKPOINT_H
#define FABRIC_CHECKPOINT_H

#include "frames.h"

#define CHECKPOINT_VERSION 2 /* 2: body and clamp reactions in the curve rows, friction anchors, kinetic damping */

PetscErrorCode CheckpointLoadStep(Fabric fab);
PetscErrorCode RestartLoad(Fabric fab);

#endif
