/* relax.h - the driver: load steps relaxed to balance with early exit (MODEL.md 8) (relax.c). */
#ifndef FABRIC_RELAX_H
#define FABRIC_RELAX_H

#include "fabric.h"

PetscErrorCode FabricRun(Fabric fab);
PetscErrorCode ApplyLoadStep(Fabric fab, PetscInt k);

#endif
