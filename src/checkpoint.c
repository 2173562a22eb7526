/* checkpoint.c - checkpoint and restart: a run killed at a wall-time limit continues exactly.
 *
 * -checkpoint_every K writes DIR/checkpoint.h5 every K load steps, collectively through PETSc's
 * HDF5 viewer, aside (DIR/.checkpoint.h5.tmp) and then renamed into place, so checkpoint.h5 is
 * always a complete checkpoint. It holds everything the run depends on:
 *   /state    positions, velocities, the paper integrator's positions_old and velocities_old,
 *             the extrapolation history converged_positions(_prev) when allocated, and the
 *             broken segments (dof 2 on the grid: segment to i+1 and to j+1 of each point),
 *             the friction anchors of each body (-friction_mu > 0);
 *   /history  curve (21 numbers per load step done: the rows of curve.csv and the balance flag),
 *             frames (time, load step, te step of each frame of fabric.h5);
 *   /scene    what the run computes with (grid, yarns, load program, numerics): a restart
 *             with another scene or grid is refused;
 *   /         load step, grip travel and last grip step, te steps, point updates, the
 *             converged and broken flags, frames, wall time, the kinetic damping's last kinetic
 *             energy and reset count, and the largest |value| of every
 *             state vector (checked after reading: a damaged file is refused).
 * -restart FILE reads it back: rank 0 checks the file alone first (so that a damaged or
 * foreign file gives one clear message on every rank, never a hang), then all ranks read the
 * vectors collectively. The ghosted broken flags are rebuilt from their owned part with one
 * global-to-local exchange. The state is restored bit for bit, so the run continues as if it
 * had never stopped.
 */
#include "checkpoint.h"
#include "measure.h"
#include "comm.h"
#include "events.h"
#include "load.h"

#include <fcntl.h>
#include <petscviewerhdf5.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#define MAX_KEYS  320
#define MAX_STATE 12 /* state vectors (StateVecs) */

typedef struct {
  char      name[40];
  PetscReal value;
} SceneKey;

#define KEY(nm, v) (PetscStrncpy(key[n].name, nm, sizeof key[n].name), key[n].value = (PetscReal) (v), n++)
/* a 3-vector as PREFIX_x UNIT, PREFIX_y UNIT, PREFIX_z UNIT */
#define KEY3(prefix, unit, v)                                             \
  for (int d_ = 0; d_ < 3; d_++) {                                        \
    char nm3_[40];                                                        \
    PetscSNPrintf(nm3_, sizeof nm3_, "%s_%c%s", prefix, "xyz"[d_], unit); \
    KEY(nm3_, (v)[d_]);                                                   \
  }

/* the keys of the clamp and grip lines and of the grip's path, after the n keys before them */
static PetscInt LineAndPathKeys(const Scene *s, SceneKey *key, PetscInt n)
{
  /* every slot (unused ones are 0) */
  KEY("clamp_lines", s->clamps.clamp_lines);
  KEY("grip_lines", s->clamps.grip_lines);
  KEY("grip_path_waypoints", s->load.waypoints);
  for (int l = 0; l < 2 * MAX_LINES; l++) {
    const PetscReal *line    = l < MAX_LINES ? s->clamps.clamp_line[l] : s->clamps.grip_line[l - MAX_LINES];
    const char      *what[4] = {"x_m", "y_m", "angle_rad", "half_width_m"};
    for (int c = 0; c < 4; c++) {
      char nm[40];
      PetscSNPrintf(nm, sizeof nm, "%s_line_%d_%s", l < MAX_LINES ? "clamp" : "grip", l % MAX_LINES + 1, what[c]);
      KEY(nm, line[c]);
    }
  }
  for (int w = 0; w < MAX_WAYPOINTS; w++) {
    char nm[40];
    PetscSNPrintf(nm, sizeof nm, "grip_path_%d", w + 1);
    KEY3(nm, "_m", s->load.waypoint[w]);
  }
  return n;
}

/* what the run computes with, in SI (names say the unit) */
static PetscInt SceneKeys(Fabric fab, SceneKey *key)
{
  const Scene *s = &fab->s;
  PetscInt     n = 0;
  KEY("grid_nx", s->spec.nx);
  KEY("grid_ny", s->spec.ny);
  KEY("pull", s->spec.pull);
  KEY("ends_per_m", s->spec.ends_per_m);
  KEY("picks_per_m", s->spec.picks_per_m);
  KEY("gauge_m", s->spec.gauge);
  KEY("width_m", s->spec.width);
  for (int y = 0; y < 2; y++) {
    const YarnLaw *l = y ? &s->yarns.weft : &s->yarns.warp;
    char           nm[40];
#define YKEY(suffix, v) (PetscSNPrintf(nm, sizeof nm, "%s_" suffix, y ? "weft" : "warp"), KEY(nm, v))
    YKEY("mu_kg_m", l->mu);
    YKEY("crimp", l->crimp);
    YKEY("EA_N", l->EA);
    YKEY("Ec_N", l->Ec);
    YKEY("compression_ratio", l->k_comp);
    YKEY("bending_Nm2", l->bending);
    YKEY("break_strain", l->break_ey);
    YKEY("table_nodes", l->ntab);
    YKEY("table_end_N", l->ntab ? l->tab_T[l->ntab - 1] : 0.0);
    YKEY("contact_strain", l->e_contact);
    YKEY("law_smoothing", l->smoothing);
#undef YKEY
  }
  KEY("shear_G_N_m", s->terms.shear_G);
  KEY("shear_lock_deg", s->terms.lock_deg);
  KEY("jam_factor", s->terms.jam_factor);
  KEY("traction", s->terms.traction);
  KEY("bending", s->terms.bending);
  KEY("shear", s->terms.shear);
  KEY3("gravity", "", s->terms.gravity);
  KEY("nu", s->num.nu);
  KEY("damping_ratio", s->num.damping_ratio);
  KEY("elongation", s->load.elongation);
  KEY("speed_m_s", s->load.speed);
  KEY3("point_load", "_N", s->load.point_load);
  KEY("point_load_i", s->load.load_at[0]);
  KEY("point_load_j", s->load.load_at[1]);
  KEY("load_steps", s->load.load_steps);
  KEY("max_inner_steps", s->load.max_inner_steps);
  KEY("integrator", s->num.integrator);
  KEY("te_s", s->num.te_user);
  KEY("te_safety", s->num.te_safety);
  KEY("te_strain_window", s->num.te_window);
  KEY("te_check", s->num.te_check);
  KEY("early_exit", s->num.early_exit);
  KEY("balance_tol", s->num.balance_tol);
  KEY("speed_tol_m_s", s->num.speed_tol);
  KEY("predict", s->num.predict);
  KEY("front", s->num.front);
  KEY("sleep_tol", s->num.sleep_tol);
  KEY("kinetic_damping", s->num.kinetic_damping);
  KEY("grip_ramp_steps", s->num.grip_ramp);
  KEY("test", s->test);
  KEY("shape", s->spec.shape);
  KEY("disc_radius_m", s->spec.disc_radius);
  KEY("clamp", s->clamps.clamp);
  KEY("clamp_ring_inner_m", s->clamps.ring[0]);
  KEY("clamp_ring_outer_m", s->clamps.ring[1]);
  KEY("jaw_depth_m", s->spec.jaw_depth);
  KEY("sphere_radius_m", s->bodies.sphere_radius);
  KEY3("sphere_start", "_m", s->bodies.sphere_start);
  KEY3("sphere_dir", "", s->bodies.sphere_dir);
  KEY("sphere_travel_m", s->bodies.sphere_travel);
  KEY("thickness_m", s->bodies.thickness);
  KEY("plane", s->bodies.plane);
  KEY3("plane_point", "_m", s->bodies.plane_point);
  KEY3("plane_normal", "", s->bodies.plane_normal);
  KEY("contact_stiffness_N_m", s->bodies.contact_k);
  KEY("pedestal_radius_m", s->bodies.pedestal_radius);
  KEY3("pedestal_top", "_m", s->bodies.pedestal_top);
  KEY("pedestal_height_m", s->bodies.pedestal_height);
  KEY("friction_mu", s->bodies.friction_mu);
  n = LineAndPathKeys(s, key, n);
#undef KEY3
#undef KEY
  PetscCheckAbort(n <= MAX_KEYS, PETSC_COMM_SELF, PETSC_ERR_PLIB, "SceneKeys: %d keys, raise MAX_KEYS", (int) n);
  return n;
}

/* the state vectors of a checkpoint, in /state */
typedef struct {
  const char *name;
  Vec        *vec;
  const char *root_flag; /* attribute that says it is there ("" = always) */
} StateVec;

static PetscInt StateVecs(Fabric fab, StateVec *sv)
{
  PetscInt n = 0;
  sv[n++]    = (StateVec){"positions", &fab->state.X, ""};
  sv[n++]    = (StateVec){"velocities", &fab->state.V, ""};
  sv[n++]    = (StateVec){"positions_old", &fab->state.Xold, "has_positions_old"};
  sv[n++]    = (StateVec){"velocities_old", &fab->state.Vold, "has_velocities_old"};
  sv[n++]    = (StateVec){"converged_positions", &fab->state.Xconv, "has_converged_positions"};
  sv[n++]    = (StateVec){"converged_positions_prev", &fab->state.Xconv_prev, "has_converged_positions_prev"};
  sv[n++]    = (StateVec){"friction_anchors_sphere", &fab->state.anchor[0], "has_friction_anchors_sphere"};
  sv[n++]    = (StateVec){"friction_anchors_plane", &fab->state.anchor[1], "has_friction_anchors_plane"};
  sv[n++]    = (StateVec){"friction_anchors_pedestal", &fab->state.anchor[2], "has_friction_anchors_pedestal"};
  return n;
}

/* broken segments of the owned points as a dof-2 vector: [to i+1, to j+1] */
static PetscErrorCode BrokenToVec(Fabric fab, Vec B)
{
  const Patch *p = &fab->grid.patch;
  PetscScalar *b;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(B, &b));
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
    for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
      const PetscInt q = (j - p->ys) * p->xm + (i - p->xs), k = (j - p->gys) * p->gxm + (i - p->gxs);
      b[2 * q]     = p->broken_x[k];
      b[2 * q + 1] = p->broken_y[k];
    }
  PetscCall(VecRestoreArray(B, &b));
  PetscFunctionReturn(0);
}

/* the ghosted broken flags from the owned ones: one global-to-local exchange */
static PetscErrorCode BrokenFromVec(Fabric fab, Vec B)
{
  Patch             *p = &fab->grid.patch;
  Vec                Bl;
  const PetscScalar *b;

  PetscFunctionBeginUser;
  PetscCall(DMGetLocalVector(fab->grid.da_seg, &Bl));
  PetscCall(DMGlobalToLocalBegin(fab->grid.da_seg, B, INSERT_VALUES, Bl));
  PetscCall(DMGlobalToLocalEnd(fab->grid.da_seg, B, INSERT_VALUES, Bl));
  PetscCall(VecGetArrayRead(Bl, &b));
  for (PetscInt k = 0; k < p->gxm * p->gym; k++) {
    p->broken_x[k] = b[2 * k] != 0;
    p->broken_y[k] = b[2 * k + 1] != 0;
  }
  PetscCall(VecRestoreArrayRead(Bl, &b));
  PetscCall(DMRestoreLocalVector(fab->grid.da_seg, &Bl));
  PetscFunctionReturn(0);
}

/* a vector held by rank 0 alone (the curve rows, the frame list): one 1-D dataset */
static PetscErrorCode ViewRankZero(Fabric fab, PetscViewer v, const char *name, const PetscReal *a, PetscInt n)
{
  Vec          w;
  PetscScalar *x;

  PetscFunctionBeginUser;
  PetscCall(VecCreateMPI(fab->comm, fab->rank == 0 ? n : 0, n, &w));
  PetscCall(VecGetArray(w, &x));
  if (fab->rank == 0) PetscCall(PetscArraycpy(x, a, n));
  PetscCall(VecRestoreArray(w, &x));
  PetscCall(PetscObjectSetName((PetscObject) w, name));
  PetscCall(VecView(w, v));
  PetscCall(VecDestroy(&w));
  PetscFunctionReturn(0);
}

/* the counters of the run, as attributes of / */
static PetscErrorCode WriteCounters(Fabric fab, PetscViewer v)
{
  FabricIO io = fab->io;

  PetscFunctionBeginUser;
  {
    int version = CHECKPOINT_VERSION, load_step = (int) fab->load.load_step, frames = (int) io->frames,
        converged = fab->stats.converged, broken = fab->stats.broken_any, ranks = fab->size;
    long      te_steps = (long) fab->stats.te_steps, updates = (long) fab->stats.point_updates;
    PetscReal time = TestTime(&fab->s, &fab->load), wall = fab->stats.wall;
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "fabric_checkpoint", PETSC_INT, &version));
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "load_step", PETSC_INT, &load_step));
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "time_s", PETSC_REAL, &time));
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "grip_disp_m", PETSC_REAL, &fab->load.travel));
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "grip_step_prev_m", PETSC_REAL, &fab->load.travel_step_prev));
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "te_steps", PETSC_LONG, &te_steps));
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "point_updates", PETSC_LONG, &updates));
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "converged", PETSC_INT, &converged));
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "broken_any", PETSC_INT, &broken));
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "frames", PETSC_INT, &frames));
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "wall_s", PETSC_REAL, &wall));
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "ranks", PETSC_INT, &ranks));
    /* sleeping: the awake box and the force scale of the last te step */
    for (int c = 0; c < 4; c++) {
      char nm[32];
      int  b = (int) fab->front.awake_box[c];
      PetscCall(PetscSNPrintf(nm, sizeof nm, "awake_box_%d", c));
      PetscCall(PetscViewerHDF5WriteAttribute(v, "/", nm, PETSC_INT, &b));
    }
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "last_tension_max_N", PETSC_REAL, &fab->step.last.tension_max));
    { /* kinetic damping: the kinetic energy after the last te step (a reset is decided on it) */
      long resets = (long) fab->step.ke_resets;
      PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "kinetic_energy_J", PETSC_REAL, &fab->step.ke_prev));
      PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "kinetic_resets", PETSC_LONG, &resets));
    }
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckpointWrite(Fabric fab)
{
  FabricIO    io  = fab->io;
  const char *dir = fab->s.out.output_dir;
  char        file[PETSC_MAX_PATH_LEN], tmp[PETSC_MAX_PATH_LEN];
  PetscViewer v;
  StateVec    sv[MAX_STATE];
  SceneKey    key[MAX_KEYS];
  PetscInt    nsv = StateVecs(fab, sv), nkey = SceneKeys(fab, key);
  int         ok = 1;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(EV_Output, 0, 0, 0, 0));
  PetscCall(PetscSNPrintf(file, sizeof file, "%s/checkpoint.h5", dir));
  PetscCall(PetscSNPrintf(tmp, sizeof tmp, "%s/.checkpoint.h5.tmp", dir));
  PetscCall(PetscViewerHDF5Open(fab->comm, tmp, FILE_MODE_WRITE, &v));

  /* the state vectors, and the largest |value| of each (read back and compared on restart) */
  PetscCall(PetscViewerHDF5PushGroup(v, "/state"));
  for (PetscInt k = 0; k < nsv; k++) {
    Vec       x = *sv[k].vec;
    char      nm[64];
    PetscReal norm;
    int       has = x != NULL;
    if (sv[k].root_flag[0]) PetscCall(PetscViewerHDF5WriteAttribute(v, "/", sv[k].root_flag, PETSC_INT, &has));
    if (!x) continue;
    PetscCall(PetscObjectSetName((PetscObject) x, sv[k].name));
    PetscCall(VecView(x, v));
    PetscCall(VecNorm(x, NORM_INFINITY, &norm));
    PetscCall(PetscSNPrintf(nm, sizeof nm, "max_abs_%s", sv[k].name));
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", nm, PETSC_REAL, &norm));
  }
  {
    Vec B;
    PetscCall(DMGetGlobalVector(fab->grid.da_seg, &B));
    PetscCall(BrokenToVec(fab, B));
    PetscCall(PetscObjectSetName((PetscObject) B, "broken_segments"));
    PetscCall(VecView(B, v));
    PetscCall(DMRestoreGlobalVector(fab->grid.da_seg, &B));
  }
  PetscCall(PetscViewerHDF5PopGroup(v));
  PetscCall(PetscObjectSetName((PetscObject) fab->state.X, "positions"));
  PetscCall(PetscObjectSetName((PetscObject) fab->state.V, NULL));

  /* the curve rows and the frame list, held by rank 0 */
  PetscCall(PetscViewerHDF5PushGroup(v, "/history"));
  {
    PetscReal *rows;
    PetscCall(PetscMalloc1(CURVE_COLS * fab->load.load_step, &rows));
    for (PetscInt k = 0; k < fab->load.load_step; k++) CurveRowPack(&fab->stats.curve[k], rows + CURVE_COLS * k);
    PetscCall(ViewRankZero(fab, v, "curve", rows, CURVE_COLS * fab->load.load_step));
    PetscCall(PetscFree(rows));
  }
  if (io->frames) {
    PetscReal *fr;
    PetscCall(PetscMalloc1(3 * io->frames, &fr));
    for (PetscInt k = 0; k < io->frames; k++) {
      fr[3 * k]     = io->frame[k].time;
      fr[3 * k + 1] = (PetscReal) io->frame[k].load_step;
      fr[3 * k + 2] = (PetscReal) io->frame[k].te_step;
    }
    PetscCall(ViewRankZero(fab, v, "frames", fr, 3 * io->frames));
    PetscCall(PetscFree(fr));
  }
  PetscCall(PetscViewerHDF5PopGroup(v));

  /* the scene it belongs to */
  PetscCall(PetscViewerHDF5PushGroup(v, "/scene"));
  PetscCall(PetscViewerHDF5WriteGroup(v, NULL));
  for (PetscInt k = 0; k < nkey; k++)
    PetscCall(PetscViewerHDF5WriteAttribute(v, NULL, key[k].name, PETSC_REAL, &key[k].value));
  PetscCall(PetscViewerHDF5WriteAttribute(v, NULL, "scene", PETSC_STRING, fab->s.out.name));
  PetscCall(PetscViewerHDF5PopGroup(v));

  PetscCall(WriteCounters(fab, v));
  PetscCall(PetscViewerDestroy(&v));

  /* every rank has closed the file: rank 0 syncs it to disk and renames it into place */
  PetscCallMPI(MPI_Barrier(fab->comm));
  if (fab->rank == 0) {
    int fd = open(tmp, O_RDONLY);
    ok     = fd >= 0 && !fsync(fd);
    if (fd >= 0) close(fd);
    ok = ok && !rename(tmp, file);
    fd = open(dir, O_RDONLY);
    if (fd >= 0) {
      (void) fsync(fd);
      close(fd);
    }
  }
  PetscCallMPI(MPI_Bcast(&ok, 1, MPI_INT, 0, fab->comm));
  PetscCheck(ok, fab->comm, PETSC_ERR_FILE_WRITE, "-output_dir %s: cannot write checkpoint.h5", dir);
  PetscCall(PetscLogEventEnd(EV_Output, 0, 0, 0, 0));
  if (!fab->s.out.quiet)
    PetscCall(PetscPrintf(fab->comm, "checkpoint at load step %" PetscInt_FMT ": %s\n", fab->load.load_step, file));
  PetscFunctionReturn(0);
}

/* End of a load step: a checkpoint every -checkpoint_every load steps */
PetscErrorCode CheckpointLoadStep(Fabric fab)
{
  FabricIO io = fab->io;

  PetscFunctionBeginUser;
  if (!io || !io->checkpoint_every || !fab->s.out.output_dir[0] || fab->load.load_step % io->checkpoint_every)
    PetscFunctionReturn(0);
  PetscCall(CheckpointWrite(fab));
  PetscFunctionReturn(0);
}

/* ------------------------------------------------------------------ restart */

typedef struct {    /* what rank 0 reads alone, then broadcasts */
  int       status; /* 0: fine; otherwise msg says what is wrong */
  char      msg[5 * PETSC_MAX_PATH_LEN];
  int       load_step, frames, converged, broken_any;
  int       has[MAX_STATE];
  long long te_steps, point_updates;
  double    grip_disp, grip_step_prev, wall, max_abs[MAX_STATE];
  int       awake_box[4];
  double    last_tension_max;
  double    ke_prev;
  long long ke_resets;
} Header;

static int ReadAttr(hid_t obj, const char *name, hid_t type, void *value)
{
  hid_t a;
  int   ok;
  if (H5Aexists(obj, name) <= 0) return 0;
  a = H5Aopen(obj, name, H5P_DEFAULT);
  if (a < 0) return 0;
  ok = H5Aread(a, type, value) >= 0;
  H5Aclose(a);
  return ok;
}

/* dataset path of rank (dims) == want; reads it into buf (doubles) if buf */
static int CheckDataset(hid_t fid, const char *path, int rank, const hsize_t *want, double *buf)
{
  hid_t   d, sp;
  hsize_t dims[4];
  int     ok;
  if (H5Lexists(fid, path, H5P_DEFAULT) <= 0) return 0;
  /* intermediate groups: H5Lexists above fails on a missing parent group, which is caught as <= 0 */
  d = H5Dopen2(fid, path, H5P_DEFAULT);
  if (d < 0) return 0;
  sp = H5Dget_space(d);
  ok = sp >= 0 && H5Sget_simple_extent_ndims(sp) == rank;
  if (ok) {
    H5Sget_simple_extent_dims(sp, dims, NULL);
    for (int k = 0; k < rank; k++) ok = ok && dims[k] == want[k];
  }
  if (ok && buf) ok = H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf) >= 0;
  if (sp >= 0) H5Sclose(sp);
  H5Dclose(d);
  return ok;
}

/* a scene value for a message: enums by name, numbers with as many digits as tell them apart */
static void KeyValue(const char *name, double v, char *buf, size_t len, double other)
{
  static const struct {
    const char        *key;
    const char *const *names;
    int                count;
  } enums[] = {
      {"pull", PullAxisNames, 2}, {"integrator", IntegratorNames, 2}, {"predict", PredictNames, 3},
      {"test", TestNames, 5},     {"shape", ShapeNames, 3},           {"clamp", ClampNames, 4},
  };
  char a[64], b[64];
  for (size_t e = 0; e < sizeof enums / sizeof enums[0]; e++)
    if (!strcmp(name, enums[e].key) && v >= 0 && v < enums[e].count && v == (int) v) {
      snprintf(buf, len, "%s", enums[e].names[(int) v]);
      return;
    }
  snprintf(a, sizeof a, "%.10g", v);
  snprintf(b, sizeof b, "%.10g", other);
  snprintf(buf, len, strcmp(a, b) ? "%.10g" : "%.17g", v);
}

#define FAIL(...)                                 \
  do {                                            \
    h->status = 1;                                \
    snprintf(h->msg, sizeof h->msg, __VA_ARGS__); \
    goto done;                                    \
  } while (0)

/* the checkpoint's /scene group g against this run's scene and grid; 0 (and h->msg) if they differ */
static int SameScene(Fabric fab, hid_t g, const char *file, Header *h)
{
  const Scene *s = &fab->s;
  SceneKey     key[MAX_KEYS];
  PetscInt     nkey = SceneKeys(fab, key);

  {
    double there[MAX_KEYS];
    char   name[PETSC_MAX_PATH_LEN] = "?";
    for (PetscInt k = 0; k < nkey; k++)
      if (!ReadAttr(g, key[k].name, H5T_NATIVE_DOUBLE, &there[k]))
        FAIL("-restart %s: damaged checkpoint: /scene has no %s", file, key[k].name);
    {
      hid_t a = H5Aexists(g, "scene") > 0 ? H5Aopen(g, "scene", H5P_DEFAULT) : -1;
      if (a >= 0) {
        hid_t t = H5Aget_type(a);
        if (H5Tget_size(t) < sizeof name) H5Aread(a, t, name);
        H5Tclose(t);
        H5Aclose(a);
      }
    }
    if (there[0] != (double) s->spec.nx || there[1] != (double) s->spec.ny)
      FAIL("-restart %s: the checkpoint is of another grid: %g x %g crossings there (scene %s), %" PetscInt_FMT
           " x %" PetscInt_FMT " here (scene %s): restart with the scene and options of the checkpointed run",
           file, there[0], there[1], name, s->spec.nx, s->spec.ny, s->out.name);
    for (PetscInt k = 2; k < nkey; k++)
      if (there[k] != (double) key[k].value) {
        char a[64], b[64];
        KeyValue(key[k].name, there[k], a, sizeof a, (double) key[k].value);
        KeyValue(key[k].name, (double) key[k].value, b, sizeof b, there[k]);
        FAIL("-restart %s: the checkpoint is of another scene: %s = %s there (scene %s), %s here (scene %s): restart "
             "with the scene and options of the checkpointed run",
             file, key[k].name, a, name, b, s->out.name);
      }
  }
  return 1;
done:
  return 0;
}

/* Rank 0, alone (serial HDF5): is FILE a complete checkpoint of this scene? Fills h and, on
   success, the curve rows (*rows, CURVE_COLS per load step) and the frame list (*frames). */
static PetscErrorCode ReadHeader(Fabric fab, const char *file, Header *h, double **rows, double **frames)
{
  const Scene  *s = &fab->s;
  H5E_auto2_t   efunc;
  void         *edata;
  hid_t         fid = -1, g = -1;
  StateVec      sv[MAX_STATE];
  PetscInt      nsv      = StateVecs(fab, sv);
  const hsize_t dims3[3] = {(hsize_t) s->spec.ny, (hsize_t) s->spec.nx, 3},
                dims2[3] = {(hsize_t) s->spec.ny, (hsize_t) s->spec.nx, 2};
  int version            = 0;

  PetscFunctionBeginUser;
  *rows = *frames = NULL;
  H5Eget_auto2(H5E_DEFAULT, &efunc, &edata);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* failures become one message, not an HDF5 error stack */
  if (H5Fis_hdf5(file) <= 0)
    FAIL("-restart %s: not an HDF5 file, so not a checkpoint (give the checkpoint.h5 that -checkpoint_every wrote)",
         file);
  fid = H5Fopen(file, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (fid < 0) FAIL("-restart %s: the HDF5 file cannot be opened: it is damaged or truncated", file);
  g = H5Gopen2(fid, "/", H5P_DEFAULT);
  if (!ReadAttr(g, "fabric_checkpoint", H5T_NATIVE_INT, &version))
    FAIL("-restart %s: not a fabric checkpoint (no fabric_checkpoint attribute): give the checkpoint.h5 that "
         "-checkpoint_every wrote",
         file);
  if (version != CHECKPOINT_VERSION)
    FAIL("-restart %s: checkpoint format %d, this fabric reads format %d", file, version, CHECKPOINT_VERSION);
  H5Gclose(g);
  g = -1;

  /* the same scene and grid */
  if (H5Lexists(fid, "/scene", H5P_DEFAULT) <= 0 || (g = H5Gopen2(fid, "/scene", H5P_DEFAULT)) < 0)
    FAIL("-restart %s: damaged checkpoint: no /scene group", file);
  if (!SameScene(fab, g, file, h)) goto done;
  H5Gclose(g);
  g = H5Gopen2(fid, "/", H5P_DEFAULT);

  /* the counters */
  if (!ReadAttr(g, "load_step", H5T_NATIVE_INT, &h->load_step) || !ReadAttr(g, "frames", H5T_NATIVE_INT, &h->frames) ||
      !ReadAttr(g, "converged", H5T_NATIVE_INT, &h->converged) ||
      !ReadAttr(g, "broken_any", H5T_NATIVE_INT, &h->broken_any) ||
      !ReadAttr(g, "te_steps", H5T_NATIVE_LLONG, &h->te_steps) ||
      !ReadAttr(g, "point_updates", H5T_NATIVE_LLONG, &h->point_updates) ||
      !ReadAttr(g, "grip_disp_m", H5T_NATIVE_DOUBLE, &h->grip_disp) ||
      !ReadAttr(g, "grip_step_prev_m", H5T_NATIVE_DOUBLE, &h->grip_step_prev) ||
      !ReadAttr(g, "wall_s", H5T_NATIVE_DOUBLE, &h->wall))
    FAIL("-restart %s: damaged checkpoint: a counter of the run is missing", file);
  if (!ReadAttr(g, "awake_box_0", H5T_NATIVE_INT, &h->awake_box[0]) ||
      !ReadAttr(g, "awake_box_1", H5T_NATIVE_INT, &h->awake_box[1]) ||
      !ReadAttr(g, "awake_box_2", H5T_NATIVE_INT, &h->awake_box[2]) ||
      !ReadAttr(g, "awake_box_3", H5T_NATIVE_INT, &h->awake_box[3]) ||
      !ReadAttr(g, "last_tension_max_N", H5T_NATIVE_DOUBLE, &h->last_tension_max))
    FAIL("-restart %s: damaged checkpoint: the sleeping state is missing", file);
  if (!ReadAttr(g, "kinetic_energy_J", H5T_NATIVE_DOUBLE, &h->ke_prev) ||
      !ReadAttr(g, "kinetic_resets", H5T_NATIVE_LLONG, &h->ke_resets))
    FAIL("-restart %s: damaged checkpoint: the kinetic damping state is missing", file);
  if (h->load_step < 1 || h->load_step > s->load.load_steps || h->frames < 0 || h->te_steps < 0)
    FAIL("-restart %s: damaged checkpoint: load step %d of %" PetscInt_FMT, file, h->load_step, s->load.load_steps);

  /* the state vectors: there, of this grid */
  for (PetscInt k = 0; k < nsv; k++) {
    char path[128], nm[64];
    h->has[k] = 1;
    if (sv[k].root_flag[0] && !ReadAttr(g, sv[k].root_flag, H5T_NATIVE_INT, &h->has[k]))
      FAIL("-restart %s: damaged checkpoint: no %s attribute", file, sv[k].root_flag);
    if (!h->has[k]) continue;
    snprintf(path, sizeof path, "/state/%s", sv[k].name);
    snprintf(nm, sizeof nm, "max_abs_%s", sv[k].name);
    if (!CheckDataset(fid, path, 3, dims3, NULL) || !ReadAttr(g, nm, H5T_NATIVE_DOUBLE, &h->max_abs[k]))
      FAIL("-restart %s: damaged checkpoint: %s is missing or not of the %" PetscInt_FMT " x %" PetscInt_FMT " grid",
           file, path, s->spec.nx, s->spec.ny);
  }
  if (!CheckDataset(fid, "/state/broken_segments", 3, dims2, NULL))
    FAIL("-restart %s: damaged checkpoint: /state/broken_segments is missing or not of this grid", file);
  if (s->num.integrator == INTEGRATOR_PAPER && !h->has[2])
    FAIL("-restart %s: damaged checkpoint: the paper integrator needs positions_old", file);

  /* the history */
  {
    const hsize_t nrows = (hsize_t) CURVE_COLS * h->load_step, nfr = (hsize_t) 3 * h->frames;
    PetscCall(PetscMalloc1(nrows, rows));
    if (!CheckDataset(fid, "/history/curve", 1, &nrows, *rows))
      FAIL("-restart %s: damaged checkpoint: /history/curve does not hold %d load steps", file, h->load_step);
    if (h->frames) {
      PetscCall(PetscMalloc1(nfr, frames));
      if (!CheckDataset(fid, "/history/frames", 1, &nfr, *frames))
        FAIL("-restart %s: damaged checkpoint: /history/frames does not hold %d frames", file, h->frames);
    }
  }
done:
  if (g >= 0) H5Gclose(g);
  if (fid >= 0) H5Fclose(fid);
  H5Eset_auto2(H5E_DEFAULT, efunc, edata);
  PetscFunctionReturn(0);
}

/* Rank 0: does DIR/fabric.h5 hold the frames written before the checkpoint? */
static void CheckFramesFile(Fabric fab, Header *h)
{
  char        file[PETSC_MAX_PATH_LEN], path[64];
  H5E_auto2_t efunc;
  void       *edata;
  hid_t       fid;
  int         nx = 0, ny = 0;

  if (snprintf(file, sizeof file, "%s/fabric.h5", fab->s.out.output_dir) >= (int) sizeof file) file[0] = 0;
  H5Eget_auto2(H5E_DEFAULT, &efunc, &edata);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  fid = H5Fis_hdf5(file) > 0 ? H5Fopen(file, H5F_ACC_RDONLY, H5P_DEFAULT) : -1;
  if (fid < 0) {
    h->status = 1;
    snprintf(
        h->msg, sizeof h->msg,
        "-restart %s: %s, which holds the %d frames written before the checkpoint, is missing or cannot be opened "
        "(damaged); restart into the -output_dir of the checkpointed run, or with -output_every 0 -output_te_every 0",
        fab->io->restart, file, h->frames);
  } else {
    hid_t g = H5Gopen2(fid, "/", H5P_DEFAULT);
    if (!ReadAttr(g, "nx", H5T_NATIVE_INT, &nx) || !ReadAttr(g, "ny", H5T_NATIVE_INT, &ny) || nx != fab->s.spec.nx ||
        ny != fab->s.spec.ny) {
      h->status = 1;
      snprintf(h->msg, sizeof h->msg,
               "-restart %s: %s is not of this grid (%d x %d crossings, this run has %" PetscInt_FMT " x %" PetscInt_FMT
               ")",
               fab->io->restart, file, nx, ny, fab->s.spec.nx, fab->s.spec.ny);
    }
    for (int k = 0; k < h->frames && !h->status; k++) {
      snprintf(path, sizeof path, "/frames/%06d", k);
      if (H5Lexists(fid, "/frames", H5P_DEFAULT) <= 0 || H5Lexists(fid, path, H5P_DEFAULT) <= 0) {
        h->status = 1;
        snprintf(
            h->msg, sizeof h->msg,
            "-restart %s: %s lacks frame %d of the %d written before the checkpoint: it is not the file of this run",
            fab->io->restart, file, k, h->frames);
      }
    }
    H5Gclose(g);
    H5Fclose(fid);
  }
  H5Eset_auto2(H5E_DEFAULT, efunc, edata);
}

/* the run's counters from a checkpoint's header */
static void RestoreCounters(Fabric fab, const Header *hp)
{
  const Header h = *hp;

  fab->load.load_step        = h.load_step;
  fab->load.load_factor      = (PetscReal) h.load_step / (PetscReal) fab->s.load.load_steps;
  fab->load.travel           = h.grip_disp;
  fab->load.travel_now       = h.grip_disp; /* a load step ends with its ramp done */
  fab->load.travel_step_prev = h.grip_step_prev;
  for (int c = 0; c < 4; c++) fab->front.awake_box[c] = h.awake_box[c];
  fab->step.last.tension_max = h.last_tension_max;
  fab->step.ke_prev          = h.ke_prev;
  fab->step.ke_resets        = (PetscInt64) h.ke_resets;
  fab->stats.te_steps        = (PetscInt64) h.te_steps;
  fab->stats.point_updates   = (PetscInt64) h.point_updates;
  fab->stats.converged       = h.converged ? PETSC_TRUE : PETSC_FALSE;
  fab->stats.broken_any      = h.broken_any ? PETSC_TRUE : PETSC_FALSE;
}

PetscErrorCode RestartLoad(Fabric fab)
{
  FabricIO    io = fab->io;
  Header      h;
  double     *rows = NULL, *frames = NULL;
  StateVec    sv[MAX_STATE];
  PetscInt    nsv = StateVecs(fab, sv);
  PetscViewer v;

  PetscFunctionBeginUser;
  if (!io || !io->restart[0]) PetscFunctionReturn(0);
  PetscCall(PetscLogEventBegin(EV_Output, 0, 0, 0, 0));
  PetscCall(PetscMemzero(&h, sizeof h));
  if (fab->rank == 0) {
    PetscCall(ReadHeader(fab, io->restart, &h, &rows, &frames));
    if (!h.status && h.frames > 0 && fab->s.out.output_dir[0] && (io->output_every > 0 || io->output_te_every > 0))
      CheckFramesFile(fab, &h);
  }
  PetscCallMPI(MPI_Bcast(&h, sizeof h, MPI_BYTE, 0, fab->comm));
  if (h.status) {
    PetscCall(PetscFree(rows));
    PetscCall(PetscFree(frames));
  }
  PetscCheck(!h.status, fab->comm, PETSC_ERR_USER_INPUT, "%s", h.msg);
  if (fab->rank) {
    PetscCall(PetscMalloc1(CURVE_COLS * h.load_step, &rows));
    if (h.frames) PetscCall(PetscMalloc1(3 * h.frames, &frames));
  }
  PetscCallMPI(MPI_Bcast(rows, CURVE_COLS * h.load_step, MPI_DOUBLE, 0, fab->comm));
  if (h.frames) PetscCallMPI(MPI_Bcast(frames, 3 * h.frames, MPI_DOUBLE, 0, fab->comm));

  /* the state vectors, read collectively; each must match the largest |value| it was saved with */
  PetscCall(PetscViewerHDF5Open(fab->comm, io->restart, FILE_MODE_READ, &v));
  PetscCall(PetscViewerHDF5PushGroup(v, "/state"));
  for (PetscInt k = 0; k < nsv; k++) {
    PetscReal norm;
    if (!h.has[k]) continue;
    if (!*sv[k].vec) PetscCall(VecDuplicate(fab->state.X, sv[k].vec));
    PetscCall(PetscObjectSetName((PetscObject) *sv[k].vec, sv[k].name));
    PetscCall(VecLoad(*sv[k].vec, v));
    PetscCall(VecNorm(*sv[k].vec, NORM_INFINITY, &norm));
    PetscCheck(norm == (PetscReal) h.max_abs[k], fab->comm, PETSC_ERR_FILE_UNEXPECTED,
               "-restart %s: damaged checkpoint: %s read back with largest |value| %.17g, saved with %.17g",
               io->restart, sv[k].name, (double) norm, h.max_abs[k]);
  }
  {
    Vec B;
    PetscCall(DMGetGlobalVector(fab->grid.da_seg, &B));
    PetscCall(PetscObjectSetName((PetscObject) B, "broken_segments"));
    PetscCall(VecLoad(B, v));
    PetscCall(BrokenFromVec(fab, B));
    PetscCall(DMRestoreGlobalVector(fab->grid.da_seg, &B));
  }
  PetscCall(PetscViewerHDF5PopGroup(v));
  PetscCall(PetscViewerDestroy(&v));
  PetscCall(PetscObjectSetName((PetscObject) fab->state.X, "positions"));
  PetscCall(PetscObjectSetName((PetscObject) fab->state.V, NULL));

  RestoreCounters(fab, &h);
  for (PetscInt k = 0; k < h.load_step; k++) CurveRowUnpack(rows + CURVE_COLS * k, &fab->stats.curve[k]);
  io->frames = 0;
  for (PetscInt k = 0; k < h.frames; k++) {
    FrameInfo f = {frames[3 * k], (PetscInt) frames[3 * k + 1], (PetscInt) frames[3 * k + 2]};
    PetscCall(FramesAppend(fab, &f));
  }
  io->restarted = PETSC_TRUE;
  fab->stats.wall_start -= h.wall; /* elapsed time and ETA count the run before the restart */
  PetscCall(PetscFree(rows));
  PetscCall(PetscFree(frames));
  PetscCall(PetscLogEventEnd(EV_Output, 0, 0, 0, 0));
  if (!fab->s.out.quiet)
    PetscCall(PetscPrintf(fab->comm,
                          "fabric: restart from %s at load step %" PetscInt_FMT "/%" PetscInt_FMT " (%" PetscInt64_FMT
                          " te steps, %" PetscInt_FMT " frames so far)\n",
                          io->restart, fab->load.load_step, fab->s.load.load_steps, fab->stats.te_steps, io->frames));
  PetscFunctionReturn(0);
}
