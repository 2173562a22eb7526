/* load.h - the load program (MODEL.md 6): travel, test time, grip paths and ramps (load.c). */
#ifndef FABRIC_LOAD_H
#define FABRIC_LOAD_H

#include "fabric.h"

/* total travel of what the load program moves, m: the jaw (its path's length) or the sphere */
PetscReal LoadTravel(const Scene *s);
/* the grip's displacement at length a along its path (-grip_path_mm), held at its end */
void PathPoint(const LoadProgram *lp, PetscReal a, PetscReal u[3]);
/* the grips' move from length `from` to length `to` along their path (the pull without a path) */
void GripPathMove(const Scene *s, const PetscReal pull_dir[3], PetscReal from, PetscReal to, PetscReal move[3]);
/* curve.csv's elongation at length disp along the grip's path: displacement along the pull / gauge */
PetscReal GripElongation(const Scene *s, const PetscReal pull_dir[3], PetscReal disp);
/* the test time of the load state, s */
PetscReal TestTime(const Scene *s, const LoadState *ls);
PetscReal TestTimeAt(const Scene *s, const LoadState *ls, PetscReal travel);
/* put the grips at length disp along their path (shift_history: also the paper scheme's x(n-1)) */
PetscErrorCode PlaceGrips(Fabric fab, PetscReal disp, PetscBool shift_history);
/* one te step of the grips' cosine ramp towards this load step's travel (no-op when done) */
PetscErrorCode RampGrips(Fabric fab);

#endif
