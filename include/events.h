/* events.h - the PetscLogEvents of a run, read with -log_view (events.c). */
#ifndef FABRIC_EVENTS_H
#define FABRIC_EVENTS_H

#include <petscsys.h>

extern PetscLogEvent EV_Force, EV_Integrate, EV_Halo, EV_Reduce, EV_Output, EV_Bound, EV_Predict, EV_Check;

PetscErrorCode EventsRegister(void);

#endif
