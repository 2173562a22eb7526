/* frames.c - the results a user opens in ParaView: DIR/fabric.h5 and DIR/fabric.xmf (layout in frames.h).
 *
 * Frames are written collectively into PETSc's HDF5 viewer (ViewDMDA: VecView's shapes, without its
 * leak): each rank writes its own patch of the DMDA vectors in the natural (ny, nx, dof) layout,
 * nothing is gathered on one rank, so the file is the same on any number of ranks. fabric.h5 is
 * opened and closed for every frame: between frames it is complete. A frame's fields are flushed to
 * the file before the root attribute "frames" counts it: a run killed while writing one leaves the
 * count at the frames written whole (HDF5 orders its writes only at a flush). Rank 0 then adds the frame
 * to fabric.xmf: its entry and the closing tags in one write, in place (the whole index, aside and
 * renamed into place, at the first frame and after a restart), so the index names only complete
 * frames and a frame costs its own entry (rewriting the whole index made n frames cost n^2).
 *
 * Frames: the state at the start (rest, load step 0), then every -output_every K load steps and
 * the last load step, at the load step's test time time_s = grip travel / test speed (as in
 * curve.csv). With -output_te_every M (dynamic scenes) also every M te steps within each load
 * step, at time_s + the te of its te steps so far (te changes within a load step: after the
 * grips' jump, in a tear); a load step's own frame is then the one at its last te step, so that
 * the times of a load step's frames increase.
 *
 * The module never sees the Fabric: the driver lends what frames are taken of (FrameSource: the
 * communicator, the grid, the state vectors, the output options) and says where the run is
 * (FrameInfo: test time, load step, te step); FabricIO keeps the frame list and te-frame counter.
 *
 * Point fields (not on the hot path: computed here, per frame, from the ghosted positions):
 *   warp tension at a point: the mean chord tension T(e) (MODEL.md 5.1) of its intact warp
 *   (x) segments, 0 if it has none; weft tension likewise with the y segments;
 *   shear angle (degrees): asin(s), s = cos(angle(tw, tf)) with the warp tangent
 *   tw = x(i+1,j) - x(i-1,j) and weft tangent tf = x(i,j+1) - x(i,j-1), one-sided at an edge
 *   (MODEL.md 5.3, as kernels.c ComputeShearRow); 0 at a point without a warp or a weft neighbour.
 */
#include "frames.h"
#include "comm.h"
#include "events.h"
#include "revision.h"

#include <fcntl.h>
#include <math.h>
#include <petscviewerhdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* the output state of frames and checkpoints, from the scene's output options */
PetscErrorCode IOSetUp(const SceneOutput *out, FabricIO *pio)
{
  FabricIO io;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&io));
  io->output_every     = out->output_every;
  io->output_te_every  = out->output_te_every;
  io->output_tear_every = out->output_tear_every;
  io->checkpoint_every = out->checkpoint_every;
  PetscCall(PetscStrncpy(io->restart, out->restart, sizeof io->restart));
  io->te_load_step = -1;
  io->xmf_frames   = -1; /* none written yet */
  *pio             = io;
  PetscFunctionReturn(0);
}

PetscErrorCode IODestroy(FabricIO *pio)
{
  FabricIO io = *pio;

  PetscFunctionBeginUser;
  if (!io) PetscFunctionReturn(0);
  PetscCall(DMDestroy(&io->da1));
  PetscCall(PetscFree(io->frame));
  free(io->xmf_at);
  PetscCall(PetscFree(*pio));
  PetscFunctionReturn(0);
}

static PetscBool FramesOn(FabricIO io, const char *output_dir)
{
  return (output_dir[0] && IOWritesFrames(io)) ? PETSC_TRUE : PETSC_FALSE;
}

PetscErrorCode ComputePointFields(const FabricGrid *g, Vec X, Vec Xl, Vec warp_tension, Vec weft_tension, Vec shear_deg)
{
  const Patch       *p = &g->patch;
  const PetscScalar *x;
  PetscScalar       *tw, *tf, *sh;

  PetscFunctionBeginUser;
  PetscCall(HaloExchange(g->da, X, Xl));
  PetscCall(VecGetArrayRead(Xl, &x));
  PetscCall(VecGetArray(warp_tension, &tw));
  PetscCall(VecGetArray(weft_tension, &tf));
  PetscCall(VecGetArray(shear_deg, &sh));
  PointFields(p, x, tw, tf, sh);
  PetscCall(VecRestoreArray(shear_deg, &sh));
  PetscCall(VecRestoreArray(weft_tension, &tf));
  PetscCall(VecRestoreArray(warp_tension, &tw));
  PetscCall(VecRestoreArrayRead(Xl, &x));
  PetscFunctionReturn(0);
}

/* ------------------------------------------------------------------ fabric.h5 */

#if defined(PETSC_USE_COMPLEX) || !defined(PETSC_USE_REAL_DOUBLE)
  #error "ViewDMDA writes PetscScalar as a real double"
#endif

/* an HDF5 call of ViewDMDA that failed (a negative id or status): the dataset named */
#define H5CALL(comm, call, what, name) \
  PetscCheck((call) >= 0, comm, PETSC_ERR_LIB, "HDF5 could not %s of dataset %s", what, name)

/* DMDA vector v as dataset `name` of the viewer's current group, in the shape and type VecView gives
   it (float64, ny x nx, or ny x nx x dof; contiguous, where VecView chunks it), each rank's patch by
   one collective hyperslab write; a dataset of the name already there is written over. Not VecView:
   PETSc 3.18's (VecView_MPI_HDF5_DA) leaves each new dataset's creation property list open, about
   3 KB held to the end of the run, 20 KB a frame (the heap grew from 49 to 111 MB over 3200 frames
   of a small strip). */
PetscErrorCode ViewDMDA(Vec v, const char *name, PetscViewer viewer)
{
  MPI_Comm           comm;
  DM                 da;
  PetscInt           M, N, dof, xs, ys, xm, ym;
  hid_t              fid, gid, fspace, mspace, dset, dxpl;
  hsize_t            dims[3], count[3], offset[3] = {0, 0, 0};
  int                ndim;
  const PetscScalar *x;
  herr_t             st;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject) v, &comm));
  PetscCall(VecGetDM(v, &da));
  PetscCheck(da, comm, PETSC_ERR_ARG_WRONG, "ViewDMDA: vector for dataset %s has no DMDA", name);
  PetscCall(DMDAGetInfo(da, NULL, &M, &N, NULL, NULL, NULL, NULL, &dof, NULL, NULL, NULL, NULL, NULL));
  PetscCall(DMDAGetCorners(da, &xs, &ys, NULL, &xm, &ym, NULL));
  ndim      = dof > 1 ? 3 : 2;
  dims[0] = (hsize_t) N, dims[1] = (hsize_t) M, dims[2] = (hsize_t) dof;
  count[0] = (hsize_t) ym, count[1] = (hsize_t) xm, count[2] = (hsize_t) dof;
  offset[0] = (hsize_t) ys, offset[1] = (hsize_t) xs;
  PetscCall(PetscViewerHDF5OpenGroup(viewer, NULL, &fid, &gid));
  H5CALL(comm, fspace = H5Screate_simple(ndim, dims, NULL), "make the file space", name);
  if (H5Lexists(gid, name, H5P_DEFAULT) > 0)
    H5CALL(comm, dset = H5Dopen2(gid, name, H5P_DEFAULT), "open", name);
  else
    H5CALL(comm, dset = H5Dcreate2(gid, name, H5T_IEEE_F64LE, fspace, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
           "create", name);
  H5CALL(comm, mspace = H5Screate_simple(ndim, count, NULL), "make the memory space", name);
  if (xm * ym > 0) H5CALL(comm, H5Sselect_hyperslab(fspace, H5S_SELECT_SET, offset, NULL, count, NULL), "select", name);
  else H5CALL(comm, H5Sselect_none(fspace), "select", name);
  H5CALL(comm, dxpl = H5Pcreate(H5P_DATASET_XFER), "make the transfer list", name);
  H5CALL(comm, H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE), "set the collective transfer", name);
  PetscCall(VecGetArrayRead(v, &x));
  st = H5Dwrite(dset, H5T_NATIVE_DOUBLE, mspace, fspace, dxpl, x);
  PetscCall(VecRestoreArrayRead(v, &x));
  H5CALL(comm, st, "write", name);
  H5CALL(comm, H5Pclose(dxpl), "close the transfer list", name);
  H5CALL(comm, H5Sclose(mspace), "close the memory space", name);
  H5CALL(comm, H5Sclose(fspace), "close the file space", name);
  H5CALL(comm, H5Dclose(dset), "close", name);
  if (gid != fid) H5CALL(comm, H5Gclose(gid), "close the group", name);
  PetscFunctionReturn(0);
}

/* a new fabric.h5: the grid (rest positions, point kinds) and what the file is */
static PetscErrorCode CreateFile(FabricIO io, const FrameSource *src, const char *file)
{
  const FabricGrid *g = src->grid;
  const Patch      *p = &g->patch;
  PetscViewer       v;
  Vec               kind;
  PetscScalar      *a;
  int               nx = (int) p->nx, ny = (int) p->ny, zero = 0;

  PetscFunctionBeginUser;
  if (!io->da1) PetscCall(DMDACreateCompatibleDMDA(g->da, 1, &io->da1));
  PetscCall(DMGetGlobalVector(io->da1, &kind));
  PetscCall(VecGetArray(kind, &a));
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
    for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
      const PetscInt q = (j - p->ys) * p->xm + (i - p->xs);
      a[q]             = p->exists[(j - p->gys) * p->gxm + (i - p->gxs)] ? (PetscReal) g->kind[q] : -1.0;
    }
  PetscCall(VecRestoreArray(kind, &a));
  PetscCall(PetscViewerHDF5Open(src->comm, file, FILE_MODE_WRITE, &v));
  PetscCall(PetscViewerHDF5PushGroup(v, "/grid"));
  PetscCall(ViewDMDA(g->X0, "rest_positions", v));
  PetscCall(ViewDMDA(kind, "point_kind", v));
  PetscCall(PetscViewerHDF5PopGroup(v));
  PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "nx", PETSC_INT, &nx));
  PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "ny", PETSC_INT, &ny));
  PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "scene", PETSC_STRING, src->out->name));
  PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "fabric_revision", PETSC_STRING, FabricRevision()));
  PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "scene_hash", PETSC_STRING, io->scene_hash));
  PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "frames", PETSC_INT, &zero));
  PetscCall(PetscViewerDestroy(&v));
  PetscCall(DMRestoreGlobalVector(io->da1, &kind));
  PetscFunctionReturn(0);
}

PetscErrorCode FramesAppend(FabricIO io, const FrameInfo *f)
{
  PetscFunctionBeginUser;
  if (io->frames == io->frames_cap) {
    FrameInfo *grown;
    io->frames_cap = PetscMax(16, 2 * io->frames_cap);
    PetscCall(PetscMalloc1(io->frames_cap, &grown));
    if (io->frames) PetscCall(PetscArraycpy(grown, io->frame, io->frames));
    PetscCall(PetscFree(io->frame));
    io->frame = grown;
  }
  io->frame[io->frames++] = *f;
  PetscFunctionReturn(0);
}

static PetscErrorCode FramesXdmfLast(FabricIO io, MPI_Comm comm, const char *dir, PetscInt nx, PetscInt ny);

/* write the current state as frame f; a frame of the same load step and te step as the last
   one replaces it (the te frame at a load step's last te step is also the load step's frame) */
static PetscErrorCode WriteFrame(FabricIO io, const FrameSource *src, const FrameInfo *f)
{
  const FabricGrid *g   = src->grid;
  const char       *dir = src->out->output_dir;
  PetscViewer       v;
  Vec               disp, tw, tf, sh;
  char              file[PETSC_MAX_PATH_LEN], group[64];
  PetscInt          index = io->frames;
  hid_t             fid;
  int               flushed, count, load_step = (int) f->load_step, te_step = (int) f->te_step;

  PetscFunctionBeginUser;
  if (io->frames && io->frame[io->frames - 1].load_step == f->load_step &&
      io->frame[io->frames - 1].te_step == f->te_step)
    index = io->frames - 1;
  PetscCall(PetscLogEventBegin(EV_Output, 0, 0, 0, 0));
  PetscCall(DMGetGlobalVector(g->da, &disp));
  PetscCall(DMGetGlobalVector(io->da1, &tw));
  PetscCall(DMGetGlobalVector(io->da1, &tf));
  PetscCall(DMGetGlobalVector(io->da1, &sh));
  PetscCall(VecWAXPY(disp, -1.0, g->X0, src->X));
  PetscCall(ComputePointFields(g, src->X, src->Xl, tw, tf, sh));

  PetscCall(PetscSNPrintf(file, sizeof file, "%s/fabric.h5", dir));
  PetscCall(PetscSNPrintf(group, sizeof group, "/frames/%06" PetscInt_FMT, index));
  PetscCall(PetscViewerHDF5Open(src->comm, file, FILE_MODE_APPEND, &v));
  PetscCall(PetscViewerHDF5PushGroup(v, group));
  PetscCall(ViewDMDA(src->X, "positions", v));
  PetscCall(ViewDMDA(src->V, "velocities", v));
  PetscCall(ViewDMDA(disp, "displacement", v));
  PetscCall(ViewDMDA(tw, "warp_tension", v));
  PetscCall(ViewDMDA(tf, "weft_tension", v));
  PetscCall(ViewDMDA(sh, "shear_angle_deg", v));
  PetscCall(PetscViewerHDF5WriteAttribute(v, NULL, "time_s", PETSC_REAL, &f->time));
  PetscCall(PetscViewerHDF5WriteAttribute(v, NULL, "load_step", PETSC_INT, &load_step));
  PetscCall(PetscViewerHDF5WriteAttribute(v, NULL, "te_step", PETSC_INT, &te_step));
  PetscCall(PetscViewerHDF5PopGroup(v));
  PetscCall(PetscViewerHDF5GetFileId(v, &fid));
  flushed = H5Fflush(fid, H5F_SCOPE_GLOBAL) >= 0;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &flushed, 1, MPI_INT, MPI_MIN, src->comm));
  PetscCheck(flushed, src->comm, PETSC_ERR_FILE_WRITE, "-output_dir %s: cannot write %s", dir, file);
  count = (int) index + 1;
  PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "frames", PETSC_INT, &count));
  PetscCall(PetscViewerDestroy(&v));

  PetscCall(DMRestoreGlobalVector(io->da1, &sh));
  PetscCall(DMRestoreGlobalVector(io->da1, &tf));
  PetscCall(DMRestoreGlobalVector(io->da1, &tw));
  PetscCall(DMRestoreGlobalVector(g->da, &disp));
  io->frames = index;
  PetscCall(FramesAppend(io, f));
  PetscCall(FramesXdmfLast(io, src->comm, dir, g->patch.nx, g->patch.ny));
  PetscCall(PetscLogEventEnd(EV_Output, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* After a restart: drop the frames the interrupted run wrote after its checkpoint (they are
   written again) and count the frames before it that the file holds. Rank 0 does it alone,
   through serial HDF5 (metadata only), before the ranks open the file together again. */
static PetscErrorCode DropFramesFrom(MPI_Comm comm, const char *why, const char *file, PetscInt first,
                                     PetscInt *kept)
{
  int         status[2] = {0, 0}; /* frames kept, failed */
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCall(CommRank(comm, &rank));
  if (rank == 0) {
    H5E_auto2_t efunc;
    void       *edata;
    hid_t       fid, g;
    H5G_info_t  info;
    char        name[64];
    int         count = (int) first;

    H5Eget_auto2(H5E_DEFAULT, &efunc, &edata);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    fid = H5Fopen(file, H5F_ACC_RDWR, H5P_DEFAULT);
    if (fid < 0)
      status[1] = 1;
    else {
      if (H5Lexists(fid, "/frames", H5P_DEFAULT) > 0 && (g = H5Gopen2(fid, "/frames", H5P_DEFAULT)) >= 0) {
        if (H5Gget_info(g, &info) >= 0) {
          /* by name in decreasing order, so that deleting a link does not move the ones to come */
          for (hsize_t l = info.nlinks; l-- > 0;) {
            char *end;
            long  index;
            if (H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, l, name, sizeof name, H5P_DEFAULT) < 0) {
              status[1] = 1;
              continue;
            }
            index = strtol(name, &end, 10);
            if (*end || index < 0) continue; /* not a frame (RestartLoad refused such a file) */
            if (index < first)
              status[0]++;
            else if (H5Ldelete(g, name, H5P_DEFAULT) < 0)
              status[1] = 1;
          }
        } else
          status[1] = 1;
        H5Gclose(g);
      }
      {
        hid_t a = H5Aopen(fid, "frames", H5P_DEFAULT);
        if (a < 0 || H5Awrite(a, H5T_NATIVE_INT, &count) < 0) status[1] = 1;
        if (a >= 0) H5Aclose(a);
      }
      if (H5Fclose(fid) < 0) status[1] = 1;
    }
    H5Eset_auto2(H5E_DEFAULT, efunc, edata);
  }
  PetscCall(BroadcastFromRoot(comm, status, 2, MPI_INT));
  PetscCheck(!status[1], comm, PETSC_ERR_FILE_WRITE, "%s: cannot remove them from %s", why, file);
  *kept = status[0];
  PetscFunctionReturn(0);
}

/* a restart: fabric.h5 and fabric.xmf keep the frames written before the checkpoint, no later one */
static PetscErrorCode DropFramesAfterCheckpoint(FabricIO io, const FrameSource *src, const char *file)
{
  PetscInt kept;
  char     why[PETSC_MAX_PATH_LEN + 64];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(why, sizeof why, "-restart %s: the frames written after the checkpoint", io->restart));
  PetscCall(DropFramesFrom(src->comm, why, file, io->frames, &kept));
  PetscCheck(kept == io->frames, src->comm, PETSC_ERR_FILE_UNEXPECTED,
             "-restart %s: %s holds %" PetscInt_FMT " of the %" PetscInt_FMT
             " frames written before the checkpoint: it is not the file of this run",
             io->restart, file, kept, io->frames);
  PetscCall(FramesWriteXdmf(io, src->comm, src->out->output_dir, src->grid->patch.nx, src->grid->patch.ny));
  PetscFunctionReturn(0);
}

/* A load step that leaves its own load to locate a break (relax.c LocateBreak): its te-step frames since the state
   the location starts from (frame `from` on) showed the relaxation to a load the break came before, so they go (the
   frames that follow are of the located path) */
PetscErrorCode FramesDropLoadStep(FabricIO io, const FrameSource *src, PetscInt load_step, PetscInt from)
{
  const char *dir   = src->out->output_dir;
  PetscInt    first = io ? io->frames : 0, kept;
  char        file[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  if (!io || !FramesOn(io, dir)) PetscFunctionReturn(0);
  while (first > from && first > 1 && io->frame[first - 1].load_step == load_step) first--; /* frame 0 stays: a restart's
                                                                                              first, earlier than any */
  if (first == io->frames) PetscFunctionReturn(0);
  PetscCall(PetscSNPrintf(file, sizeof file, "%s/fabric.h5", dir));
  PetscCall(DropFramesFrom(src->comm, "a located break: the te-step frames of its load step", file, first, &kept));
  io->frames = kept;
  PetscCall(FramesWriteXdmf(io, src->comm, dir, src->grid->patch.nx, src->grid->patch.ny));
  PetscFunctionReturn(0);
}

/* Start of the run: a new fabric.h5 with the state at the start as frame 0, or, after a
   restart, the frames written before the checkpoint (also when this run writes none). */
PetscErrorCode FramesOpen(FabricIO io, const FrameSource *src, const FrameInfo *start)
{
  const char *dir = src->out->output_dir;
  char        file[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  if (dir[0]) PetscCall(PetscSNPrintf(file, sizeof file, "%s/fabric.h5", dir));
  if (!FramesOn(io, dir)) { /* a restart that writes no frames: those the stopped run wrote after its checkpoint go,
                               from its own file only (one that is damaged or another run's is left alone) */
    if (dir[0] && io->restarted && io->frames > 0 && io->frames_file_ours)
      PetscCall(DropFramesAfterCheckpoint(io, src, file));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscLogEventBegin(EV_Output, 0, 0, 0, 0));
  if (!io->da1) PetscCall(DMDACreateCompatibleDMDA(src->grid->da, 1, &io->da1));
  if (io->restarted && io->frames > 0) PetscCall(DropFramesAfterCheckpoint(io, src, file));
  else {
    io->frames = 0;
    PetscMPIInt rank;
    PetscCall(CommRank(src->comm, &rank));
    if (rank == 0) { /* the earlier run's index goes with its fabric.h5, which CreateFile replaces: this run writes its
                         own after its first frame, and one stopped before it left that index beside its new file */
      char xmf[PETSC_MAX_PATH_LEN];
      PetscCall(PetscSNPrintf(xmf, sizeof xmf, "%s/fabric.xmf", dir));
      (void) unlink(xmf);
    }
    PetscCall(CreateFile(io, src, file));
    PetscCall(WriteFrame(io, src, start));
  }
  PetscCall(PetscLogEventEnd(EV_Output, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* End of a load step (f: as curve.csv has it): a frame every -output_every load steps and at the last one; with
   te frames, the one of its last te step (elapsed: the time its te steps took); a rupture's at the time the
   test ended, its tear's end */
PetscErrorCode FramesLoadStep(FabricIO io, const FrameSource *src, const FrameInfo *f, PetscReal elapsed,
                              PetscBool last, PetscBool ruptured)
{
  FrameInfo at = *f;

  PetscFunctionBeginUser;
  if (!FramesOn(io, src->out->output_dir) || !io->output_every) PetscFunctionReturn(0);
  if (f->load_step % io->output_every && !last && !ruptured) PetscFunctionReturn(0);
  if (io->output_te_every || io->output_tear_every || ruptured || /* after its te and tear frames, also those */
      (io->frames && io->frame[io->frames - 1].time >= f->time)) /* before a restart that turned them off */
    at.time += elapsed;
  PetscCall(WriteFrame(io, src, &at));
  PetscFunctionReturn(0);
}

/* After each te step (RelaxLoadStep; now: the test time and load step, te_steps: the run's te steps so far): a
   frame every -output_te_every te steps of the load step */
PetscErrorCode FramesTeStep(FabricIO io, const FrameSource *src, const FrameInfo *now, PetscInt64 te_steps)
{
  FrameInfo f;
  PetscInt  n;

  PetscFunctionBeginUser;
  if (!io) PetscFunctionReturn(0);
  if (now->load_step != io->te_load_step) { /* the first te step of a load step; counted with the frames off
                                               too, so that a restart within it that turns them on counts right */
    io->te_load_step = now->load_step;
    io->te_base      = te_steps - 1;
  }
  if (!io->output_te_every || !FramesOn(io, src->out->output_dir)) PetscFunctionReturn(0);
  n = (PetscInt) (te_steps - io->te_base);
  if (n % io->output_te_every) PetscFunctionReturn(0);
  f         = *now;
  f.te_step = n;
  PetscCall(WriteFrame(io, src, &f));
  PetscFunctionReturn(0);
}

PetscErrorCode FramesTearStep(FabricIO io, const FrameSource *src, const FrameInfo *now)
{
  PetscFunctionBeginUser;
  if (!FramesOn(io, src->out->output_dir)) PetscFunctionReturn(0);
  PetscCall(WriteFrame(io, src, now));
  PetscFunctionReturn(0);
}

/* ------------------------------------------------------------------ fabric.xmf */

/* One layer of a 3-D structured grid: ParaView's Xdmf2 reader does not read the vector
   attributes of a 2DSMesh, and all its XDMF readers read this (nx x ny x 1 points) */
static void XdmfItem(FILE *fp, const char *indent, PetscInt nx, PetscInt ny, int dof, const char *path)
{
  if (dof > 1)
    fprintf(fp,
            "%s<DataItem Dimensions=\"1 %" PetscInt_FMT " %" PetscInt_FMT
            " %d\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">fabric.h5:%s</DataItem>\n",
            indent, ny, nx, dof, path);
  else
    fprintf(fp,
            "%s<DataItem Dimensions=\"1 %" PetscInt_FMT " %" PetscInt_FMT
            "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">fabric.h5:%s</DataItem>\n",
            indent, ny, nx, path);
}

static const char xdmf_tail[] = "    </Grid>\n  </Domain>\n</Xdmf>\n";

/* frame k's entry of the index */
static void XdmfFrame(FILE *fp, const FrameInfo *f, PetscInt k, PetscInt nx, PetscInt ny)
{
  static const struct {
    const char *name, *type;
    int         dof;
  } field[] = {
      {"velocities", "Vector", 3},   {"displacement", "Vector", 3},    {"warp_tension", "Scalar", 1},
      {"weft_tension", "Scalar", 1}, {"shear_angle_deg", "Scalar", 1},
  };
  char path[128];

  fprintf(fp, "      <Grid Name=\"frame_%06" PetscInt_FMT "\" GridType=\"Uniform\">\n", k);
  fprintf(fp, "        <Time TimeType=\"Single\" Value=\"%.17g\"/>\n", (double) f->time);
  fprintf(fp,
          "        <Information Name=\"load_step\" Value=\"%" PetscInt_FMT
          "\"/>\n        <Information Name=\"te_step\" Value=\"%" PetscInt_FMT "\"/>\n",
          f->load_step, f->te_step);
  fprintf(fp, "        <Topology TopologyType=\"3DSMesh\" Dimensions=\"1 %" PetscInt_FMT " %" PetscInt_FMT "\"/>\n",
          ny, nx);
  fprintf(fp, "        <Geometry GeometryType=\"XYZ\">\n");
  snprintf(path, sizeof path, "/frames/%06" PetscInt_FMT "/positions", k);
  XdmfItem(fp, "          ", nx, ny, 3, path);
  fprintf(fp, "        </Geometry>\n");
  for (size_t a = 0; a < sizeof field / sizeof field[0]; a++) {
    fprintf(fp, "        <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\">\n", field[a].name, field[a].type);
    snprintf(path, sizeof path, "/frames/%06" PetscInt_FMT "/%s", k, field[a].name);
    XdmfItem(fp, "          ", nx, ny, field[a].dof, path);
    fprintf(fp, "        </Attribute>\n");
  }
  fprintf(fp, "        <Attribute Name=\"point_kind\" AttributeType=\"Scalar\" Center=\"Node\">\n");
  XdmfItem(fp, "          ", nx, ny, 1, "/grid/point_kind");
  fprintf(fp, "        </Attribute>\n      </Grid>\n");
}

/* xmf_at holds at least n entries (rank 0); 0 when it cannot */
static int XmfAtFits(FabricIO io, PetscInt n)
{
  if (n > io->xmf_cap) {
    const PetscInt cap   = PetscMax(16, 2 * n);
    PetscInt64    *grown = realloc(io->xmf_at, (size_t) cap * sizeof *grown);
    if (!grown) return 0;
    io->xmf_at = grown, io->xmf_cap = cap;
  }
  return 1;
}

/* Rank 0 writes the XDMF index of the frames aside, then renames it into place, and keeps where
   each frame's entry begins (xmf_at), so that a later frame's entry is written in place. */
PetscErrorCode FramesWriteXdmf(FabricIO io, MPI_Comm comm, const char *dir, PetscInt nx, PetscInt ny)
{
  int         ok = 1;
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCall(CommRank(comm, &rank));
  if (rank == 0) {
    char  file[PETSC_MAX_PATH_LEN], tmp[PETSC_MAX_PATH_LEN];
    FILE *fp = NULL;
    PetscCall(PetscSNPrintf(file, sizeof file, "%s/fabric.xmf", dir));
    PetscCall(PetscSNPrintf(tmp, sizeof tmp, "%s/.fabric.xmf.tmp", dir));
    ok = XmfAtFits(io, io->frames + 1) && (fp = fopen(tmp, "w")) != NULL;
    if (ok) {
      fprintf(fp,
              "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"2.0\">\n  <Domain>\n");
      fprintf(fp, "    <Grid Name=\"fabric\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
      for (PetscInt k = 0; k <= io->frames; k++) {
        io->xmf_at[k] = (PetscInt64) ftell(fp);
        if (k < io->frames) XdmfFrame(fp, &io->frame[k], k, nx, ny);
      }
      fputs(xdmf_tail, fp);
      ok = !ferror(fp);
      ok = !fclose(fp) && ok;
      ok = ok && !rename(tmp, file);
    }
  }
  PetscCall(BroadcastFromRoot(comm, &ok, 1, MPI_INT));
  PetscCheck(ok, comm, PETSC_ERR_FILE_WRITE, "-output_dir %s: cannot write fabric.xmf", dir);
  io->xmf_frames = io->frames;
  PetscFunctionReturn(0);
}

/* Rank 0: frame k's entry and the closing tags in one write where the entry begins (after the
   entries before it, or over the entry of the frame it replaces, when the new one is no shorter:
   the file never shrinks, so no byte of the old end is left after the new closing tags). 0 when
   it does not (a shorter entry, no file to write into: the whole index then, as a restart
   writes it, so that the index does not depend on the run's history). */
static int XdmfWriteLast(FabricIO io, const char *file, PetscInt k, PetscInt nx, PetscInt ny)
{
  const size_t tail = sizeof xdmf_tail - 1;
  const size_t old  = k < io->xmf_frames ? (size_t) (io->xmf_at[k + 1] - io->xmf_at[k]) : 0;
  char        *text = NULL;
  size_t       len  = 0;
  FILE        *mem;
  int          ok, fd;

  if (!XmfAtFits(io, k + 2) || !(mem = open_memstream(&text, &len))) return 0;
  XdmfFrame(mem, &io->frame[k], k, nx, ny);
  fputs(xdmf_tail, mem);
  ok = !ferror(mem);
  ok = !fclose(mem) && ok && len >= tail + old;
  if (ok) {
    ok = (fd = open(file, O_WRONLY | O_CLOEXEC)) >= 0;
    ok = ok && pwrite(fd, text, len, (off_t) io->xmf_at[k]) == (ssize_t) len;
    if (fd >= 0) ok = !close(fd) && ok;
  }
  if (ok) io->xmf_at[k + 1] = io->xmf_at[k] + (PetscInt64) (len - tail);
  free(text);
  return ok;
}

/* The index after the frame io->frames - 1 was written: a frame costs its own entry, not the
   whole index (XdmfWriteLast). The whole index is written aside (FramesWriteXdmf) when this run
   has not written the entries before it, or the entry was not written in place. */
static PetscErrorCode FramesXdmfLast(FabricIO io, MPI_Comm comm, const char *dir, PetscInt nx, PetscInt ny)
{
  int         ok = 0;
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  if (io->xmf_frames >= 0 && io->xmf_frames >= io->frames - 1) { /* the same on every rank */
    PetscCall(CommRank(comm, &rank));
    if (rank == 0) {
      char file[PETSC_MAX_PATH_LEN];
      PetscCall(PetscSNPrintf(file, sizeof file, "%s/fabric.xmf", dir));
      ok = XdmfWriteLast(io, file, io->frames - 1, nx, ny);
    }
    PetscCall(BroadcastFromRoot(comm, &ok, 1, MPI_INT));
  }
  if (ok) io->xmf_frames = io->frames;
  else PetscCall(FramesWriteXdmf(io, comm, dir, nx, ny));
  PetscFunctionReturn(0);
}

/* the files of the run, for the closing message */
PetscErrorCode IODescribe(FabricIO io, const char *output_dir, PetscBool kept_checkpoint, char *buf, size_t len)
{
  size_t n;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(buf, len, "curve.csv, summary.json"));
  if (FramesOn(io, output_dir)) {
    PetscCall(PetscStrlen(buf, &n));
    PetscCall(PetscSNPrintf(buf + n, len - n, ", fabric.h5 and fabric.xmf (%" PetscInt_FMT " frames)", io->frames));
  } else if (io && output_dir[0] && io->restarted && io->frames > 0 && io->frames_file_ours) { /* FramesOpen kept them */
    PetscCall(PetscStrlen(buf, &n));
    PetscCall(PetscSNPrintf(buf + n, len - n, ", fabric.h5 and fabric.xmf (%" PetscInt_FMT " frames, from before the checkpoint)",
                            io->frames));
  }
  if (kept_checkpoint || (io && io->checkpoints)) { /* one this run wrote (also by -checkpoint_every_te or _s), or
                                                      the restart's own: not a -checkpoint_every past the last load step */
    PetscCall(PetscStrlen(buf, &n));
    PetscCall(PetscSNPrintf(buf + n, len - n, ", checkpoint.h5"));
  }
  PetscFunctionReturn(0);
}
