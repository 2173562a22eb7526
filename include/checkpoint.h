/* checkpoint.h - checkpoint and restart: a run killed at a wall-time limit continues exactly (checkpoint.c). */
#ifndef FABRIC_CHECKPOINT_H
#define FABRIC_CHECKPOINT_H

#include "frames.h"

/* 3: a checksum on every array; checkpoints within a load step (the relaxation's state) */
#define CHECKPOINT_VERSION 19 /* 19: the static path's checkpoints within a load step, at a Newton step; 18: a located break's state below and its counts (-break_locate_pct); 17: the checksum of the attributes of /; 16: -te_measure's records; 15: the crossings sleeping keeps awake; 14: a test's array default among the scene keys (the drape's -clamp_ring_mm 0,180); 13: whether the largest force came from balanced states, a yarn table's checksum; 12: the time of the load step's te steps, coarse Newton steps, the segments broken at the last converged state; 11: FIRE's sums' scales; 10: the static path's first guesses, shift and iteration counts; 9: the energy watch's held count, te's window doublings; 8: the stable step's window; 7: the balance hold and the energy watch; 6: FIRE's state; 5: the rupture state; 4: the scene keys from the option table; 3: checksums */
#define CHECKPOINT_STOPPED 3 /* exit status of a run stopped by SIGTERM or SIGUSR1 after its checkpoint */

typedef struct {        /* where the relaxation of a load step is (RelaxLoadStep) */
  PetscInt round;       /* re-relaxations after yarns broke, so far */
  PetscInt te_step;     /* te steps done in this round */
  PetscInt inner_steps; /* te steps of the rounds before (-solver static: Newton steps before this solve's attempt) */
  PetscInt newton;      /* -solver static (te_step 0): Newton steps of this solve's attempt */
} RelaxPoint;

PetscErrorCode CheckpointLoadStep(Fabric fab);
PetscErrorCode CheckpointTeStep(Fabric fab, const RelaxPoint *at);
PetscErrorCode CheckpointLoadStepLook(Fabric fab, PetscBool static_path);
PetscErrorCode CheckpointNewtonStep(Fabric fab, const RelaxPoint *at);
PetscErrorCode RestartLoad(Fabric fab);
PetscBool      CheckpointWithinLoadStep(Fabric fab, PetscInt k); /* restarted within load step k: the load step set */
PetscBool      CheckpointResumesLoadStep(void);                    /* restarted within a load step (no side effect) */
PetscBool      FabricHDF5File(const char *file, const char *attr); /* an HDF5 file whose root has attr (this rank) */
void           CheckpointRelaxStart(RelaxPoint *at);
PetscBool      CheckpointStopped(void);
void           CheckpointSignal(int sig); /* the handler of SIGTERM and SIGUSR1: sets a flag, nothing else */

#endif
