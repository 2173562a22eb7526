/* frames.h - results for ParaView (frames.c) and the output state shared with checkpoint.c.
 *
 * DIR/fabric.h5 (parallel HDF5 through PETSc's HDF5 viewer, every rank writes its own patch):
 *   /grid/rest_positions        (ny, nx, 3)  m, the rest state X0
 *   /grid/point_kind            (ny, nx)     0 free, 1 clamped, 2 grip, -1 absent
 *   /frames/NNNNNN/positions    (ny, nx, 3)  m
 *   /frames/NNNNNN/velocities   (ny, nx, 3)  m/s
 *   /frames/NNNNNN/displacement (ny, nx, 3)  m, positions - rest positions
 *   /frames/NNNNNN/warp_tension, weft_tension (ny, nx) N, shear_angle_deg (ny, nx) degrees
 *   attributes of a frame group: time_s, load_step, te_step (te steps into the load step)
 *   attributes of /: nx, ny, scene, frames (how many frames the file holds)
 * DIR/fabric.xmf: the XDMF index of those frames (a temporal collection of structured grids of
 *   3-D points, nx x ny x 1), rewritten by rank 0 after every frame (aside, then renamed).
 * DIR/checkpoint.h5: everything a run needs to continue exactly (checkpoint.c).
 */
#ifndef FABRIC_FRAMES_H
#define FABRIC_FRAMES_H

#include "fabric.h"

typedef struct {       /* one frame of fabric.h5 */
  PetscReal time;      /* s: the load step's test time, plus n te for a frame n te steps into it */
  PetscInt  load_step; /* 0: the rest state */
  PetscInt  te_step;   /* te steps into the load step when the frame was taken */
} FrameInfo;

struct _p_FabricIO {
  /* options */
  PetscInt output_every;                /* a frame every K load steps and at the last (0: none) */
  PetscInt output_te_every;             /* a frame every M te steps within a load step (0: none) */
  PetscInt checkpoint_every;            /* DIR/checkpoint.h5 every K load steps (0: never) */
  char     restart[PETSC_MAX_PATH_LEN]; /* -restart FILE, "" for a fresh run */
  /* frames */
  DM         da1; /* dof 1, the layout of fab->grid.da: scalar point fields */
  PetscInt   frames, frames_cap;
  FrameInfo *frame;        /* every frame written so far (the same on all ranks) */
  PetscInt   te_load_step; /* load step of the te-frame counter */
  PetscInt64 te_base;      /* te_steps when that load step began */
  /* restart */
  PetscBool restarted;
};
typedef struct _p_FabricIO *FabricIO;

/* frames.c */
PetscErrorCode IOSetUp(Fabric fab);
PetscErrorCode IODestroy(Fabric fab);
PetscErrorCode FramesOpen(Fabric fab);
PetscErrorCode FramesLoadStep(Fabric fab, const CurveRow *row);
PetscErrorCode FramesTeStep(Fabric fab);
PetscErrorCode IODescribe(Fabric fab, char *buf, size_t len);
PetscErrorCode ComputePointFields(Fabric fab, Vec warp_tension, Vec weft_tension, Vec shear_deg);
PetscErrorCode FramesWriteXdmf(Fabric fab);
PetscErrorCode FramesAppend(Fabric fab, const FrameInfo *f);

#endif
