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
 *   3-D points, nx x ny x 1): rank 0 writes it aside and renames it at the first frame and a restart,
 *   and after each later frame writes that frame's entry and the closing tags in place.
 * DIR/checkpoint.h5: everything a run needs to continue exactly (checkpoint.c).
 */
#ifndef FABRIC_FRAMES_H
#define FABRIC_FRAMES_H

#include "fabric.h"

typedef struct {       /* one frame of fabric.h5 */
  PetscReal time;      /* s: the load step's test time, plus the te of the te steps before the frame */
  PetscInt  load_step; /* 0: the rest state */
  PetscInt  te_step;   /* te steps into the load step when the frame was taken */
} FrameInfo;

struct _p_FabricIO {
  /* options */
  PetscInt output_every;                /* a frame every K load steps and at the last (0: none) */
  PetscInt output_te_every;             /* a frame every M te steps within a load step (0: none) */
  PetscInt output_tear_every;           /* a frame every M te steps of a tear (0: none) */
  PetscInt checkpoint_every;            /* DIR/checkpoint.h5 every K load steps (0: never) */
  char     restart[PETSC_MAX_PATH_LEN]; /* -restart FILE, "" for a fresh run */
  /* frames */
  DM         da1; /* dof 1, the layout of the grid's da: scalar point fields */
  PetscInt   frames, frames_cap;
  FrameInfo *frame;        /* every frame written so far (the same on all ranks) */
  PetscInt   te_load_step; /* load step of the te-frame counter */
  PetscInt64 te_base;      /* te_steps when that load step began */
  /* fabric.xmf */
  PetscInt    xmf_frames;   /* frames it lists (the same on all ranks) */
  PetscInt64 *xmf_at;       /* rank 0: where frame k's entry begins in it, k <= xmf_frames (the tail's at xmf_frames) */
  PetscInt    xmf_cap;      /* rank 0: xmf_at's length */
  /* which run the frames are of */
  char scene_hash[24]; /* fabric.h5's root attribute: a hash of what the run computes with (RestartLoad) */
  /* restart */
  PetscBool restarted;
  PetscInt  restart_load_step; /* the checkpoint's load steps done (summary.json's restarted_from) */
  PetscBool restart_within;    /* the checkpoint was taken within the load step after them */
  PetscBool frames_file_ours; /* DIR/fabric.h5 holds this run's frames before the checkpoint (rank 0 looked
                                 before any output was touched; RestartLoad) */
  PetscInt  checkpoints; /* DIR/checkpoint.h5 written by this run, of any kind (-checkpoint_every*, a signal) */
};
typedef struct _p_FabricIO *FabricIO;

/* what frames are taken of: parts of the fabric, lent by the driver (relax.c) */
typedef struct {
  MPI_Comm           comm;
  const FabricGrid  *grid; /* layout (da), size (patch.nx, ny), rest positions X0, point kinds, patch */
  Vec                X, V; /* positions, velocities */
  Vec                Xl;   /* ghosted positions: work space of the point fields */
  const SceneOutput *out;  /* output_dir, the scene's name */
} FrameSource;

/* frames.c */
/* the output state of frames and checkpoints, from the scene's output options */
PetscErrorCode IOSetUp(const SceneOutput *out, FabricIO *io);
PetscErrorCode IODestroy(FabricIO *io);
/* start of the run: a new fabric.h5 with frame `start` (the state the run starts from, te step 0),
   or after a restart the frames written before the checkpoint */
PetscErrorCode FramesOpen(FabricIO io, const FrameSource *src, const FrameInfo *start);
/* end of a load step: a frame every -output_every load steps and at the last one. f: the load step as
   curve.csv has it (test time, number, its te steps N'); with te or tear frames, or when it ended in a
   rupture (ruptured), at time + elapsed, the time its te steps took (a rupture's: summary.json's rupture
   time) */
PetscErrorCode FramesLoadStep(FabricIO io, const FrameSource *src, const FrameInfo *f, PetscReal elapsed,
                              PetscBool last, PetscBool ruptured);
/* after a te step: a frame every -output_te_every te steps. now: the test time (the load step's and
   its te steps'), the load step; te_steps: the run's te steps so far */
PetscErrorCode FramesTeStep(FabricIO io, const FrameSource *src, const FrameInfo *now, PetscInt64 te_steps);
/* within a tear (relax.c): a frame every -output_tear_every te steps, of now (test time, load step,
   te steps into the load step) */
PetscErrorCode FramesTearStep(FabricIO io, const FrameSource *src, const FrameInfo *now);
/* frames are asked for: at load steps, te steps or in tears */
static inline PetscBool IOWritesFrames(FabricIO io)
{
  return (io && (io->output_every > 0 || io->output_te_every > 0 || io->output_tear_every > 0)) ? PETSC_TRUE
                                                                                                : PETSC_FALSE;
}
/* the files of the run, for the closing message */
PetscErrorCode IODescribe(FabricIO io, const char *output_dir, PetscBool kept_checkpoint, char *buf, size_t len);
/* warp and weft tension and shear angle of each owned point (Xl: ghosted work vector of X) */
PetscErrorCode ComputePointFields(const FabricGrid *g, Vec X, Vec Xl, Vec warp_tension, Vec weft_tension,
                                  Vec shear_deg);
/* rank 0 writes DIR/fabric.xmf, the index of io's frames of an nx x ny grid */
PetscErrorCode FramesWriteXdmf(FabricIO io, MPI_Comm comm, const char *output_dir, PetscInt nx, PetscInt ny);
/* one more frame in io's list (a restart's frames) */
PetscErrorCode FramesAppend(FabricIO io, const FrameInfo *f);
/* a load step that leaves its own load to locate a break: its te-step frames from frame `from` on go */
PetscErrorCode FramesDropLoadStep(FabricIO io, const FrameSource *src, PetscInt load_step, PetscInt from);
/* DMDA vector v as dataset `name` of the HDF5 viewer's current group, in VecView's shape and type
   (ny x nx [x dof] float64, stored contiguous), collectively */
PetscErrorCode ViewDMDA(Vec v, const char *name, PetscViewer viewer);

#endif
