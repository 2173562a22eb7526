/* predict.h - displacement prediction (MODEL.md 10): graph distances and the predicted move (predict.c). */
#ifndef FABRIC_PREDICT_H
#define FABRIC_PREDICT_H

#include "fabric.h"

#define DIST_INF 1e30
/* graph distance of every owned point to the points marked in source (one flag per owned point) */
PetscErrorCode GraphDistance(MPI_Comm comm, DM da, const Patch *p, const char *source, PetscReal *dist);
PetscErrorCode PredictSetUp(Fabric fab);
PetscErrorCode PredictLoadStep(Fabric fab, PetscReal grip_step, const PetscReal grip_move[3], PetscBool *moved);

#endif
