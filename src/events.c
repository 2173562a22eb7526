/* events.c - the PetscLogEvents of a run (-log_view shows where the time goes). */
#include "events.h"

PetscLogEvent EV_Force, EV_Integrate, EV_Halo, EV_Reduce, EV_Output, EV_Bound, EV_Predict, EV_Check;

PetscErrorCode EventsRegister(void)
{
  static PetscBool done = PETSC_FALSE;
  PetscClassId     id;

  PetscFunctionBeginUser;
  if (done) PetscFunctionReturn(0);
  PetscCall(PetscClassIdRegister("Fabric", &id));
  PetscCall(PetscLogEventRegister("FabricForce", id, &EV_Force));
  PetscCall(PetscLogEventRegister("FabricIntegrate", id, &EV_Integrate));
  PetscCall(PetscLogEventRegister("FabricHalo", id, &EV_Halo));
  PetscCall(PetscLogEventRegister("FabricReduce", id, &EV_Reduce));
  PetscCall(PetscLogEventRegister("FabricOutput", id, &EV_Output));
  PetscCall(PetscLogEventRegister("FabricStableStep", id, &EV_Bound));
  PetscCall(PetscLogEventRegister("FabricPredict", id, &EV_Predict));
  PetscCall(PetscLogEventRegister("FabricBalanceCheck", id, &EV_Check));
  done = PETSC_TRUE;
  PetscFunctionReturn(0);
}
