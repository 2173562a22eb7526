/* checkpoint.c - checkpoint and restart: a run killed at a wall-time limit continues exactly.
 *
 * DIR/checkpoint.h5 is written collectively through PETSc's HDF5 viewer, aside
 * (DIR/.checkpoint.h5.tmp) and then renamed into place, so checkpoint.h5 is always a complete
 * checkpoint: at the end of every -checkpoint_every K load steps; within a load step every
 * -checkpoint_every_te K te steps and once -checkpoint_every_s S seconds of wall-clock time have
 * passed since the last one; and on SIGTERM or SIGUSR1 (a batch system's wall-time limit), after
 * which the run stops with exit status 3. Within a load step it is taken after a te step that the
 * relaxation continues from (-solver static: after a Newton step that the solve continues from). Signals and the clock are looked at every LOOK_EVERY te steps (and at
 * a load step's end once as many have passed), with one small max-reduction (rank 0's clock
 * decides), so all ranks take the same decision at the same te step. It holds everything the run
 * depends on:
 *   /state    positions, velocities, the paper integrator's positions_old and velocities_old,
 *             the extrapolation history converged_positions(_prev) when allocated, and the
 *             broken segments (dof 2 on the grid: segment to i+1 and to j+1 of each point),
 *             the friction anchors of each body (-friction_mu > 0);
 *   /history  curve (21 numbers per load step done: the rows of curve.csv and the balance flag),
 *             frames (time, load step, te step of each frame of fabric.h5);
 *   /scene    what the run computes with (grid, yarns, load program, numerics): a restart
 *             with another scene or grid is refused;
 *   /         load steps done, grip travel and last grip step, te steps, point updates, the
 *             converged and broken flags, frames, wall time, the kinetic damping's last kinetic
 *             energy and reset count, the sleeping state, and the relaxation's state within a
 *             load step (RelaxState: where the break loop and its te steps are, the jaw's ramp,
 *             the front, the step control, the te-frame counter).
 * Every array carries a 64-bit checksum (attribute "checksum" of its dataset): the sum mod 2^64
 * of a hash of (index in the dataset's natural order, the value's 8 bytes) over its entries.
 * The hash is a bijection of the value for a given index, so a change of any one entry always
 * changes the sum; the sum does not depend on the order of the terms, so each rank sums its own
 * entries and one exact integer reduction gives the same checksum on any number of ranks.
 * -restart FILE reads it back: rank 0 checks the file alone first (so that a damaged or
 * foreign file gives one clear message on every rank, never a hang), then all ranks read the
 * vectors collectively and check their checksums. The ghosted broken flags are rebuilt from
 * their owned part with one global-to-local exchange. The state is restored bit for bit, so
 * the run continues as if it had never stopped.
 */
#include "checkpoint.h"
#include "measure.h"
#include "comm.h"
#include "events.h"
#include "hash.h"
#include "integrate.h"
#include "load.h"

#include <fcntl.h>
#include <petscviewerhdf5.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#define MAX_KEYS  320
#define MAX_STATE 16 /* state vectors (StateVecs) */

typedef struct {
  char      name[40];
  PetscReal value;
} SceneKey;

#define KEY(nm, v) (PetscStrncpy(key[n].name, nm, sizeof key[n].name), key[n].value = (PetscReal) (v), n++)

/* what the run computes with: the grid, what a yarn table file holds (its table's size, last force and checksum), and every numeric option
   of the option table (scene.h SceneOptionValues) apart from those that only say what is written
   and when; an array as its count and every slot (unused ones 0), so that the keys are the same
   set for any options */
static PetscBool OutputOnlyOption(const char *name)
{
  const char *out[] = {
      "quiet", "output_every", "output_te_every", "output_tear_every", "checkpoint_every", "checkpoint_every_te", "checkpoint_every_s"};
  for (size_t q = 0; q < sizeof out / sizeof out[0]; q++)
    if (!strcmp(name, out[q])) return PETSC_TRUE;
  return PETSC_FALSE;
}

static double TableChecksum(const YarnLaw *l);

static PetscInt SceneKeys(const Scene *s, SceneKey *key)
{
  PetscInt  n = 0, nv, cap;
  char      name[64], nm[80];
  PetscReal v[4 * MAX_WAYPOINTS];

  KEY("grid_nx", s->spec.nx);
  KEY("grid_ny", s->spec.ny);
  for (int y = 0; y < 2; y++) {
    const YarnLaw *l = y ? &s->yarns.weft : &s->yarns.warp;
    PetscSNPrintf(nm, sizeof nm, "%s_table_nodes", l->name);
    KEY(nm, l->ntab);
    PetscSNPrintf(nm, sizeof nm, "%s_table_end_N", l->name);
    KEY(nm, l->ntab ? l->tab_T[l->ntab - 1] : 0.0);
    PetscSNPrintf(nm, sizeof nm, "%s_law_csv_checksum", l->name);
    KEY(nm, TableChecksum(l));
  }
  for (PetscInt k = 0; SceneOptionValues(s, k, name, v, &nv); k++) {
    if (OutputOnlyOption(name)) continue;
    cap = SceneOptionCapacity(k);
    if (!cap) {
      KEY(name, v[0]);
      continue;
    }
    PetscSNPrintf(nm, sizeof nm, "%s_count", name);
    KEY(nm, nv);
    for (PetscInt c = 0; c < cap; c++) {
      PetscSNPrintf(nm, sizeof nm, "%s_%d", name, (int) c + 1);
      KEY(nm, c < nv ? v[c] : 0.0);
    }
  }
  PetscCheckAbort(n <= MAX_KEYS, PETSC_COMM_SELF, PETSC_ERR_PLIB, "SceneKeys: %d keys, raise MAX_KEYS", (int) n);
  return n;
}

/* fabric.h5's scene_hash: SceneKeys' names and values hashed, 16 hex digits. A restart appends to the fabric.h5 of
   its own run only: another run's in the same directory, with other options on the same grid, had its frames taken
   as this run's (CheckFramesFile) */
static void SceneHash(const Scene *s, char *text, size_t len)
{
  SceneKey key[MAX_KEYS];
  PetscInt n = SceneKeys(s, key);
  uint64_t h = HASH_GOLDEN;

  for (PetscInt k = 0; k < n; k++) {
    double   v = key[k].value == 0 ? 0.0 : (double) key[k].value; /* -0 is 0, as SameScene compares */
    uint64_t bits;
    for (const char *c = key[k].name; *c; c++) h = Mix64(h ^ (unsigned char) *c);
    memcpy(&bits, &v, sizeof bits);
    h = Mix64(h ^ bits);
  }
  snprintf(text, len, "%016llx", (unsigned long long) h);
}

#define LOOK_EVERY 16 /* te steps between looks at the signals and the clock */

/* the run's checkpointing (one fabric per process) */
static struct {
  PetscBool      resume;     /* restarted within a load step: RelaxLoadStep continues from `at` */
  RelaxPoint     at;         /* where */
  PetscInt64     last_te;    /* te steps at the last checkpoint or the start */
  PetscInt64     last_look;  /* te steps at the last look at the signals and the clock */
  PetscLogDouble last_wall;  /* rank 0: wall clock at the last checkpoint or the start */
  int            stopped_by; /* the signal that stopped the run after its checkpoint, 0 = none */
} ckpt;
static volatile sig_atomic_t caught_signal; /* SIGTERM or SIGUSR1 came (CheckpointSignal) */

void CheckpointSignal(int sig)
{
  caught_signal = sig;
}

PetscBool CheckpointStopped(void)
{
  return ckpt.stopped_by ? PETSC_TRUE : PETSC_FALSE;
}

/* ------------------------------------------------------------------ checksums */

/* one entry's term: for a given index, a bijection of the value's 8 bytes */
static inline uint64_t EntryHash(uint64_t index, double value)
{
  uint64_t bits;
  memcpy(&bits, &value, sizeof bits);
  return Mix64(bits ^ Mix64(index + HASH_GOLDEN));
}

/* an array that one rank holds (curve rows, frame list): index = position */
static uint64_t ArrayChecksum(const double *a, size_t n)
{
  uint64_t sum = 0;
  for (size_t k = 0; k < n; k++) sum += EntryHash(k, a[k]);
  return sum;
}

/* a tabulated law's fast table (tensions and slopes at every node): 52 bits of their checksum, exact as a
   double (a scene key); 0 for a law with no table */
static double TableChecksum(const YarnLaw *l)
{
  if (!l->ntab) return 0.0;
  return (double) ((ArrayChecksum(l->tab_T, (size_t) l->ntab) ^ Mix64(ArrayChecksum(l->tab_dT, (size_t) l->ntab))) >> 12);
}

/* a vector of the grid (dof values per point) in the natural order of its dataset (ny, nx, dof):
   each rank sums its owned entries; unsigned sums are exact mod 2^64 in any order */
static PetscErrorCode GridChecksum(MPI_Comm comm, const Patch *p, Vec x, uint64_t *sum)
{
  const PetscScalar *a;
  PetscInt           n, dof;
  uint64_t           local = 0;

  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(x, &n));
  dof = n / (p->xm * p->ym);
  PetscCall(VecGetArrayRead(x, &a));
  for (PetscInt j = p->ys; j < p->ys + p->ym; j++)
    for (PetscInt i = p->xs; i < p->xs + p->xm; i++) {
      const PetscInt q = (j - p->ys) * p->xm + (i - p->xs);
      const uint64_t e = ((uint64_t) j * (uint64_t) p->nx + (uint64_t) i) * (uint64_t) dof;
      for (PetscInt d = 0; d < dof; d++) local += EntryHash(e + (uint64_t) d, a[q * dof + d]);
    }
  PetscCall(VecRestoreArrayRead(x, &a));
  *sum = local;
  PetscCall(GlobalSumUInt64(comm, sum, 1));
  PetscFunctionReturn(0);
}

/* the attribute "checksum" (unsigned 64-bit) of the dataset at path; every rank, the same value */
static PetscErrorCode WriteChecksum(PetscViewer v, const char *path, uint64_t sum)
{
  hid_t  file, d, sp, a = -1;
  herr_t status = -1;

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5GetFileId(v, &file));
  d  = H5Dopen2(file, path, H5P_DEFAULT);
  sp = H5Screate(H5S_SCALAR);
  if (d >= 0 && sp >= 0) a = H5Acreate2(d, "checksum", H5T_STD_U64LE, sp, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) status = H5Awrite(a, H5T_NATIVE_UINT64, &sum);
  if (a >= 0) H5Aclose(a);
  if (sp >= 0) H5Sclose(sp);
  if (d >= 0) H5Dclose(d);
  PetscCheck(status >= 0, PETSC_COMM_SELF, PETSC_ERR_LIB, "checkpoint: cannot write the checksum of %s", path);
  PetscFunctionReturn(0);
}

/* The attributes of / (the counters, the rupture state and the relaxation's state) carry one more
   checksum, attributes_checksum: the sum mod 2^64 of a hash of (name, value) over every other
   numeric attribute there. It is computed from the file, as written and as read, so every
   attribute the checkpoint gains is covered. An integer is hashed as its 64-bit value, a real as
   its 8 bytes: a change of any one value, in range or not, changes the sum. */
#define ATTRS_CHECKSUM "attributes_checksum"
typedef struct {
  uint64_t sum;
  int      bad; /* an attribute that is not one numeric value */
} AttrsSum;

static herr_t AttrsSumOne(hid_t loc, const char *name, const H5A_info_t *info, void *ctx)
{
  AttrsSum   *s  = ctx;
  uint64_t    nh = 1469598103934665603ULL, bits = 0; /* FNV-1a of the name */
  hid_t       a, t, sp;
  H5T_class_t cls;
  int         ok = 0;

  (void) info;
  if (!strcmp(name, ATTRS_CHECKSUM)) return 0;
  for (const char *c = name; *c; c++) nh = (nh ^ (unsigned char) *c) * 1099511628211ULL;
  if ((a = H5Aopen(loc, name, H5P_DEFAULT)) < 0) return s->bad = 1, -1;
  t   = H5Aget_type(a);
  sp  = H5Aget_space(a);
  cls = t >= 0 ? H5Tget_class(t) : H5T_NO_CLASS;
  if (sp >= 0 && H5Sget_simple_extent_npoints(sp) == 1) {
    if (cls == H5T_FLOAT) {
      double v;
      ok = H5Aread(a, H5T_NATIVE_DOUBLE, &v) >= 0;
      memcpy(&bits, &v, sizeof bits);
    } else if (cls == H5T_INTEGER) {
      long long v;
      ok   = H5Aread(a, H5T_NATIVE_LLONG, &v) >= 0;
      bits = (uint64_t) v;
    }
  }
  if (sp >= 0) H5Sclose(sp);
  if (t >= 0) H5Tclose(t);
  H5Aclose(a);
  if (!ok) return s->bad = 1, -1;
  s->sum += Mix64(bits ^ Mix64(nh + HASH_GOLDEN));
  return 0;
}

/* the checksum of the attributes of the group g (open); 0 if one is not a single number */
static int AttrsChecksum(hid_t g, uint64_t *sum)
{
  AttrsSum s = {0, 0};
  hsize_t  at = 0;
  if (H5Aiterate2(g, H5_INDEX_NAME, H5_ITER_INC, &at, AttrsSumOne, &s) < 0 || s.bad) return 0;
  *sum = s.sum;
  return 1;
}

/* attributes_checksum of /, from the attributes written; every rank, the same value */
static PetscErrorCode WriteAttrsChecksum(PetscViewer v)
{
  hid_t    file, g, sp = -1, a = -1;
  herr_t   status = -1;
  uint64_t sum;

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5GetFileId(v, &file));
  g = H5Gopen2(file, "/", H5P_DEFAULT);
  if (g >= 0 && AttrsChecksum(g, &sum)) sp = H5Screate(H5S_SCALAR);
  if (sp >= 0) a = H5Acreate2(g, ATTRS_CHECKSUM, H5T_STD_U64LE, sp, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) status = H5Awrite(a, H5T_NATIVE_UINT64, &sum);
  if (a >= 0) H5Aclose(a);
  if (sp >= 0) H5Sclose(sp);
  if (g >= 0) H5Gclose(g);
  PetscCheck(status >= 0, PETSC_COMM_SELF, PETSC_ERR_LIB, "checkpoint: cannot write the checksum of the attributes of /");
  PetscFunctionReturn(0);
}

/* ------------------------------------------------------------------ what a checkpoint holds */

/* the state vectors of a checkpoint, in /state */
typedef struct {
  const char *name;
  Vec        *vec;
  const char *root_flag; /* attribute that says it is there ("" = always) */
} StateVec;

static PetscInt StateVecs(FabricState *st, StateVec *sv)
{
  PetscInt n = 0;
#define ADD(...) \
  do { \
    PetscCheckAbort(n < MAX_STATE, PETSC_COMM_SELF, PETSC_ERR_PLIB, "StateVecs: more than %d state vectors, raise MAX_STATE", \
                    MAX_STATE); \
    sv[n++] = (StateVec){__VA_ARGS__}; \
  } while (0)
  ADD("positions", &st->X, "");
  ADD("velocities", &st->V, "");
  ADD("positions_old", &st->Xold, "has_positions_old");
  ADD("velocities_old", &st->Vold, "has_velocities_old");
  ADD("converged_positions", &st->Xconv, "has_converged_positions");
  ADD("converged_positions_prev", &st->Xconv_prev, "has_converged_positions_prev");
  ADD("friction_anchors_sphere", &st->anchor[0], "has_friction_anchors_sphere");
  ADD("friction_anchors_plane", &st->anchor[1], "has_friction_anchors_plane");
  ADD("friction_anchors_pedestal", &st->anchor[2], "has_friction_anchors_pedestal");
  ADD("static_balanced_1", &st->hist.Xh[0], "has_static_balanced_1");
  ADD("static_balanced_2", &st->hist.Xh[1], "has_static_balanced_2");
  ADD("static_balanced_3", &st->hist.Xh[2], "has_static_balanced_3");
  ADD("below_break_positions", &st->Xbelow, "has_below_break_positions");
#undef ADD
  return n;
}

/* The relaxation's state within a load step: what ApplyLoadStep set up and the te steps carried
   on (RelaxLoadStep's break round and te step, the jaw's ramp, the front, the step control and
   damping (FIRE's step and mixing), the last te step's balance test and its hold, the energy watch, the gravity of the load step, the te-frame
   counter). Attributes of /, written by every checkpoint and all restored, so that a restart
   within a load step continues it exactly (one at its end: ApplyLoadStep sets most of it anew). */
typedef struct {
  long   within, round, te_step, inner_steps, ramp_steps, ramp_done, front_step, front_covered, bound_fresh;
  long   last_balanced, te_frame_load_step, te_frame_base, fire_npos, fire_stops;
  long   balance_held, balance_need, watch_checks, watch_held, window_grow, window_bound_at, te_rebounds;
  double win_lo[2], win_hi[2], win_s;
  double travel_from, travel_now, te, te_bound, omega_max, damp_c, omega1, last_residual, last_speed, gravity[3];
  double fire_dt, fire_alpha, fire_scale[3], watch_h0, watch_hmin, watch_kmax;
  long   static_nhist, nonlinear_iterations, linear_iterations, static_newton; /* -solver static */
  double static_lh[3], static_shift, static_rnorm0;
  double elapsed;
  long   coarse_nonlinear_iterations, conv_segments, static_segments;
  long   te_measured, te_prev_step, tm_step[4], tm_end[4]; /* -te_measure: its count and its four records */
  double tm_te[4], tm_bound[4], tm_limit[4];
} RelaxState;

typedef struct {
  const char *name;
  int         real; /* double, else long */
  void       *value;
} Attr;

#define MAX_RELAX_ATTRS 96

static int RelaxAttrs(RelaxState *r, Attr *a)
{
  int n = 0;
#define ATTR_L(nm, f) (a[n++] = (Attr){nm, 0, &r->f})
#define ATTR_D(nm, f) (a[n++] = (Attr){nm, 1, &r->f})
  ATTR_L("within_load_step", within), ATTR_L("relax_round", round), ATTR_L("relax_te_step", te_step);
  ATTR_L("relax_inner_steps", inner_steps), ATTR_L("ramp_steps", ramp_steps), ATTR_L("ramp_done", ramp_done);
  ATTR_L("front_step", front_step), ATTR_L("front_covered", front_covered), ATTR_L("bound_fresh", bound_fresh);
  ATTR_L("last_balanced", last_balanced), ATTR_L("te_frame_load_step", te_frame_load_step);
  ATTR_L("te_frame_base", te_frame_base);
  ATTR_D("travel_from_m", travel_from), ATTR_D("travel_now_m", travel_now), ATTR_D("te_now_s", te);
  ATTR_D("te_bound_s", te_bound), ATTR_D("omega_max_rad_s", omega_max), ATTR_D("damping_c_1_s", damp_c);
  ATTR_D("omega1_rad_s", omega1), ATTR_D("last_residual", last_residual), ATTR_D("last_speed_m_s", last_speed);
  ATTR_D("gravity_now_x_m_s2", gravity[0]), ATTR_D("gravity_now_y_m_s2", gravity[1]);
  ATTR_D("gravity_now_z_m_s2", gravity[2]);
  ATTR_D("fire_dt_s", fire_dt), ATTR_D("fire_alpha", fire_alpha), ATTR_L("fire_positive_steps", fire_npos);
  ATTR_L("fire_stops", fire_stops), ATTR_D("fire_scale_power", fire_scale[0]);
  ATTR_D("fire_scale_force2", fire_scale[1]), ATTR_D("fire_scale_speed2", fire_scale[2]);
  ATTR_L("balance_held", balance_held), ATTR_L("balance_need", balance_need);
  ATTR_L("energy_watch_checks", watch_checks), ATTR_D("energy_watch_first_J", watch_h0);
  ATTR_D("energy_watch_lowest_J", watch_hmin), ATTR_D("energy_watch_kinetic_J", watch_kmax);
  ATTR_L("energy_watch_held", watch_held), ATTR_L("te_window_doublings", window_grow);
  ATTR_L("te_window_set_at", window_bound_at);
  ATTR_L("te_rebounds", te_rebounds), ATTR_D("te_window_warp_lo", win_lo[0]), ATTR_D("te_window_warp_hi", win_hi[0]);
  ATTR_D("te_window_weft_lo", win_lo[1]), ATTR_D("te_window_weft_hi", win_hi[1]), ATTR_D("te_window_shear", win_s);
  ATTR_L("static_balanced_count", static_nhist), ATTR_D("static_load_factor_1", static_lh[0]);
  ATTR_D("static_load_factor_2", static_lh[1]), ATTR_D("static_load_factor_3", static_lh[2]);
  ATTR_D("static_shift", static_shift), ATTR_L("nonlinear_iterations", nonlinear_iterations);
  ATTR_L("static_newton_steps", static_newton), ATTR_D("static_residual_norm0", static_rnorm0);
  ATTR_L("linear_iterations", linear_iterations), ATTR_D("load_step_elapsed_s", elapsed);
  ATTR_L("coarse_nonlinear_iterations", coarse_nonlinear_iterations), ATTR_L("converged_positions_segments", conv_segments);
  ATTR_L("static_balanced_segments", static_segments);
  ATTR_L("te_measure_states", te_measured), ATTR_L("te_measure_prev_load_step", te_prev_step);
  {
    static const char *const rec[4] = {"first", "last", "tightest", "worst"};
    static char              names[4][5][48];
    for (int q = 0; q < 4; q++) {
      const char *const fld[5] = {"load_step", "end", "te_s", "te_bound_s", "limit_s"};
      for (int k = 0; k < 5; k++) snprintf(names[q][k], sizeof names[q][k], "te_measure_%s_%s", rec[q], fld[k]);
      a[n++] = (Attr){names[q][0], 0, &r->tm_step[q]}, a[n++] = (Attr){names[q][1], 0, &r->tm_end[q]};
      a[n++] = (Attr){names[q][2], 1, &r->tm_te[q]}, a[n++] = (Attr){names[q][3], 1, &r->tm_bound[q]};
      a[n++] = (Attr){names[q][4], 1, &r->tm_limit[q]};
    }
  }
#undef ATTR_L
#undef ATTR_D
  return n;
}

/* at: where RelaxLoadStep is within the load step, NULL at its end */
static void RelaxStatePack(Fabric fab, const RelaxPoint *at, RelaxState *r)
{
  r->within        = at != NULL;
  r->round         = at ? (long) at->round : 0;
  r->te_step       = at ? (long) at->te_step : 0;
  r->static_newton = at ? (long) at->newton : 0;
  r->inner_steps   = at ? (long) at->inner_steps : 0;
  r->ramp_steps    = (long) fab->load.ramp_steps;
  r->ramp_done     = (long) fab->load.ramp_done;
  r->front_step    = (long) fab->front.front_step;
  r->front_covered = (long) fab->front.front_covered;
  r->bound_fresh   = (long) fab->step.bound_fresh;
  r->last_balanced = (long) fab->step.last.balanced;
  r->travel_from   = fab->load.travel_from;
  r->travel_now    = fab->load.travel_now;
  r->elapsed       = fab->load.elapsed;
  r->coarse_nonlinear_iterations = (long) fab->stats.coarse_nonlinear_iterations;
  r->conv_segments               = (long) fab->state.conv_segments;
  r->static_segments             = (long) fab->state.hist.segments;
  r->te            = fab->step.te;
  r->te_bound      = fab->step.te_bound;
  r->omega_max     = fab->step.omega_max;
  r->damp_c        = fab->step.damp_c;
  r->omega1        = fab->step.omega1;
  r->last_residual = fab->step.last.residual;
  r->last_speed    = fab->step.last.speed;
  for (int d = 0; d < 3; d++) r->gravity[d] = fab->load.gravity_now[d];
  r->te_frame_load_step = (long) fab->io->te_load_step;
  r->te_frame_base      = (long) fab->io->te_base;
  r->fire_dt            = fab->step.fire_dt;
  r->fire_alpha         = fab->step.fire_alpha;
  r->fire_npos          = (long) fab->step.fire_npos;
  r->fire_stops         = (long) fab->step.fire_stops;
  for (int q = 0; q < 3; q++) r->fire_scale[q] = fab->step.fire_scale[q];
  r->static_nhist       = (long) fab->state.hist.nhist;
  r->static_shift       = fab->state.hist.shift;
  r->static_rnorm0      = fab->state.hist.rnorm0;
  for (int q = 0; q < 3; q++) r->static_lh[q] = fab->state.hist.lh[q];
  r->nonlinear_iterations = (long) fab->stats.nonlinear_iterations;
  r->linear_iterations    = (long) fab->stats.linear_iterations;
  r->balance_held       = (long) fab->step.balance_held;
  r->balance_need       = (long) fab->step.balance_need;
  r->watch_checks       = (long) fab->step.watch_checks;
  r->watch_held         = (long) fab->step.watch_held;
  r->window_grow        = (long) fab->step.window_grow;
  r->window_bound_at    = (long) fab->step.window_bound_at;
  r->watch_h0           = fab->step.watch_h0;
  r->watch_hmin         = fab->step.watch_hmin;
  r->watch_kmax         = fab->step.watch_kmax;
  r->te_rebounds        = (long) fab->stats.te_rebounds;
  for (int d = 0; d < 2; d++) r->win_lo[d] = fab->grid.patch.win_lo[d], r->win_hi[d] = fab->grid.patch.win_hi[d];
  r->win_s = fab->grid.patch.win_s;
  {
    const TeMeasure *m[4] = {&fab->step.te_first, &fab->step.te_last, &fab->step.te_tightest, &fab->step.te_worst};
    r->te_measured  = (long) fab->step.te_measured;
    r->te_prev_step = (long) fab->step.te_prev_step;
    for (int q = 0; q < 4; q++)
      r->tm_step[q] = (long) m[q]->load_step, r->tm_end[q] = (long) m[q]->end, r->tm_te[q] = m[q]->te,
      r->tm_bound[q] = m[q]->te_bound, r->tm_limit[q] = m[q]->limit;
  }
}

static void RelaxStateUnpack(const RelaxState *r, Fabric fab)
{
  fab->load.ramp_steps     = (PetscInt) r->ramp_steps;
  fab->load.ramp_done      = (PetscInt) r->ramp_done;
  fab->front.front_step    = (PetscInt) r->front_step;
  fab->front.front_covered = r->front_covered ? PETSC_TRUE : PETSC_FALSE;
  fab->step.bound_fresh    = r->bound_fresh ? PETSC_TRUE : PETSC_FALSE;
  fab->step.last.balanced  = r->last_balanced ? PETSC_TRUE : PETSC_FALSE;
  fab->load.travel_from    = r->travel_from;
  fab->load.travel_now     = r->travel_now;
  fab->load.elapsed        = r->elapsed;
  fab->stats.coarse_nonlinear_iterations = (PetscInt64) r->coarse_nonlinear_iterations;
  fab->state.conv_segments               = (PetscInt64) r->conv_segments;
  fab->state.hist.segments               = (PetscInt64) r->static_segments;
  fab->step.te             = r->te;
  fab->step.te_bound       = r->te_bound;
  fab->step.omega_max      = r->omega_max;
  fab->step.damp_c         = r->damp_c;
  fab->step.omega1         = r->omega1;
  fab->step.last.residual  = r->last_residual;
  fab->step.last.speed     = r->last_speed;
  for (int d = 0; d < 3; d++) fab->load.gravity_now[d] = r->gravity[d];
  fab->io->te_load_step = (PetscInt) r->te_frame_load_step;
  fab->io->te_base      = (PetscInt64) r->te_frame_base;
  fab->step.fire_dt     = r->fire_dt;
  fab->step.fire_alpha  = r->fire_alpha;
  fab->step.fire_npos   = (PetscInt) r->fire_npos;
  fab->step.fire_stops  = (PetscInt64) r->fire_stops;
  for (int q = 0; q < 3; q++) fab->step.fire_scale[q] = r->fire_scale[q];
  fab->state.hist.nhist = (PetscInt) r->static_nhist;
  fab->state.hist.shift = r->static_shift;
  fab->state.hist.rnorm0 = r->static_rnorm0;
  for (int q = 0; q < 3; q++) fab->state.hist.lh[q] = r->static_lh[q];
  fab->stats.nonlinear_iterations = (PetscInt64) r->nonlinear_iterations;
  fab->stats.linear_iterations    = (PetscInt64) r->linear_iterations;
  fab->step.balance_held = (PetscInt) r->balance_held;
  fab->step.balance_need = (PetscInt) r->balance_need;
  fab->step.watch_checks = (PetscInt) r->watch_checks;
  fab->step.watch_held   = (PetscInt) r->watch_held;
  fab->step.window_grow  = (PetscInt) r->window_grow;
  fab->step.window_bound_at = (PetscInt64) r->window_bound_at;
  fab->step.watch_h0     = r->watch_h0;
  fab->step.watch_hmin   = r->watch_hmin;
  fab->step.watch_kmax   = r->watch_kmax;
  fab->stats.te_rebounds = (PetscInt64) r->te_rebounds;
  for (int d = 0; d < 2; d++) fab->grid.patch.win_lo[d] = r->win_lo[d], fab->grid.patch.win_hi[d] = r->win_hi[d];
  fab->grid.patch.win_s = r->win_s;
  {
    TeMeasure *m[4] = {&fab->step.te_first, &fab->step.te_last, &fab->step.te_tightest, &fab->step.te_worst};
    fab->step.te_measured  = (PetscInt) r->te_measured;
    fab->step.te_prev_step = (PetscInt) r->te_prev_step;
    for (int q = 0; q < 4; q++)
      m[q]->load_step = (PetscInt) r->tm_step[q], m[q]->end = r->tm_end[q] ? PETSC_TRUE : PETSC_FALSE, m[q]->te = r->tm_te[q],
      m[q]->te_bound = r->tm_bound[q], m[q]->limit = r->tm_limit[q];
  }
}

/* broken segments of the owned points as a dof-2 vector: [to i+1, to j+1] */
static PetscErrorCode BrokenToVec(const Patch *p, Vec B)
{
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

/* the ghosted broken flags from the owned ones (B, a vector of da_seg): one halo exchange */
static PetscErrorCode BrokenFromVec(DM da_seg, Patch *p, Vec B)
{
  Vec                Bl;
  const PetscScalar *b;

  PetscFunctionBeginUser;
  PetscCall(DMGetLocalVector(da_seg, &Bl));
  PetscCall(HaloExchange(da_seg, B, Bl));
  PetscCall(VecGetArrayRead(Bl, &b));
  for (PetscInt k = 0; k < p->gxm * p->gym; k++) {
    p->broken_x[k] = b[2 * k] != 0;
    p->broken_y[k] = b[2 * k + 1] != 0;
  }
  PetscCall(VecRestoreArrayRead(Bl, &b));
  PetscCall(DMRestoreLocalVector(da_seg, &Bl));
  PetscFunctionReturn(0);
}

/* ------------------------------------------------------------------ writing */

/* /state: the state vectors and the broken segments, each with its checksum */
static PetscErrorCode WriteState(MPI_Comm comm, const FabricGrid *g, FabricState *st, PetscViewer v)
{
  StateVec sv[MAX_STATE];
  PetscInt nsv = StateVecs(st, sv);
  char     path[128];
  uint64_t sum;
  Vec      B;

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5PushGroup(v, "/state"));
  for (PetscInt k = 0; k < nsv; k++) {
    Vec x   = *sv[k].vec;
    int has = x != NULL;
    if (sv[k].root_flag[0]) PetscCall(PetscViewerHDF5WriteAttribute(v, "/", sv[k].root_flag, PETSC_INT, &has));
    if (!x) continue;
    PetscCall(ViewDMDA(x, sv[k].name, v));
    PetscCall(GridChecksum(comm, &g->patch, x, &sum));
    PetscCall(PetscSNPrintf(path, sizeof path, "/state/%s", sv[k].name));
    PetscCall(WriteChecksum(v, path, sum));
  }
  PetscCall(DMGetGlobalVector(g->da_seg, &B));
  PetscCall(BrokenToVec(&g->patch, B));
  PetscCall(ViewDMDA(B, "broken_segments", v));
  PetscCall(GridChecksum(comm, &g->patch, B, &sum));
  PetscCall(WriteChecksum(v, "/state/broken_segments", sum));
  PetscCall(DMRestoreGlobalVector(g->da_seg, &B));
  PetscCall(PetscViewerHDF5PopGroup(v));
  PetscFunctionReturn(0);
}

/* an array held by rank 0 alone (the curve rows, the frame list): one 1-D dataset in /history, with its checksum */
static PetscErrorCode ViewRankZero(MPI_Comm comm, PetscMPIInt rank, PetscViewer v, const char *name, const PetscReal *a,
                                   PetscInt n)
{
  Vec          w;
  PetscScalar *x;
  uint64_t     sum = rank == 0 ? ArrayChecksum(a, (size_t) n) : 0;
  char         path[128];

  PetscFunctionBeginUser;
  PetscCall(VecCreateMPI(comm, rank == 0 ? n : 0, n, &w));
  PetscCall(VecGetArray(w, &x));
  if (rank == 0) PetscCall(PetscArraycpy(x, a, n));
  PetscCall(VecRestoreArray(w, &x));
  PetscCall(PetscObjectSetName((PetscObject) w, name));
  PetscCall(VecView(w, v));
  PetscCall(VecDestroy(&w));
  PetscCall(BroadcastFromRoot(comm, &sum, 1, MPI_UINT64_T));
  PetscCall(PetscSNPrintf(path, sizeof path, "/history/%s", name));
  PetscCall(WriteChecksum(v, path, sum));
  PetscFunctionReturn(0);
}

/* /history: the rows of the load steps done (none before the first is done) and the frame list */
static PetscErrorCode WriteHistory(Fabric fab, PetscViewer v, PetscInt done)
{
  FabricIO   io = fab->io;
  PetscReal *rows, *fr;

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5PushGroup(v, "/history"));
  if (done) {
    PetscCall(PetscMalloc1(CURVE_COLS * done, &rows));
    for (PetscInt k = 0; k < done; k++) CurveRowPack(&fab->stats.curve[k], rows + CURVE_COLS * k);
    PetscCall(ViewRankZero(fab->comm, fab->rank, v, "curve", rows, CURVE_COLS * done));
    PetscCall(PetscFree(rows));
  }
  if (io->frames) {
    PetscCall(PetscMalloc1(3 * io->frames, &fr));
    for (PetscInt k = 0; k < io->frames; k++) {
      fr[3 * k]     = io->frame[k].time;
      fr[3 * k + 1] = (PetscReal) io->frame[k].load_step;
      fr[3 * k + 2] = (PetscReal) io->frame[k].te_step;
    }
    PetscCall(ViewRankZero(fab->comm, fab->rank, v, "frames", fr, 3 * io->frames));
    PetscCall(PetscFree(fr));
  }
  PetscCall(PetscViewerHDF5PopGroup(v));
  PetscFunctionReturn(0);
}

/* /scene: what the run computes with */
static PetscErrorCode WriteScene(const Scene *s, PetscViewer v)
{
  SceneKey key[MAX_KEYS];
  PetscInt nkey = SceneKeys(s, key);

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5PushGroup(v, "/scene"));
  PetscCall(PetscViewerHDF5WriteGroup(v, NULL));
  for (PetscInt k = 0; k < nkey; k++)
    PetscCall(PetscViewerHDF5WriteAttribute(v, NULL, key[k].name, PETSC_REAL, &key[k].value));
  PetscCall(PetscViewerHDF5WriteAttribute(v, NULL, "scene", PETSC_STRING, s->out.name));
  PetscCall(PetscViewerHDF5PopGroup(v));
  PetscFunctionReturn(0);
}

/* the rupture state (fabric.h RuptureState) as attributes of / */
#define RUPTURE_ATTRS 21
static const char *const RuptureAttr[RUPTURE_ATTRS] = {
    "segments_broken", "first_break_ratio", "first_break_dir", "first_break_i", "first_break_j", "first_break_step",
    "first_break_time_s", "peak_force_N", "at_peak_force", "rupture_step", "rupture_time_s", "tear_te_steps",
    "break_load", "last_break_load", "last_force_N", "last_at", "peak_force_balanced", "below_kept",
    "below_load_factor", "breaks_located", "located_break_load"};

static void RupturePack(const RuptureState *r, PetscReal a[RUPTURE_ATTRS])
{
  a[0] = (PetscReal) r->segments, a[1] = r->first.ratio, a[2] = (PetscReal) r->first.dir;
  a[3] = (PetscReal) r->first.i, a[4] = (PetscReal) r->first.j, a[5] = (PetscReal) r->first_step;
  a[6] = r->first_time, a[7] = r->peak_force, a[8] = r->at_peak, a[9] = (PetscReal) r->rupture_step;
  a[10] = r->rupture_time, a[11] = (PetscReal) r->tear_te_steps;
  a[12] = r->load_now, a[13] = r->last_load, a[14] = r->last_force, a[15] = r->last_at;
  a[16] = (PetscReal) r->peak_balanced, a[17] = (PetscReal) r->have_below, a[18] = r->below_lambda;
  a[19] = (PetscReal) r->located, a[20] = r->located_ratio;
}

static void RuptureUnpack(const double a[RUPTURE_ATTRS], RuptureState *r)
{
  r->segments = (PetscInt64) a[0], r->first.ratio = a[1], r->first.dir = (PetscInt) a[2];
  r->first.i = (PetscInt) a[3], r->first.j = (PetscInt) a[4], r->first_step = (PetscInt) a[5];
  r->first_time = a[6], r->peak_force = a[7], r->at_peak = a[8], r->rupture_step = (PetscInt) a[9];
  r->rupture_time = a[10], r->tear_te_steps = (PetscInt64) a[11];
  r->load_now = a[12], r->last_load = a[13], r->last_force = a[14], r->last_at = a[15];
  r->peak_balanced = a[16] != 0 ? PETSC_TRUE : PETSC_FALSE;
  r->have_below = a[17] != 0 ? PETSC_TRUE : PETSC_FALSE, r->below_lambda = a[18];
  r->located = (PetscInt64) a[19], r->located_ratio = a[20];
}

/* the counters of the run, as attributes of /; done: the load steps done */
static PetscErrorCode WriteCounters(Fabric fab, PetscViewer v, PetscInt done)
{
  FabricIO io = fab->io;
  int version = CHECKPOINT_VERSION, load_step = (int) done, frames = (int) io->frames, converged = fab->stats.converged,
      broken = fab->stats.broken_any, ranks = fab->size;
  long      te_steps = (long) fab->stats.te_steps, updates = (long) fab->stats.point_updates;
  long      resets = (long) fab->step.ke_resets;
  PetscReal time = TestTime(&fab->s, &fab->load), wall = fab->stats.wall;

  PetscFunctionBeginUser;
  PetscCall(BroadcastFromRoot(fab->comm, &wall, 1, MPIU_REAL)); /* an attribute has one value on all ranks */
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
    b = (int) fab->front.keep_box[c];
    PetscCall(PetscSNPrintf(nm, sizeof nm, "keep_box_%d", c));
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", nm, PETSC_INT, &b));
  }
  PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "last_tension_max_N", PETSC_REAL, &fab->step.last.tension_max));
  /* kinetic damping: the kinetic energy after the last te step (a reset is decided on it) */
  PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "kinetic_energy_J", PETSC_REAL, &fab->step.ke_prev));
  PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "kinetic_resets", PETSC_LONG, &resets));
  {
    PetscReal r[RUPTURE_ATTRS];
    RupturePack(&fab->stats.rupture, r);
    for (int k = 0; k < RUPTURE_ATTRS; k++) PetscCall(PetscViewerHDF5WriteAttribute(v, "/", RuptureAttr[k], PETSC_REAL, &r[k]));
  }
  PetscFunctionReturn(0);
}

/* the relaxation's state (RelaxState), as attributes of / */
static PetscErrorCode WriteRelaxState(Fabric fab, PetscViewer v, const RelaxPoint *at)
{
  RelaxState r;
  Attr       a[MAX_RELAX_ATTRS];
  int        n = RelaxAttrs(&r, a);

  PetscFunctionBeginUser;
  RelaxStatePack(fab, at, &r);
  for (int k = 0; k < n; k++)
    PetscCall(PetscViewerHDF5WriteAttribute(v, "/", a[k].name, a[k].real ? PETSC_REAL : PETSC_LONG, a[k].value));
  PetscFunctionReturn(0);
}

/* every rank has closed tmp: rank 0 syncs it to disk and renames it into place (a kill before leaves the last
   checkpoint as it was) */
static PetscErrorCode CommitFile(MPI_Comm comm, PetscMPIInt rank, const char *dir, const char *tmp, const char *file)
{
  int ok = 1;

  PetscFunctionBeginUser;
  PetscCall(Barrier(comm));
  if (rank == 0) {
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
  PetscCall(BroadcastFromRoot(comm, &ok, 1, MPI_INT));
  PetscCheck(ok, comm, PETSC_ERR_FILE_WRITE, "-output_dir %s: cannot write checkpoint.h5", dir);
  PetscFunctionReturn(0);
}

/* DIR/checkpoint.h5 at the end of a load step (at = NULL) or within it, after te step at */
static PetscErrorCode CheckpointWrite(Fabric fab, const RelaxPoint *at)
{
  const char    *dir  = fab->s.out.output_dir;
  const PetscInt done = fab->load.load_step - (at ? 1 : 0);
  char           file[PETSC_MAX_PATH_LEN], tmp[PETSC_MAX_PATH_LEN];
  PetscViewer    v;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(EV_Output, 0, 0, 0, 0));
  if (at) { /* the wall time so far (the end of a load step has just taken it) */
    PetscCall(PetscTime(&fab->stats.wall));
    fab->stats.wall -= fab->stats.wall_start;
  }
  PetscCall(PetscSNPrintf(file, sizeof file, "%s/checkpoint.h5", dir));
  PetscCall(PetscSNPrintf(tmp, sizeof tmp, "%s/.checkpoint.h5.tmp", dir));
  PetscCall(PetscViewerHDF5Open(fab->comm, tmp, FILE_MODE_WRITE, &v));
  PetscCall(WriteState(fab->comm, &fab->grid, &fab->state, v));
  PetscCall(WriteHistory(fab, v, done));
  PetscCall(WriteScene(&fab->s, v));
  PetscCall(WriteCounters(fab, v, done));
  PetscCall(WriteRelaxState(fab, v, at));
  PetscCall(WriteAttrsChecksum(v)); /* last: it covers every attribute of / */
  PetscCall(PetscViewerDestroy(&v));
  PetscCall(CommitFile(fab->comm, fab->rank, dir, tmp, file));
  ckpt.last_te = fab->stats.te_steps;
  fab->io->checkpoints++;
  if (fab->rank == 0) PetscCall(PetscTime(&ckpt.last_wall));
  PetscCall(PetscLogEventEnd(EV_Output, 0, 0, 0, 0));
  if (fab->s.out.quiet) PetscFunctionReturn(0);
  if (at)
    PetscCall(PetscPrintf(fab->comm, "checkpoint at load step %" PetscInt_FMT ", %s step %" PetscInt_FMT ": %s\n",
                          fab->load.load_step, at->newton ? "Newton" : "te", at->inner_steps + at->te_step + at->newton,
                          file));
  else
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
  PetscCall(CheckpointWrite(fab, NULL));
  PetscFunctionReturn(0);
}

static const char *SignalName(int sig)
{
  return sig == SIGTERM ? "SIGTERM" : sig == SIGUSR1 ? "SIGUSR1" : "signal";
}

/* A look at the signal caught and rank 0's clock (look[1]: -checkpoint_every_s has passed since the last
   checkpoint), reduced in one max-reduction: every rank takes the same decision */
static PetscErrorCode Look(Fabric fab, PetscReal look[2])
{
  const PetscReal every_s = fab->s.out.checkpoint_every_s;

  PetscFunctionBeginUser;
  ckpt.last_look = fab->stats.te_steps;
  look[0]        = (PetscReal) caught_signal;
  look[1]        = 0;
  if (fab->rank == 0 && every_s > 0) {
    PetscLogDouble now;
    PetscCall(PetscTime(&now));
    look[1] = now - ckpt.last_wall >= every_s ? 1.0 : 0.0;
  }
  PetscCall(GlobalMax(fab->comm, look, 2));
  PetscFunctionReturn(0);
}

/* After te step `at` of a load step that continues: a checkpoint every -checkpoint_every_te te steps, once
   -checkpoint_every_s seconds have passed, or on SIGTERM or SIGUSR1, after which the run stops
   (CheckpointStopped). Signals and rank 0's clock are looked at every LOOK_EVERY te steps, in one
   max-reduction: every rank takes the same decision at the same te step. */
PetscErrorCode CheckpointTeStep(Fabric fab, const RelaxPoint *at)
{
  const SceneOutput *o       = &fab->s.out;
  PetscReal          look[2] = {0, 0}; /* the signal caught, rank 0's clock says a checkpoint is due */
  PetscBool          due;

  PetscFunctionBeginUser;
  if (!o->output_dir[0]) PetscFunctionReturn(0);
  due = o->checkpoint_every_te > 0 && fab->stats.te_steps - ckpt.last_te >= o->checkpoint_every_te;
  if (fab->stats.te_steps - ckpt.last_look >= LOOK_EVERY) {
    PetscCall(Look(fab, look));
    due = due || look[0] > 0 || look[1] > 0;
  }
  if (!due) PetscFunctionReturn(0);
  PetscCall(CheckpointWrite(fab, at));
  if (look[0] > 0) {
    ckpt.stopped_by = (int) look[0];
    PetscCall(PetscPrintf(fab->comm,
                          "fabric: %s: checkpoint written at load step %" PetscInt_FMT ", te step %" PetscInt_FMT
                          ": restart with -restart %s/checkpoint.h5\n",
                          SignalName(ckpt.stopped_by), fab->load.load_step, at->inner_steps + at->te_step,
                          o->output_dir));
  }
  PetscFunctionReturn(0);
}

/* A look (Look); on a signal or when the clock says so, the checkpoint of the load step's end (at = NULL) or of
   the Newton iterate at `at`; on a signal the run then stops (CheckpointStopped) */
static PetscErrorCode LookAndWrite(Fabric fab, const RelaxPoint *at)
{
  PetscReal look[2]; /* the signal caught, rank 0's clock says a checkpoint is due */
  char      where[96];

  PetscFunctionBeginUser;
  PetscCall(Look(fab, look));
  if (!(look[0] > 0) && !(look[1] > 0)) PetscFunctionReturn(0);
  PetscCall(CheckpointWrite(fab, at));
  if (!(look[0] > 0)) PetscFunctionReturn(0);
  ckpt.stopped_by = (int) look[0];
  if (at)
    PetscCall(PetscSNPrintf(where, sizeof where, "at load step %" PetscInt_FMT ", Newton step %" PetscInt_FMT,
                            fab->load.load_step, at->inner_steps + at->newton));
  else PetscCall(PetscSNPrintf(where, sizeof where, "at the end of load step %" PetscInt_FMT, fab->load.load_step));
  PetscCall(PetscPrintf(fab->comm, "fabric: %s: checkpoint written %s: restart with -restart %s/checkpoint.h5\n",
                        SignalName(ckpt.stopped_by), where, fab->s.out.output_dir));
  PetscFunctionReturn(0);
}

/* -solver static, after Newton step `at` of a solve that goes on (not a located break's trial): on SIGTERM or
   SIGUSR1 a checkpoint of the iterate, after which the run stops; once -checkpoint_every_s seconds have passed, a
   checkpoint. Each such Newton step looks (one small max-reduction, against a Newton step's tangent and linear
   solve): a load step's solve can take hours (the drape at 24 threads/cm, docs/static.md). */
PetscErrorCode CheckpointNewtonStep(Fabric fab, const RelaxPoint *at)
{
  PetscFunctionBeginUser;
  if (fab->s.out.output_dir[0]) PetscCall(LookAndWrite(fab, at));
  PetscFunctionReturn(0);
}

/* At the end of a load step that continues: on SIGTERM or SIGUSR1 a checkpoint of the load step, then the run
   stops; once -checkpoint_every_s seconds have passed, a checkpoint. The static path looks at every load step's
   end (and within its solves, CheckpointNewtonStep); the explicit path, which looks within its rounds
   (CheckpointTeStep), looks here too once LOOK_EVERY te steps have passed since its last look: its rounds of one
   te step (-max_inner_steps 1, or a prediction that balances at once) never look within, and a run of such load
   steps heard no signal. */
PetscErrorCode CheckpointLoadStepLook(Fabric fab, PetscBool static_path)
{
  PetscFunctionBeginUser;
  if (!fab->s.out.output_dir[0]) PetscFunctionReturn(0);
  if (!static_path && fab->stats.te_steps - ckpt.last_look < LOOK_EVERY) PetscFunctionReturn(0);
  PetscCall(LookAndWrite(fab, NULL));
  PetscFunctionReturn(0);
}

/* ------------------------------------------------------------------ restart */

typedef struct {     /* what rank 0 reads alone, then broadcasts */
  int        status; /* 0: fine; otherwise msg says what is wrong */
  char       msg[5 * PETSC_MAX_PATH_LEN];
  int        load_step, frames, converged, broken_any; /* load_step: the load steps done */
  int        has[MAX_STATE];
  long long  te_steps, point_updates;
  double     grip_disp, grip_step_prev, wall;
  uint64_t   sum[MAX_STATE + 1]; /* checksums of the state vectors, then of the broken segments */
  int        awake_box[4], keep_box[4];
  double     last_tension_max;
  double     ke_prev;
  long long  ke_resets;
  double     rupture[RUPTURE_ATTRS];
  RelaxState relax;
} Header;

/* a scalar attribute (one value: a damaged file's array would be read past value) */
static int ReadAttr(hid_t obj, const char *name, hid_t type, void *value)
{
  hid_t a, sp;
  int   ok;
  if (H5Aexists(obj, name) <= 0) return 0;
  a = H5Aopen(obj, name, H5P_DEFAULT);
  if (a < 0) return 0;
  sp = H5Aget_space(a);
  ok = sp >= 0 && H5Sget_simple_extent_npoints(sp) == 1 && H5Aread(a, type, value) >= 0;
  if (sp >= 0) H5Sclose(sp);
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

/* Can a grid dataset (dims[0] rows of dims[1] x dims[2] values) be read whole? Rank 0 reads it, rows at a time,
   before the ranks load it together: a damaged one (data past the file's end, a filter this HDF5 lacks) failed
   inside VecLoad with HDF5's error stack on every rank and no word of -restart */
#define READ_ROWS_VALUES (1 << 20) /* values read at a time */
static int DatasetReadable(hid_t fid, const char *path, const hsize_t dims[3])
{
  const hsize_t row = dims[1] * dims[2], rows = PetscMax(1, READ_ROWS_VALUES / PetscMax(row, 1));
  hid_t         d = H5Dopen2(fid, path, H5P_DEFAULT), sp = d >= 0 ? H5Dget_space(d) : -1;
  double       *buf = malloc(sizeof(double) * (size_t) (PetscMin(rows, dims[0]) * row));
  int           ok  = d >= 0 && sp >= 0 && buf;

  for (hsize_t j = 0; ok && j < dims[0]; j += rows) {
    const hsize_t start[3] = {j, 0, 0}, count[3] = {PetscMin(rows, dims[0] - j), dims[1], dims[2]};
    hid_t         mem      = H5Screate_simple(3, count, NULL);
    ok = mem >= 0 && H5Sselect_hyperslab(sp, H5S_SELECT_SET, start, NULL, count, NULL) >= 0 &&
         H5Dread(d, H5T_NATIVE_DOUBLE, mem, sp, H5P_DEFAULT, buf) >= 0;
    if (mem >= 0) H5Sclose(mem);
  }
  free(buf);
  if (sp >= 0) H5Sclose(sp);
  if (d >= 0) H5Dclose(d);
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
      {"pull", PullAxisNames, 2}, {"integrator", IntegratorNames, 3}, {"predict", PredictNames, 3},
      {"test", TestNames, 5},     {"shape", ShapeNames, 3},           {"clamp", ClampNames, 4},
      {"solver", SolverNames, 2},
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

/* the attribute "checksum" of the dataset at path */
static int ReadChecksum(hid_t fid, const char *path, uint64_t *sum)
{
  hid_t d = H5Dopen2(fid, path, H5P_DEFAULT);
  int   ok;
  if (d < 0) return 0;
  ok = ReadAttr(d, "checksum", H5T_NATIVE_UINT64, sum);
  H5Dclose(d);
  return ok;
}

/* what is wrong with the checkpoint, in h->msg; the checks below return 0 then */
#define REFUSE(...) (h->status = 1, snprintf(h->msg, sizeof h->msg, __VA_ARGS__), 0)

/* the checkpoint's /scene group g against this run's scene and grid; 0 (and h->msg) if they differ */
static int SameScene(const Scene *s, hid_t g, const char *file, Header *h)
{
  SceneKey key[MAX_KEYS];
  PetscInt nkey = SceneKeys(s, key);
  double   there[MAX_KEYS];
  char     name[PETSC_MAX_PATH_LEN] = "?";
  hid_t    a;

  for (PetscInt k = 0; k < nkey; k++)
    if (!ReadAttr(g, key[k].name, H5T_NATIVE_DOUBLE, &there[k]))
      return REFUSE("-restart %s: damaged checkpoint: /scene has no %s", file, key[k].name);
  a = H5Aexists(g, "scene") > 0 ? H5Aopen(g, "scene", H5P_DEFAULT) : -1;
  if (a >= 0) {
    hid_t t = H5Aget_type(a);
    if (H5Tget_size(t) < sizeof name) H5Aread(a, t, name);
    H5Tclose(t);
    H5Aclose(a);
  }
  if (there[0] != (double) s->spec.nx || there[1] != (double) s->spec.ny)
    return REFUSE("-restart %s: the checkpoint is of another grid: %g x %g crossings there (scene %s), %" PetscInt_FMT
                  " x %" PetscInt_FMT " here (scene %s): restart with the scene and options of the checkpointed run",
                  file, there[0], there[1], name, s->spec.nx, s->spec.ny, s->out.name);
  for (PetscInt k = 2; k < nkey; k++)
    if (there[k] != (double) key[k].value) {
      char va[64], vb[64];
      KeyValue(key[k].name, there[k], va, sizeof va, (double) key[k].value);
      KeyValue(key[k].name, (double) key[k].value, vb, sizeof vb, there[k]);
      return REFUSE("-restart %s: the checkpoint is of another scene: %s = %s there (scene %s), %s here (scene %s): "
                    "restart with the scene and options of the checkpointed run",
                    file, key[k].name, va, name, vb, s->out.name);
    }
  return 1;
}

/* FILE is HDF5, a fabric checkpoint of this format, of this scene and grid; *fid: the open file */
static int OpenCheckpoint(const Scene *s, const char *file, Header *h, hid_t *fid)
{
  int   version = 0, ok;
  hid_t g;

  if (H5Fis_hdf5(file) <= 0)
    return REFUSE("-restart %s: not an HDF5 file, so not a checkpoint (give the checkpoint.h5 that -checkpoint_every "
                  "wrote)",
                  file);
  *fid = H5Fopen(file, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (*fid < 0) return REFUSE("-restart %s: the HDF5 file cannot be opened: it is damaged or truncated", file);
  g  = H5Gopen2(*fid, "/", H5P_DEFAULT);
  ok = ReadAttr(g, "fabric_checkpoint", H5T_NATIVE_INT, &version);
  H5Gclose(g);
  if (!ok)
    return REFUSE("-restart %s: not a fabric checkpoint (no fabric_checkpoint attribute): give the checkpoint.h5 that "
                  "-checkpoint_every wrote",
                  file);
  if (version != CHECKPOINT_VERSION)
    return REFUSE("-restart %s: checkpoint format %d, this fabric reads format %d", file, version, CHECKPOINT_VERSION);
  if (H5Lexists(*fid, "/scene", H5P_DEFAULT) <= 0 || (g = H5Gopen2(*fid, "/scene", H5P_DEFAULT)) < 0)
    return REFUSE("-restart %s: damaged checkpoint: no /scene group", file);
  ok = SameScene(s, g, file, h);
  H5Gclose(g);
  return ok;
}

/* the relaxation's state; within a load step, where it is must be a te step it continues from */
static int ReadRelaxState(const Scene *s, hid_t g, const char *file, Header *h)
{
  RelaxState *r = &h->relax;
  Attr        a[MAX_RELAX_ATTRS];
  int         n = RelaxAttrs(r, a);

  for (int k = 0; k < n; k++)
    if (!ReadAttr(g, a[k].name, a[k].real ? H5T_NATIVE_DOUBLE : H5T_NATIVE_LONG, a[k].value))
      return REFUSE("-restart %s: damaged checkpoint: the relaxation's state (%s) is missing", file, a[k].name);
    else if (a[k].real && !isfinite(*(double *) a[k].value)) /* a NaN te or travel failed later, naming no cause */
      return REFUSE("-restart %s: damaged checkpoint: %s = %g is not a finite number", file, a[k].name,
                    *(double *) a[k].value);
  if (r->within != 0 && r->within != 1)
    return REFUSE("-restart %s: damaged checkpoint: within_load_step = %ld", file, r->within);
  if (r->static_nhist < 0 || r->static_nhist > 3)
    return REFUSE("-restart %s: damaged checkpoint: static_balanced_count = %ld (0 to 3)", file, r->static_nhist);
  if (r->window_grow < 0 || r->window_grow > WINDOW_GROW_MAX)
    return REFUSE("-restart %s: damaged checkpoint: te_window_doublings = %ld (0 to %d)", file, r->window_grow,
                  WINDOW_GROW_MAX);
  if (r->te_measured < 0 || r->te_prev_step < 0 || r->te_prev_step > s->load.load_steps)
    return REFUSE("-restart %s: damaged checkpoint: te_measure_states = %ld, te_measure_prev_load_step = %ld (0 to %" PetscInt_FMT
                  ")", file, r->te_measured, r->te_prev_step, s->load.load_steps);
  for (int q = 0; r->te_measured > 0 && q < 4; q++) /* summary.json's te / limit of each record */
    if (r->tm_step[q] < 1 || r->tm_step[q] > s->load.load_steps || (r->tm_end[q] != 0 && r->tm_end[q] != 1) ||
        !(r->tm_limit[q] > 0) || r->tm_te[q] < 0 || r->tm_bound[q] < 0)
      return REFUSE("-restart %s: damaged checkpoint: te_measure record %d: load step %ld, end %ld, te %g s, bound %g s, "
                    "limit %g s", file, q, r->tm_step[q], r->tm_end[q], r->tm_te[q], r->tm_bound[q], r->tm_limit[q]);
  if (r->static_newton < 0 || r->static_newton > PETSC_MAX_INT || (r->static_newton > 0 && !r->within) ||
      r->static_rnorm0 < 0)
    return REFUSE("-restart %s: damaged checkpoint: static_newton_steps = %ld, static_residual_norm0 = %g at a load "
                  "step's %s", file, r->static_newton, r->static_rnorm0, r->within ? "Newton step" : "end");
  if (r->within && r->static_newton > 0 &&
      (r->te_step != 0 || r->round < 0 || r->inner_steps < 0 || r->inner_steps > PETSC_MAX_INT - r->static_newton))
    return REFUSE("-restart %s: damaged checkpoint: Newton step %ld of round %ld, after %ld Newton steps, with te step %ld",
                  file, r->static_newton, r->round, r->inner_steps, r->te_step);
  if (r->within && (r->static_newton > 0) != (s->num.solver == SOLVER_STATIC)) /* the scene keys hold the solver */
    return REFUSE("-restart %s: damaged checkpoint: %s within a load step of a%s run", file,
                  r->static_newton > 0 ? "a Newton step's checkpoint" : "a te step's checkpoint",
                  s->num.solver == SOLVER_STATIC ? " -solver static" : "n explicit");
  if (r->within && !r->static_newton &&
      (r->te_step < 1 || r->te_step >= s->load.max_inner_steps || r->round < 0 || r->inner_steps < 0))
    return REFUSE(
        "-restart %s: damaged checkpoint: te step %ld of round %ld within a load step of at most %" PetscInt_FMT
        " te steps",
        file, r->te_step, r->round, s->load.max_inner_steps);
  return 1;
}

/* the rupture state's counts and indices (curve rows, load steps, crossings) within their ranges: a
   rupture ends its load step, so rupture_step is one of the load steps done; the first break may be
   in the load step a checkpoint is within */
static int RuptureInRange(const Scene *s, const char *file, Header *h)
{
  const double done = h->load_step, in = done + (double) h->relax.within, nx = (double) s->spec.nx,
               ny = (double) s->spec.ny;
  const struct {
    int    k;
    double lo, hi;
    char   what[32];
  } range[] = {
      {0, 0, 2 * nx * ny, "segments of the grid"}, {2, 0, 1, "0 warp, 1 weft"},
      {3, 0, nx - 1, "crossings in x"},            {4, 0, ny - 1, "crossings in y"},
      {5, 0, in, "load steps"},                    {9, 0, done, "load steps done"},
      {11, 0, (double) h->te_steps, "te steps"},   {17, 0, 1, "0 or 1"},
      {19, 0, 2 * nx * ny, "segments of the grid"},
  };
  for (size_t r = 0; r < sizeof range / sizeof range[0]; r++) {
    const double v = h->rupture[range[r].k];
    if (!(v >= range[r].lo && v <= range[r].hi && v == floor(v)))
      return REFUSE("-restart %s: damaged checkpoint: %s = %.17g (a whole number from %.17g to %.17g, %s)", file,
                    RuptureAttr[range[r].k], v, range[r].lo, range[r].hi, range[r].what);
  }
  return 1;
}

/* the counters of the run: attributes of the root group g */
static int ReadCounters(const Scene *s, hid_t g, const char *file, Header *h)
{
  const PetscInt K = s->load.load_steps;

  if (!ReadAttr(g, "load_step", H5T_NATIVE_INT, &h->load_step) || !ReadAttr(g, "frames", H5T_NATIVE_INT, &h->frames) ||
      !ReadAttr(g, "converged", H5T_NATIVE_INT, &h->converged) ||
      !ReadAttr(g, "broken_any", H5T_NATIVE_INT, &h->broken_any) ||
      !ReadAttr(g, "te_steps", H5T_NATIVE_LLONG, &h->te_steps) ||
      !ReadAttr(g, "point_updates", H5T_NATIVE_LLONG, &h->point_updates) ||
      !ReadAttr(g, "grip_disp_m", H5T_NATIVE_DOUBLE, &h->grip_disp) ||
      !ReadAttr(g, "grip_step_prev_m", H5T_NATIVE_DOUBLE, &h->grip_step_prev) ||
      !ReadAttr(g, "wall_s", H5T_NATIVE_DOUBLE, &h->wall))
    return REFUSE("-restart %s: damaged checkpoint: a counter of the run is missing", file);
  if (!ReadAttr(g, "awake_box_0", H5T_NATIVE_INT, &h->awake_box[0]) ||
      !ReadAttr(g, "awake_box_1", H5T_NATIVE_INT, &h->awake_box[1]) ||
      !ReadAttr(g, "awake_box_2", H5T_NATIVE_INT, &h->awake_box[2]) ||
      !ReadAttr(g, "awake_box_3", H5T_NATIVE_INT, &h->awake_box[3]) ||
      !ReadAttr(g, "keep_box_0", H5T_NATIVE_INT, &h->keep_box[0]) ||
      !ReadAttr(g, "keep_box_1", H5T_NATIVE_INT, &h->keep_box[1]) ||
      !ReadAttr(g, "keep_box_2", H5T_NATIVE_INT, &h->keep_box[2]) ||
      !ReadAttr(g, "keep_box_3", H5T_NATIVE_INT, &h->keep_box[3]) ||
      !ReadAttr(g, "last_tension_max_N", H5T_NATIVE_DOUBLE, &h->last_tension_max))
    return REFUSE("-restart %s: damaged checkpoint: the sleeping state is missing", file);
  if (!ReadAttr(g, "kinetic_energy_J", H5T_NATIVE_DOUBLE, &h->ke_prev) ||
      !ReadAttr(g, "kinetic_resets", H5T_NATIVE_LLONG, &h->ke_resets))
    return REFUSE("-restart %s: damaged checkpoint: the kinetic damping state is missing", file);
  for (int k = 0; k < RUPTURE_ATTRS; k++)
    if (!ReadAttr(g, RuptureAttr[k], H5T_NATIVE_DOUBLE, &h->rupture[k]))
      return REFUSE("-restart %s: damaged checkpoint: the rupture state (%s) is missing", file, RuptureAttr[k]);
  { /* the real counters finite: a NaN grip travel ran into "numerical instability", a NaN wall time ended
       "done in nan s" */
    const struct {
      const char *name;
      double      v;
    } real[] = {{"grip_disp_m", h->grip_disp},           {"grip_step_prev_m", h->grip_step_prev},
                {"wall_s", h->wall},                     {"last_tension_max_N", h->last_tension_max},
                {"kinetic_energy_J", h->ke_prev}};
    for (size_t k = 0; k < sizeof real / sizeof real[0]; k++)
      if (!isfinite(real[k].v))
        return REFUSE("-restart %s: damaged checkpoint: %s = %g is not a finite number", file, real[k].name, real[k].v);
  }
  if (!ReadRelaxState(s, g, file, h)) return 0;
  /* at the end of load step 1..K, or within load step 1..K (load steps done: 0..K-1) */
  if (h->load_step < 1 - h->relax.within || h->load_step > K - h->relax.within || h->frames < 0 || h->te_steps < 0)
    return REFUSE("-restart %s: damaged checkpoint: load step %ld of %" PetscInt_FMT, file,
                  (long) h->load_step + h->relax.within, K);
  if (h->point_updates < 0)
    return REFUSE("-restart %s: damaged checkpoint: point_updates = %lld", file, h->point_updates);
  if (!RuptureInRange(s, file, h)) return 0;
  for (int k = 0; k < RUPTURE_ATTRS; k++) /* the forces, travels and times besides the counts checked above */
    if (!isfinite(h->rupture[k]))
      return REFUSE("-restart %s: damaged checkpoint: %s = %g is not a finite number", file, RuptureAttr[k],
                    h->rupture[k]);
  return 1;
}

/* the state vectors and the broken segments: there, of this grid, with their checksums (g: the root group) */
static int CheckStateDatasets(const Scene *s, FabricState *st, hid_t fid, hid_t g, const char *file, Header *h)
{
  StateVec      sv[MAX_STATE];
  PetscInt      nsv      = StateVecs(st, sv);
  const hsize_t dims3[3] = {(hsize_t) s->spec.ny, (hsize_t) s->spec.nx, 3},
                dims2[3] = {(hsize_t) s->spec.ny, (hsize_t) s->spec.nx, 2};
  char path[128];

  for (PetscInt k = 0; k <= nsv; k++) {
    const int broken = k == nsv;
    snprintf(path, sizeof path, "/state/%s", broken ? "broken_segments" : sv[k].name);
    if (!broken) {
      h->has[k] = 1;
      if (sv[k].root_flag[0] && !ReadAttr(g, sv[k].root_flag, H5T_NATIVE_INT, &h->has[k]))
        return REFUSE("-restart %s: damaged checkpoint: no %s attribute", file, sv[k].root_flag);
      if (!h->has[k]) continue;
    }
    if (!CheckDataset(fid, path, 3, broken ? dims2 : dims3, NULL))
      return REFUSE("-restart %s: damaged checkpoint: %s is missing or not of the %" PetscInt_FMT " x %" PetscInt_FMT
                    " grid",
                    file, path, s->spec.nx, s->spec.ny);
    if (!ReadChecksum(fid, path, &h->sum[k]))
      return REFUSE("-restart %s: damaged checkpoint: %s has no checksum", file, path);
    if (!DatasetReadable(fid, path, broken ? dims2 : dims3))
      return REFUSE("-restart %s: damaged checkpoint: %s cannot be read", file, path);
  }
  if (s->num.integrator == INTEGRATOR_PAPER && !h->has[2])
    return REFUSE("-restart %s: damaged checkpoint: the paper integrator needs positions_old", file);
  return 1;
}

/* a 1-D array of /history into buf (n doubles), checked against its checksum */
static int ReadHistoryArray(hid_t fid, const char *file, const char *path, const char *what, hsize_t n, double *buf,
                            Header *h)
{
  uint64_t sum;
  if (!CheckDataset(fid, path, 1, &n, buf))
    return REFUSE("-restart %s: damaged checkpoint: %s does not hold %s", file, path, what);
  if (!ReadChecksum(fid, path, &sum)) return REFUSE("-restart %s: damaged checkpoint: %s has no checksum", file, path);
  if (ArrayChecksum(buf, (size_t) n) != sum)
    return REFUSE("-restart %s: damaged checkpoint: the checksum of %s does not match", file, path);
  return 1;
}

/* /history/frames holds the frames counted (none: no list), checked before the list is allocated: a damaged
   count (2^31 - 1) failed in the allocation on rank 0 alone, and a count of 0 beside a list dropped the frames
   of fabric.h5 */
static int FrameListLength(hid_t fid, const char *file, Header *h)
{
  const hsize_t n = 3 * (hsize_t) h->frames;
  const int     there =
      H5Lexists(fid, "/history", H5P_DEFAULT) > 0 && H5Lexists(fid, "/history/frames", H5P_DEFAULT) > 0;
  if (!h->frames && there)
    return REFUSE("-restart %s: damaged checkpoint: frames = 0, yet /history/frames is there", file);
  if (h->frames && !CheckDataset(fid, "/history/frames", 1, &n, NULL))
    return REFUSE("-restart %s: damaged checkpoint: /history/frames does not hold %d frames", file, h->frames);
  return 1;
}

/* Rank 0, alone (serial HDF5): is FILE a complete, undamaged checkpoint of this scene? Fills h and, on
   success, the curve rows (*rows, CURVE_COLS per load step done) and the frame list (*frames). */
static PetscErrorCode ReadHeader(Fabric fab, const char *file, Header *h, double **rows, double **frames)
{
  H5E_auto2_t efunc;
  void       *edata;
  hid_t       fid = -1, g = -1;
  char        what[64];

  PetscFunctionBeginUser;
  *rows = *frames = NULL;
  H5Eget_auto2(H5E_DEFAULT, &efunc, &edata);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* failures become one message, not an HDF5 error stack */
  if (OpenCheckpoint(&fab->s, file, h, &fid)) {
    g = H5Gopen2(fid, "/", H5P_DEFAULT);
    if (ReadCounters(&fab->s, g, file, h) && CheckStateDatasets(&fab->s, &fab->state, fid, g, file, h) &&
        FrameListLength(fid, file, h)) {
      PetscCall(PetscMalloc1(CURVE_COLS * h->load_step, rows));
      PetscCall(PetscMalloc1(3 * h->frames, frames));
      snprintf(what, sizeof what, "%d load steps", h->load_step);
      if (h->load_step == 0 ||
          ReadHistoryArray(fid, file, "/history/curve", what, CURVE_COLS * h->load_step, *rows, h)) {
        snprintf(what, sizeof what, "%d frames", h->frames);
        if (h->frames) ReadHistoryArray(fid, file, "/history/frames", what, 3 * h->frames, *frames, h);
      }
      if (!h->status) { /* last: a value out of its range has been named above */
        uint64_t want, sum;
        if (!ReadAttr(g, ATTRS_CHECKSUM, H5T_NATIVE_UINT64, &want))
          (void) REFUSE("-restart %s: damaged checkpoint: / has no " ATTRS_CHECKSUM, file);
        else if (!AttrsChecksum(g, &sum) || sum != want)
          (void) REFUSE("-restart %s: damaged checkpoint: the checksum of the attributes of / (the counters and the "
                        "relaxation's state) does not match",
                        file);
      }
    }
  }
  if (g >= 0) H5Gclose(g);
  if (fid >= 0) H5Fclose(fid);
  H5Eset_auto2(H5E_DEFAULT, efunc, edata);
  PetscFunctionReturn(0);
}

/* a string attribute of obj into buf (len bytes, at least 2): 0 if it is missing or longer */
static int ReadStringAttr(hid_t obj, const char *name, char *buf, size_t len)
{
  hid_t a, t;
  int   ok = 0;
  buf[0]   = 0;
  if (H5Aexists(obj, name) <= 0 || (a = H5Aopen(obj, name, H5P_DEFAULT)) < 0) return 0;
  t = H5Aget_type(a);
  if (t >= 0 && H5Tget_class(t) == H5T_STRING && !H5Tis_variable_str(t) && H5Tget_size(t) < len) {
    memset(buf, 0, len);
    ok = H5Aread(a, t, buf) >= 0;
  }
  if (t >= 0) H5Tclose(t);
  H5Aclose(a);
  return ok;
}

/* Rank 0, before any output is touched: does DIR/fabric.h5 hold this run's frames written before the checkpoint
   (the grid, scene_hash, the frame count attribute and nothing but frames under /frames, the first
   h->frames as the checkpoint lists them)? strict (this run writes frames): if not, the restart is refused
   (h->status, h->msg); else the file is left alone. Returns 1 if it does. */
static int CheckFramesFile(const Scene *s, const FabricIO io, const double *frames, Header *h, PetscBool strict)
{
  const char *restart = io->restart;
  char        file[PETSC_MAX_PATH_LEN], path[64], hash[sizeof io->scene_hash], why[PETSC_MAX_PATH_LEN + 256] = "";
  H5E_auto2_t efunc;
  void       *edata;
  hid_t       fid, g = -1;
  int         nx = 0, ny = 0, count = 0;

  if (snprintf(file, sizeof file, "%s/fabric.h5", s->out.output_dir) >= (int) sizeof file) file[0] = 0;
  H5Eget_auto2(H5E_DEFAULT, &efunc, &edata);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  fid = H5Fis_hdf5(file) > 0 ? H5Fopen(file, H5F_ACC_RDONLY, H5P_DEFAULT) : -1;
  if (fid < 0)
    snprintf(why, sizeof why,
             "-restart %s: %s, which holds the %d frames written before the checkpoint, is missing or cannot be opened "
             "(damaged); restart into the -output_dir of the checkpointed run, or with -output_every 0 -output_te_every 0 "
             "-output_tear_every 0",
             restart, file, h->frames);
  else if ((g = H5Gopen2(fid, "/", H5P_DEFAULT)) < 0 || !ReadAttr(g, "nx", H5T_NATIVE_INT, &nx) ||
           !ReadAttr(g, "ny", H5T_NATIVE_INT, &ny) || nx != s->spec.nx || ny != s->spec.ny)
    snprintf(why, sizeof why,
             "-restart %s: %s is not of this grid (%d x %d crossings, this run has %" PetscInt_FMT " x %" PetscInt_FMT ")",
             restart, file, nx, ny, s->spec.nx, s->spec.ny);
  else if (ReadStringAttr(g, "scene_hash", hash, sizeof hash) ? strcmp(hash, io->scene_hash) != 0
                                                                : H5Aexists(g, "scene_hash") > 0) /* none: an earlier
                                                                  build's file, which the frames below tell */
    snprintf(why, sizeof why,
             "-restart %s: %s is another run's: its scene_hash %s is not this run's %s (a run of other options wrote "
             "it): it is not the file of this run",
             restart, file, hash[0] ? hash : "(unreadable)", io->scene_hash);
  else if (!ReadAttr(g, "frames", H5T_NATIVE_INT, &count))
    snprintf(why, sizeof why, "-restart %s: %s has no frames attribute at its root (damaged)", restart, file);
  else { /* /frames holds frames alone: a link of another name is not this program's */
    hid_t      fg = H5Lexists(fid, "/frames", H5P_DEFAULT) > 0 ? H5Gopen2(fid, "/frames", H5P_DEFAULT) : -1;
    H5G_info_t info;
    if (fg >= 0 && H5Gget_info(fg, &info) >= 0)
      for (hsize_t l = 0; l < info.nlinks && !why[0]; l++) {
        char name[64] = "";
        if (H5Lget_name_by_idx(fg, ".", H5_INDEX_NAME, H5_ITER_INC, l, name, sizeof name, H5P_DEFAULT) < 0) name[0] = 0;
        if (strlen(name) < 6 || strspn(name, "0123456789") != strlen(name)) /* %06d: 6 digits or more */
          snprintf(why, sizeof why, "-restart %s: %s holds /frames/%s, which is not a frame: it is not the file of this run",
                   restart, file, name);
      }
    if (fg >= 0) H5Gclose(fg);
  }
  for (int k = 0; k < h->frames && !why[0]; k++) {
    double at[3] = {0, -1, -1}; /* time_s, load_step, te_step: as the checkpoint lists the frame */
    hid_t  fg;
    snprintf(path, sizeof path, "/frames/%06d", k);
    if (H5Lexists(fid, "/frames", H5P_DEFAULT) <= 0 || H5Lexists(fid, path, H5P_DEFAULT) <= 0) {
      snprintf(why, sizeof why,
               "-restart %s: %s lacks frame %d of the %d written before the checkpoint: it is not the file of this run",
               restart, file, k, h->frames);
      break;
    }
    fg = H5Gopen2(fid, path, H5P_DEFAULT);
    if (fg < 0 || !ReadAttr(fg, "time_s", H5T_NATIVE_DOUBLE, &at[0]) ||
        !ReadAttr(fg, "load_step", H5T_NATIVE_DOUBLE, &at[1]) || !ReadAttr(fg, "te_step", H5T_NATIVE_DOUBLE, &at[2]) ||
        at[0] != frames[3 * k] || at[1] != frames[3 * k + 1] || at[2] != frames[3 * k + 2])
      snprintf(why, sizeof why,
               "-restart %s: %s's frame %d (load step %g, te step %g, %.9g s) is not the one written before the "
               "checkpoint (load step %g, te step %g, %.9g s): it is not the file of this run",
               restart, file, k, at[1], at[2], at[0], frames[3 * k + 1], frames[3 * k + 2], frames[3 * k]);
    if (fg >= 0) H5Gclose(fg);
  }
  if (g >= 0) H5Gclose(g);
  if (fid >= 0) H5Fclose(fid);
  H5Eset_auto2(H5E_DEFAULT, efunc, edata);
  if (why[0] && strict) {
    h->status = 1;
    snprintf(h->msg, sizeof h->msg, "%s", why);
  }
  return !why[0];
}

/* the run's counters and the relaxation's state from a checkpoint's header */
static void RestoreCounters(Fabric fab, const Header *hp)
{
  const Header h = *hp;

  fab->load.load_step        = h.load_step; /* the load steps done: curve.csv gets their rows */
  fab->load.load_factor      = (PetscReal) h.load_step / (PetscReal) fab->s.load.load_steps;
  fab->load.travel           = h.grip_disp;
  fab->load.travel_step_prev = h.grip_step_prev;
  for (int c = 0; c < 4; c++) fab->front.awake_box[c] = h.awake_box[c], fab->front.keep_box[c] = h.keep_box[c];
  fab->step.last.tension_max = h.last_tension_max;
  fab->step.ke_prev          = h.ke_prev;
  fab->step.ke_resets        = (PetscInt64) h.ke_resets;
  fab->stats.te_steps        = (PetscInt64) h.te_steps;
  fab->stats.point_updates   = (PetscInt64) h.point_updates;
  fab->stats.converged       = h.converged ? PETSC_TRUE : PETSC_FALSE;
  fab->stats.broken_any      = h.broken_any ? PETSC_TRUE : PETSC_FALSE;
  RuptureUnpack(h.rupture, &fab->stats.rupture);
  RelaxStateUnpack(&h.relax, fab);
  ckpt.resume         = h.relax.within ? PETSC_TRUE : PETSC_FALSE; /* FabricRun continues load step load_step + 1 */
  ckpt.at.round       = (PetscInt) h.relax.round;
  ckpt.at.te_step     = (PetscInt) h.relax.te_step;
  ckpt.at.inner_steps = (PetscInt) h.relax.inner_steps;
  ckpt.at.newton      = (PetscInt) h.relax.static_newton;
}

/* the state vectors and the broken segments, read collectively, each checked against its checksum */
static PetscErrorCode LoadStateVectors(Fabric fab, const Header *h)
{
  const char *file = fab->io->restart;
  StateVec    sv[MAX_STATE];
  PetscInt    nsv = StateVecs(&fab->state, sv);
  PetscViewer v;
  uint64_t    sum;
  Vec         B;

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5Open(fab->comm, file, FILE_MODE_READ, &v));
  PetscCall(PetscViewerHDF5PushGroup(v, "/state"));
  for (PetscInt k = 0; k < nsv; k++) {
    if (!h->has[k]) continue;
    if (!*sv[k].vec) PetscCall(VecDuplicate(fab->state.X, sv[k].vec));
    PetscCall(PetscObjectSetName((PetscObject) *sv[k].vec, sv[k].name));
    PetscCall(VecLoad(*sv[k].vec, v));
    PetscCall(GridChecksum(fab->comm, &fab->grid.patch, *sv[k].vec, &sum));
    PetscCheck(sum == h->sum[k], fab->comm, PETSC_ERR_FILE_UNEXPECTED,
               "-restart %s: damaged checkpoint: the checksum of /state/%s does not match", file, sv[k].name);
  }
  PetscCall(DMGetGlobalVector(fab->grid.da_seg, &B));
  PetscCall(PetscObjectSetName((PetscObject) B, "broken_segments"));
  PetscCall(VecLoad(B, v));
  PetscCall(GridChecksum(fab->comm, &fab->grid.patch, B, &sum));
  PetscCheck(sum == h->sum[nsv], fab->comm, PETSC_ERR_FILE_UNEXPECTED,
             "-restart %s: damaged checkpoint: the checksum of /state/broken_segments does not match", file);
  PetscCall(BrokenFromVec(fab->grid.da_seg, &fab->grid.patch, B));
  PetscCall(DMRestoreGlobalVector(fab->grid.da_seg, &B));
  PetscCall(PetscViewerHDF5PopGroup(v));
  PetscCall(PetscViewerDestroy(&v));
  PetscCall(PetscObjectSetName((PetscObject) fab->state.X, "positions"));
  PetscCall(PetscObjectSetName((PetscObject) fab->state.V, NULL));
  PetscFunctionReturn(0);
}

/* Rank 0 checks the checkpoint alone and tells every rank; then they share its curve rows and frame list */
static PetscErrorCode ReadHistory(Fabric fab, Header *h, double **rows, double **frames)
{
  FabricIO io = fab->io;
  int      ours = 0; /* DIR/fabric.h5 is this run's */

  PetscFunctionBeginUser;
  if (fab->rank == 0) {
    PetscCall(ReadHeader(fab, io->restart, h, rows, frames));
    if (!h->status && h->frames > 0 && fab->s.out.output_dir[0])
      ours = CheckFramesFile(&fab->s, io, *frames, h, IOWritesFrames(io));
  }
  PetscCall(BroadcastFromRoot(fab->comm, h, (PetscInt) sizeof *h, MPI_BYTE));
  PetscCall(BroadcastFromRoot(fab->comm, &ours, 1, MPI_INT));
  io->frames_file_ours = ours ? PETSC_TRUE : PETSC_FALSE;
  if (h->status) {
    PetscCall(PetscFree(*rows));
    PetscCall(PetscFree(*frames));
  }
  PetscCheck(!h->status, fab->comm, PETSC_ERR_USER_INPUT, "%s", h->msg);
  if (fab->rank) {
    PetscCall(PetscMalloc1(CURVE_COLS * h->load_step, rows));
    PetscCall(PetscMalloc1(3 * h->frames, frames));
  }
  PetscCall(BroadcastFromRoot(fab->comm, *rows, CURVE_COLS * h->load_step, MPI_DOUBLE));
  PetscCall(BroadcastFromRoot(fab->comm, *frames, 3 * h->frames, MPI_DOUBLE));
  PetscFunctionReturn(0);
}

/* The start of the run: the clock of -checkpoint_every_s starts, fabric.h5's scene_hash is set; with -restart, the state, counters,
   curve rows and frame list of the checkpoint. */
PetscErrorCode RestartLoad(Fabric fab)
{
  FabricIO io = fab->io;
  Header   h;
  double  *rows = NULL, *frames = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&ckpt, sizeof ckpt));
  PetscCall(PetscTime(&ckpt.last_wall));
  if (io) SceneHash(&fab->s, io->scene_hash, sizeof io->scene_hash); /* fabric.h5's, a fresh run's too */
  if (!io || !io->restart[0]) PetscFunctionReturn(0);
  PetscCall(PetscLogEventBegin(EV_Output, 0, 0, 0, 0));
  PetscCall(PetscMemzero(&h, sizeof h));
  PetscCall(ReadHistory(fab, &h, &rows, &frames));
  PetscCall(LoadStateVectors(fab, &h));
  RestoreCounters(fab, &h);
  ckpt.last_te = ckpt.last_look = fab->stats.te_steps;
  for (PetscInt k = 0; k < h.load_step; k++) CurveRowUnpack(rows + CURVE_COLS * k, &fab->stats.curve[k]);
  fab->stats.rows_done = h.load_step;
  io->frames = 0;
  for (PetscInt k = 0; k < h.frames; k++) {
    FrameInfo f = {frames[3 * k], (PetscInt) frames[3 * k + 1], (PetscInt) frames[3 * k + 2]};
    PetscCall(FramesAppend(io, &f));
  }
  io->restarted         = PETSC_TRUE;
  io->restart_load_step = fab->load.load_step;
  io->restart_within    = ckpt.resume;
  fab->stats.wall_start -= h.wall; /* elapsed time and ETA count the run before the restart */
  PetscCall(PetscFree(rows));
  PetscCall(PetscFree(frames));
  PetscCall(PetscLogEventEnd(EV_Output, 0, 0, 0, 0));
  if (fab->s.out.quiet) PetscFunctionReturn(0);
  if (ckpt.resume)
    PetscCall(PetscPrintf(fab->comm,
                          "fabric: restart from %s within load step %" PetscInt_FMT "/%" PetscInt_FMT
                          ", after its %s step %" PetscInt_FMT " (%" PetscInt64_FMT " te steps, %" PetscInt_FMT
                          " frames so far)\n",
                          io->restart, fab->load.load_step + 1, fab->s.load.load_steps, ckpt.at.newton ? "Newton" : "te",
                          ckpt.at.inner_steps + ckpt.at.te_step + ckpt.at.newton, fab->stats.te_steps, io->frames));
  else
    PetscCall(PetscPrintf(fab->comm,
                          "fabric: restart from %s at load step %" PetscInt_FMT "/%" PetscInt_FMT " (%" PetscInt64_FMT
                          " te steps, %" PetscInt_FMT " frames so far)\n",
                          io->restart, fab->load.load_step, fab->s.load.load_steps, fab->stats.te_steps, io->frames));
  PetscFunctionReturn(0);
}

/* FILE is an HDF5 file whose root group has the attribute attr (rank-local: an earlier run's result to remove) */
PetscBool FabricHDF5File(const char *file, const char *attr)
{
  H5E_auto2_t efunc;
  void       *edata;
  hid_t       fid, g;
  PetscBool   ok = PETSC_FALSE;

  H5Eget_auto2(H5E_DEFAULT, &efunc, &edata);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  fid = H5Fis_hdf5(file) > 0 ? H5Fopen(file, H5F_ACC_RDONLY, H5P_DEFAULT) : -1;
  if (fid >= 0) {
    g = H5Gopen2(fid, "/", H5P_DEFAULT);
    if (g >= 0) {
      ok = H5Aexists(g, attr) > 0 ? PETSC_TRUE : PETSC_FALSE;
      H5Gclose(g);
    }
    H5Fclose(fid);
  }
  H5Eset_auto2(H5E_DEFAULT, efunc, edata);
  return ok;
}

PetscBool CheckpointResumesLoadStep(void)
{
  return ckpt.resume;
}

/* FabricRun, before load step k: restarted within it? Then it is not applied again (its grips, prediction
   and stable step are in the checkpoint): it becomes the current load step. */
PetscBool CheckpointWithinLoadStep(Fabric fab, PetscInt k)
{
  if (!ckpt.resume) return PETSC_FALSE;
  fab->load.load_step   = k;
  fab->load.load_factor = (PetscReal) k / (PetscReal) fab->s.load.load_steps; /* as ApplyLoadStep */
  return PETSC_TRUE;
}

/* RelaxLoadStep, at its start: where it continues from (restarted within the load step), else its start */
void CheckpointRelaxStart(RelaxPoint *at)
{
  const RelaxPoint start = {0, 0, 0, 0};
  *at                    = ckpt.resume ? ckpt.at : start;
  ckpt.resume            = PETSC_FALSE;
}
