/* report.c - everything the run writes: curve.csv, summary.json, progress, positions.
 *
 * Rank 0 writes the small text files; curve.csv gets one row per load step as the run
 * goes (flushed, so a long run can be watched). Nothing is created before the scene
 * has been read and checked, so bad input leaves no output behind.
 */
#include "report.h"
#include "checkpoint.h"
#include "comm.h"
#include "events.h"
#include "frames.h"
#include "load.h"
#include "revision.h"

#include <errno.h>
#include <string.h>
#include <math.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

/* mkdir -p; on failure, the part of the path that could not be made in failed */
static int MakeDirs(const char *path, char *failed, size_t len)
{
  char   buf[PETSC_MAX_PATH_LEN];
  size_t n = strlen(path);
  snprintf(failed, len, "%s", path);
  if (n == 0 || n >= sizeof buf) return -1;
  memcpy(buf, path, n + 1);
  for (char *p = buf + 1; *p; p++) {
    if (*p != '/') continue;
    *p = 0;
    if (mkdir(buf, 0755) && errno != EEXIST) {
      snprintf(failed, len, "%s", buf);
      return -1;
    }
    *p = '/';
  }
  if (mkdir(buf, 0755) && errno != EEXIST) return -1;
  return 0;
}

/* curve.csv columns per test: strip = jaw reaction vs elongation; bias = the same plus the jaw
   travel and the central zone's shear angle; square = point load vs
   the displacement of its crossing (travel_mm); pushing = the ball's force vs its travel; drape =
   the largest drop of a crossing (drop_mm) */
static const char *CurveHeader(const Scene *s)
{
  if (s->test == TEST_DRAPE) return "load_step,time_s,drop_mm,force_N,inner_steps,residual,balanced";
  if (s->test == TEST_STRIP) return "load_step,time_s,elongation_pct,force_N,inner_steps,residual,balanced";
  if (s->test == TEST_BIAS)
    return "load_step,time_s,elongation_pct,force_N,inner_steps,residual,balanced,travel_mm,center_shear_deg";
  return "load_step,time_s,travel_mm,force_N,inner_steps,residual,balanced";
}

/* supports (a plane or a pedestal present): after the test's own columns, the force of the
   fabric on each body present, on the clamps (their pull plus the clamped crossings' weight)
   and the specimen's weight, x, y, z (N, z up). At rest they add up:
   plane + pedestal + clamp = weight. */
static PetscBool HasSupports(const Scene *s)
{
  return (s->bodies.plane || s->bodies.pedestal_radius > 0) ? PETSC_TRUE : PETSC_FALSE;
}

static void WriteSupportsHeader(const Scene *s, FILE *fp)
{
  const char *names[4]   = {"plane", "pedestal", "clamp", "weight"};
  const int   present[4] = {s->bodies.plane, s->bodies.pedestal_radius > 0, 1, 1};
  if (!HasSupports(s)) return;
  for (int b = 0; b < 4; b++)
    if (present[b]) fprintf(fp, ",%s_fx_N,%s_fy_N,%s_fz_N", names[b], names[b], names[b]);
}

static void WriteSupports(const Scene *s, FILE *fp, const CurveRow *r)
{
  const PetscReal *v[4]       = {r->plane_force, r->pedestal_force, r->clamp_force, r->weight};
  const int        present[4] = {s->bodies.plane, s->bodies.pedestal_radius > 0, 1, 1};
  if (!HasSupports(s)) return;
  for (int b = 0; b < 4; b++)
    if (present[b]) fprintf(fp, ",%.9g,%.9g,%.9g", (double) v[b][0], (double) v[b][1], (double) v[b][2]);
}

static void WriteCurveRow(const Scene *s, FILE *fp, const CurveRow *r)
{
  if (s->test == TEST_BIAS)
    fprintf(fp, "%" PetscInt_FMT ",%.9g,%.9g,%.9g,%" PetscInt_FMT ",%.6e,%d,%.9g,%.9g", r->load_step, (double) r->time,
            (double) (100.0 * r->elongation), (double) r->force, r->inner_steps, (double) r->residual, r->balanced ? 1 : 0,
            (double) (1e3 * r->elongation * s->spec.gauge), (double) r->center_shear);
  else if (s->test != TEST_STRIP)
    fprintf(fp, "%" PetscInt_FMT ",%.9g,%.9g,%.9g,%" PetscInt_FMT ",%.6e,%d", r->load_step, (double) r->time,
            (double) (1e3 * r->travel), (double) r->force, r->inner_steps, (double) r->residual, r->balanced ? 1 : 0);
  else
    fprintf(fp, "%" PetscInt_FMT ",%.9g,%.9g,%.9g,%" PetscInt_FMT ",%.6e,%d", r->load_step, (double) r->time,
            (double) (100.0 * r->elongation), (double) r->force, r->inner_steps, (double) r->residual, r->balanced ? 1 : 0);
  WriteSupports(s, fp, r);
  fputc('\n', fp);
}

/* Room on the disk for what the next load step writes. Parallel HDF5 does not recover from a full
   disk (a collective write that fails on one rank leaves the others waiting for ever), so a frame
   or a checkpoint that would not fit is not started: the run stops naming the file, and the last
   complete checkpoint.h5 stays intact (a new one is written aside, then renamed over it). The
   sizes are estimates: the checkpoint written last (or ~200 bytes a crossing for the first), 1.5
   average frames of fabric.h5 (or ~200 bytes a crossing for the grid and the first frame: a disk too small
   for it stopped in HDF5's own error after a stall, with fabric.h5 half written), and 64 KiB for curve.csv,
   fabric.xmf and summary.json. */
static PetscErrorCode CheckRoom(Fabric fab)
{
  const char *dir    = fab->s.out.output_dir;
  FabricIO    io     = fab->io;
  double      est[4] = {0, 0, 0, 0}; /* bytes: free, the next checkpoint.h5, the next frames; a checkpoint is there */

  PetscFunctionBeginUser;
  if (fab->rank == 0) {
    struct statvfs fs;
    struct stat    st;
    char           file[PETSC_MAX_PATH_LEN];
    est[0] = statvfs(dir, &fs) ? INFINITY : (double) fs.f_bavail * (double) fs.f_frsize;
    if (io && io->checkpoint_every > 0) {
      PetscCall(PetscSNPrintf(file, sizeof file, "%s/checkpoint.h5", dir));
      est[3] = !stat(file, &st);
      est[1] = est[3] ? 1.1 * (double) st.st_size + 16384 : 200.0 * (double) fab->grid.points + 32768;
    }
    if (IOWritesFrames(io)) {
      PetscCall(PetscSNPrintf(file, sizeof file, "%s/fabric.h5", dir));
      if (io->frames > 0 && !stat(file, &st)) est[2] = 1.5 * (double) st.st_size / (double) io->frames;
      else est[2] = 200.0 * (double) fab->grid.points + 65536; /* the grid and the first frame: 124-176 measured */
    }
  }
  PetscCall(BroadcastFromRoot(fab->comm, est, 4, MPI_DOUBLE));
  PetscCheck(est[0] >= est[1] + est[2] + 65536, fab->comm, PETSC_ERR_FILE_WRITE,
             "-output_dir %s: the disk is full: %.0f kB free, too little for the next %s (about %.0f kB)%s", dir,
             est[0] / 1024, est[1] > est[2] ? "checkpoint.h5" : "frame of fabric.h5", (est[1] + est[2] + 65536) / 1024,
             est[3] ? "; the last checkpoint.h5 is intact" : "");
  PetscFunctionReturn(0);
}

/* DIR/name, if there and (attr) an HDF5 file of this program's with that attribute at its root: an earlier
   run's result that this run does not write again, removed and named (rank 0; also with -quiet: a user's file
   is not deleted without a word); returns whether it was */
static PetscBool RemoveStale(const char *dir, const char *name, const char *attr)
{
  char file[PETSC_MAX_PATH_LEN];
  if (snprintf(file, sizeof file, "%s/%s", dir, name) >= (int) sizeof file || access(file, F_OK)) return PETSC_FALSE;
  if ((attr && !FabricHDF5File(file, attr)) || unlink(file)) return PETSC_FALSE;
  printf("fabric: removed %s, an earlier run's\n", file);
  return PETSC_TRUE;
}

/* -positions_out, if there and a PETSc binary vector (its first word VEC_FILE_CLASSID, big-endian): an earlier
   run's final positions, which a run that stops before its end would leave standing as if they were its own;
   removed and named as RemoveStale does (rank 0) */
static void RemoveStalePositions(const char *file)
{
  unsigned char w[4];
  FILE         *fp;
  int           ours;

  if (!file[0] || !(fp = fopen(file, "rb"))) return;
  ours = fread(w, 1, 4, fp) == 4 &&
         (((PetscInt64) w[0] << 24) | ((PetscInt64) w[1] << 16) | ((PetscInt64) w[2] << 8) | w[3]) == VEC_FILE_CLASSID;
  fclose(fp);
  if (ours && !unlink(file)) printf("fabric: removed %s, an earlier run's\n", file);
}

/* DIR/checkpoint.h5 is the -restart file itself (the same file on the same device): the run keeps it */
PetscBool RestartsFrom(const char *dir, const char *restart)
{
  char        file[PETSC_MAX_PATH_LEN];
  struct stat a, b;
  if (!restart[0] || snprintf(file, sizeof file, "%s/checkpoint.h5", dir) >= (int) sizeof file) return PETSC_FALSE;
  return !stat(file, &a) && !stat(restart, &b) && a.st_dev == b.st_dev && a.st_ino == b.st_ino ? PETSC_TRUE : PETSC_FALSE;
}

/* curve.csv: the header, and after a restart the rows before the checkpoint */
PetscErrorCode OutputOpen(Fabric fab)
{
  const char *dir                        = fab->s.out.output_dir;
  char        failed[PETSC_MAX_PATH_LEN] = "";
  int         status[2]                  = {0, 0}; /* 0 fine, 1 a directory, 2 curve.csv could not be written; errno */

  PetscFunctionBeginUser;
  if (fab->rank == 0 && dir[0]) { /* the lock first: a refused run removes nothing */
    if (MakeDirs(dir, failed, sizeof failed)) status[0] = 1, status[1] = errno;
    else if (OutputDirLock(dir, &fab->stats.lock_fp)) status[0] = 3;
  }
  if (fab->rank == 0 && !status[0]) RemoveStalePositions(fab->s.out.positions_out);
  if (!dir[0]) PetscFunctionReturn(0);
  if (fab->rank == 0) {
    char file[PETSC_MAX_PATH_LEN];
    if (!status[0]) { /* an earlier run's summary, checkpoint and frames would stand beside this run's results */
      RemoveStale(dir, "summary.json", NULL);
      if (!RestartsFrom(dir, fab->s.out.restart)) RemoveStale(dir, "checkpoint.h5", "fabric_checkpoint");
      if (!fab->s.out.restart[0] && !IOWritesFrames(fab->io) && RemoveStale(dir, "fabric.h5", "frames"))
        RemoveStale(dir, "fabric.xmf", NULL); /* its index */
    }
    if (!status[0]) {
      PetscCall(PetscSNPrintf(file, sizeof file, "%s/curve.csv", dir));
      fab->stats.curve_fp = fopen(file, "w");
      if (!fab->stats.curve_fp) status[0] = 2, status[1] = errno;
    }
    if (!status[0]) {
      fprintf(fab->stats.curve_fp, "%s", CurveHeader(&fab->s));
      WriteSupportsHeader(&fab->s, fab->stats.curve_fp);
      fputc('\n', fab->stats.curve_fp);
      for (PetscInt k = 0; k < fab->load.load_step; k++)
        WriteCurveRow(&fab->s, fab->stats.curve_fp, &fab->stats.curve[k]);
      if (fflush(fab->stats.curve_fp) || ferror(fab->stats.curve_fp)) status[0] = 2, status[1] = errno;
    }
  }
  PetscCall(BroadcastFromRoot(fab->comm, status, 2, MPI_INT));
  PetscCall(BroadcastFromRoot(fab->comm, failed, (PetscInt) sizeof failed, MPI_CHAR));
  PetscCheck(status[0] != 1, fab->comm, PETSC_ERR_FILE_OPEN, "-output_dir %s: cannot create the directory %s (%s)", dir,
             failed, strerror(status[1]));
  PetscCheck(status[0] != 2, fab->comm, PETSC_ERR_FILE_WRITE, "-output_dir %s: cannot write %s/curve.csv (%s)", dir,
             dir, strerror(status[1]));
  PetscCheck(status[0] != 3, fab->comm, PETSC_ERR_FILE_OPEN, OUTPUT_DIR_BUSY, dir, dir);
  PetscCall(CheckRoom(fab));
  PetscFunctionReturn(0);
}

/* the load step's row of curve.csv (rank 0), then room for the load step's frame and checkpoint */
PetscErrorCode OutputCurveRow(Fabric fab, const CurveRow *r)
{
  const char *dir       = fab->s.out.output_dir;
  int         status[2] = {0, 0}; /* 1: curve.csv could not be written; errno */

  PetscFunctionBeginUser;
  if (!dir[0]) PetscFunctionReturn(0);
  PetscCall(PetscLogEventBegin(EV_Output, 0, 0, 0, 0));
  if (fab->stats.curve_fp) {
    WriteCurveRow(&fab->s, fab->stats.curve_fp, r);
    if (fflush(fab->stats.curve_fp) || ferror(fab->stats.curve_fp)) status[0] = 1, status[1] = errno;
  }
  PetscCall(BroadcastFromRoot(fab->comm, status, 2, MPI_INT));
  PetscCheck(!status[0], fab->comm, PETSC_ERR_FILE_WRITE, "-output_dir %s: cannot write %s/curve.csv (%s)", dir, dir,
             strerror(status[1]));
  PetscCall(CheckRoom(fab));
  PetscCall(PetscLogEventEnd(EV_Output, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* where a segment is: the middle of its rest chord from the grid centre, mm */
static void SegmentPlace(const Fabric fab, const BreakSite *b, PetscReal mm[2])
{
  const Patch *p = &fab->grid.patch;
  mm[0]          = 1e3 * ((b->i + 0.5 * (b->dir == 0)) * p->ax - fab->grid.centre[0]);
  mm[1]          = 1e3 * ((b->j + 0.5 * (b->dir == 1)) * p->ay - fab->grid.centre[1]);
}

/* the rupture's value of the load program: elongation (%) for the jaw tests, else travel (mm) */
static PetscReal LoadValue(const Scene *s, PetscReal at)
{
  return JawTest(s) ? 100.0 * at : 1e3 * at;
}

/* the progress lines of a load step in which the first yarn broke, or the specimen ruptured */
static PetscErrorCode ProgressRupture(Fabric fab, const CurveRow *row)
{
  const RuptureState *r = &fab->stats.rupture;
  const char         *unit = JawTest(&fab->s) ? "% elongation" : "mm travel";
  PetscReal           mm[2];

  PetscFunctionBeginUser;
  if (r->first.ratio > 0 && r->first_step == row->load_step) {
    SegmentPlace(fab, &r->first, mm);
    PetscCall(PetscPrintf(fab->comm, "  first yarn break: %s segment at crossing %" PetscInt_FMT ",%" PetscInt_FMT
                          " (%.2f, %.2f mm from the centre)\n",
                          r->first.dir == 0 ? "warp" : "weft", r->first.i, r->first.j, (double) mm[0], (double) mm[1]));
  }
  if (r->rupture_step == row->load_step)
    PetscCall(PetscPrintf(fab->comm,
                          "  ruptured: the force fell to %.4g N, below %.4g %% of its maximum %.4g N at %.4g %s; "
                          "%" PetscInt64_FMT " segments broken; the test ends\n",
                          (double) row->force, (double) (100.0 * (1.0 - fab->s.rupture.drop)), (double) r->peak_force,
                          (double) LoadValue(&fab->s, r->at_peak), unit, r->segments));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputProgress(Fabric fab, const CurveRow *r)
{
  const PetscInt  K   = fab->s.load.load_steps;
  const PetscReal eta = fab->stats.wall / r->load_step * (K - r->load_step);
  char            where[48], te[32] = "", force[40] = ""; /* the static path takes no te steps; the drape no force */

  PetscFunctionBeginUser;
  if (fab->s.out.quiet) PetscFunctionReturn(0);
  if (JawTest(&fab->s))
    PetscCall(PetscSNPrintf(where, sizeof where, "elongation %7.3f %%", (double) (100.0 * r->elongation)));
  else /* no jaws: the load point's or the ball's travel, the drape's drop */
    PetscCall(PetscSNPrintf(where, sizeof where, "%s %8.3f mm", fab->s.test == TEST_DRAPE ? "drop  " : "travel",
                            (double) (1e3 * r->travel)));
  if (fab->s.num.solver != SOLVER_STATIC) PetscCall(PetscSNPrintf(te, sizeof te, "  te %.3g s", (double) fab->step.te));
  if (fab->s.test != TEST_DRAPE) PetscCall(PetscSNPrintf(force, sizeof force, "  force %10.4f N", (double) r->force));
  PetscCall(PetscPrintf(fab->comm,
                        "load step %4" PetscInt_FMT "/%" PetscInt_FMT "  %s%s  N' %6" PetscInt_FMT
                        "%s  residual %.2e%s  elapsed %.1f s  ETA %.1f s\n",
                        r->load_step, K, where, force, r->inner_steps, r->balanced ? " " : "*",
                        (double) r->residual, te, (double) fab->stats.wall, (double) eta));
  PetscCall(ProgressRupture(fab, r));
  PetscFunctionReturn(0);
}

/* the largest force so far as a JSON member: null before the first load step ended */
static void JsonPeak(FILE *fp, const char *name, PetscReal peak)
{
  if (peak == -PETSC_MAX_REAL) fprintf(fp, "  \"%s\": null,\n", name);
  else fprintf(fp, "  \"%s\": %.9g,\n", name, (double) peak);
}

/* summary.json's rupture members (ISO 13934-1, ASTM D3787): the maximum force and where it was,
   the bursting force of a ball burst, the segments broken and the rupture (null: none) */
static void SummaryRupture(Fabric fab, FILE *fp)
{
  const Scene        *s = &fab->s;
  const RuptureState *r = &fab->stats.rupture;
  PetscReal           mm[2];

  if (ReactionTest(s)) {
    const PetscBool none = r->peak_force == -PETSC_MAX_REAL; /* no load step has ended */
    JsonPeak(fp, "max_force_N", r->peak_force);
    fprintf(fp, "  \"max_force_balanced\": %s,\n", none ? "null" : r->peak_balanced ? "true" : "false");
    if (none) fprintf(fp, "  \"%s\": null,\n", JawTest(s) ? "elongation_at_max_force_pct" : "travel_at_max_force_mm");
    else if (JawTest(s)) fprintf(fp, "  \"elongation_at_max_force_pct\": %.9g,\n", (double) (100.0 * r->at_peak));
    else fprintf(fp, "  \"travel_at_max_force_mm\": %.9g,\n", (double) (1e3 * r->at_peak));
    if (s->test == TEST_PUSHING && r->rupture_step) fprintf(fp, "  \"bursting_force_N\": %.9g,\n", (double) r->peak_force);
  }
  if (!isfinite(s->yarns.warp.break_e) && !isfinite(s->yarns.weft.break_e)) return;
  fprintf(fp, "  \"segments_broken\": %" PetscInt64_FMT ",\n  \"tear_te_steps\": %" PetscInt64_FMT ",\n", r->segments,
          r->tear_te_steps);
  if (s->rupture.locate > 0) fprintf(fp, "  \"breaks_located\": %" PetscInt64_FMT ",\n", r->located);
  if (r->first.ratio > 0) {
    SegmentPlace(fab, &r->first, mm);
    fprintf(fp,
            "  \"first_break\": {\"yarn\": \"%s\", \"i\": %" PetscInt_FMT ", \"j\": %" PetscInt_FMT
            ", \"x_mm\": %.6g, \"y_mm\": %.6g, \"load_step\": %" PetscInt_FMT ", \"time_s\": %.9g},\n",
            r->first.dir == 0 ? "warp" : "weft", r->first.i, r->first.j, (double) mm[0], (double) mm[1], r->first_step,
            (double) r->first_time);
  } else fprintf(fp, "  \"first_break\": null,\n"); /* nothing broke */
  if (r->rupture_step) {
    const CurveRow *row = &fab->stats.curve[r->rupture_step - 1];
    fprintf(fp, "  \"rupture\": {\"load_step\": %" PetscInt_FMT ", \"time_s\": %.9g, \"%s\": %.9g, \"force_N\": %.9g},\n",
            r->rupture_step, (double) r->rupture_time, JawTest(s) ? "elongation_pct" : "travel_mm",
            (double) LoadValue(s, RowAt(s, row)), (double) row->force);
  } else fprintf(fp, "  \"rupture\": null,\n");
}

/* one state measured by -te_measure: te, the stable bound and the measured limit 2/omega_max */
static void JsonTeMeasure(FILE *fp, const char *name, const TeMeasure *m, const char *sep)
{
  fprintf(fp,
          "    \"%s\": {\"load_step\": %" PetscInt_FMT ", \"at\": \"%s\", \"te_s\": %.6e, \"te_bound_s\": %.6e, "
          "\"limit_s\": %.6e, \"te_over_limit\": %.6f, \"bound_over_limit\": %.6f}%s\n",
          name, m->load_step, m->end ? "end" : "start", (double) m->te, (double) m->te_bound, (double) m->limit,
          (double) (m->te / m->limit), (double) (m->te_bound / m->limit), sep);
}

/* -te_measure: te against the measured stable limit (spectrum.c) at the first and last states
   measured, the tightest (smallest limit) and the worst (largest te / limit) */
static void SummaryTeMeasure(Fabric fab, FILE *fp)
{
  const StepControl *st = &fab->step;
  if (!fab->s.num.te_measure || !st->te_measured) return;
  fprintf(fp, "  \"te_measure\": {\n    \"states\": %" PetscInt_FMT ",\n", st->te_measured);
  JsonTeMeasure(fp, "first", &st->te_first, ",");
  JsonTeMeasure(fp, "last", &st->te_last, ",");
  JsonTeMeasure(fp, "tightest", &st->te_tightest, ",");
  JsonTeMeasure(fp, "worst", &st->te_worst, "");
  fprintf(fp, "  },\n");
}

/* summary.json written aside and renamed into place, by rank 0; status[0]: SUMMARY_OK, or where it failed (the file
   aside not created, not written, not renamed); status[1]: errno */
enum { SUMMARY_OK, SUMMARY_OPEN, SUMMARY_WRITE, SUMMARY_RENAME };
static void SummaryWrite(Fabric fab, const char *error, int status[2])
{
  const Scene   *s = &fab->s;
  char           file[PETSC_MAX_PATH_LEN], tmp[PETSC_MAX_PATH_LEN];
  FILE          *fp;
  const PetscInt done = fab->stats.rows_done;
  int            write_error;

  if (snprintf(file, sizeof file, "%s/summary.json", s->out.output_dir) >= (int) sizeof file ||
      snprintf(tmp, sizeof tmp, "%s/.summary.json.tmp", s->out.output_dir) >= (int) sizeof tmp) {
    status[0] = SUMMARY_OPEN, status[1] = ENAMETOOLONG;
    return;
  }
  fp = fopen(tmp, "w");
  if (!fp) {
    status[0] = SUMMARY_OPEN, status[1] = errno;
    return;
  }
  errno = 0; /* what a failed write sets, not an earlier call's */
  fprintf(fp, "{\n  \"scene\": ");
  JsonString(fp, s->out.name);
  { /* which solver made the results */
    char petsc[32], mpi[MPI_MAX_LIBRARY_VERSION_STRING];
    FabricPetscVersion(petsc, sizeof petsc);
    FabricMpiLibrary(mpi, sizeof mpi);
    fprintf(fp, ",\n  \"fabric_revision\": ");
    JsonString(fp, FabricRevision());
    fprintf(fp, ",\n  \"petsc_version\": ");
    JsonString(fp, petsc);
    fprintf(fp, ",\n  \"mpi_library\": ");
    JsonString(fp, mpi);
  }
  fprintf(fp,
          ",\n  \"ranks\": %d,\n  \"grid\": [%" PetscInt_FMT ", %" PetscInt_FMT "],\n  \"points\": %" PetscInt_FMT
          ",\n",
          fab->size, s->spec.nx, s->spec.ny, fab->grid.points);
  if (fab->io && fab->io->restarted) /* a restart: from which checkpoint, so that a run says what it continues */
    fprintf(fp, "  \"restarted_from\": {\"load_steps_done\": %" PetscInt_FMT ", \"within_load_step\": %s},\n",
            fab->io->restart_load_step, fab->io->restart_within ? "true" : "false");
  else fprintf(fp, "  \"restarted_from\": null,\n");
  fprintf(fp, "  \"solver\": \"%s\",\n", SolverNames[s->num.solver]);
  if (s->num.solver == SOLVER_STATIC)
    fprintf(fp,
            "  \"nonlinear_iterations\": %" PetscInt64_FMT ",\n  \"linear_iterations\": %" PetscInt64_FMT
            ",\n  \"coarse_nonlinear_iterations\": %" PetscInt64_FMT ",\n",
            fab->stats.nonlinear_iterations, fab->stats.linear_iterations, fab->stats.coarse_nonlinear_iterations);
  if (s->num.solver == SOLVER_STATIC) /* Newton relaxes no load step (a tear runs the damped scheme) */
    fprintf(fp, "  \"integrator\": null,\n");
  else
    fprintf(fp, "  \"integrator\": \"%s\",\n", IntegratorNames[s->num.integrator]);
  fprintf(fp, "  \"predict\": \"%s\",\n  \"early_exit\": %s,\n", PredictNames[s->num.predict],
          s->num.early_exit ? "true" : "false");
  fprintf(fp,
          "  \"te_s\": %.6e,\n  \"te_bound_s\": %.6e,\n  \"load_steps\": %" PetscInt_FMT
          ",\n  \"load_steps_done\": %" PetscInt_FMT ",\n",
          (double) fab->step.te, (double) fab->step.te_bound, s->load.load_steps, done);
  fprintf(fp,
          "  \"te_steps\": %" PetscInt64_FMT ",\n  \"point_updates\": %" PetscInt64_FMT
          ",\n  \"wall_s\": %.6f,\n  \"point_updates_per_s\": %.6e,\n",
          fab->stats.te_steps, fab->stats.point_updates, (double) fab->stats.wall,
          fab->stats.wall > 0 ? (double) fab->stats.point_updates / fab->stats.wall : 0.0);
  fprintf(fp, "  \"te_rebounds\": %" PetscInt64_FMT ",\n", fab->stats.te_rebounds);
  fprintf(fp, "  \"gauge_mm\": %.6g,\n  \"width_mm\": %.6g,\n", (double) (s->spec.gauge * 1e3), (double) (s->spec.width * 1e3));
  JsonPeak(fp, "peak_force_N", fab->stats.rupture.peak_force);
  SummaryRupture(fab, fp);
  SummaryTeMeasure(fab, fp);
  if (s->num.kinetic_damping)
    fprintf(fp, "  \"kinetic_damping_resets\": %" PetscInt64_FMT ",\n", (PetscInt64) fab->step.ke_resets);
  if (s->test == TEST_DRAPE && done > 0)
    fprintf(fp, "  \"drape_coefficient_pct\": %.6g,\n  \"folds\": %" PetscInt_FMT ",\n", (double) fab->meas.drape_pct,
            fab->meas.folds);
  else if (s->test == TEST_DRAPE) /* no load step ended: nothing was measured (0 read as a result) */
    fprintf(fp, "  \"drape_coefficient_pct\": null,\n  \"folds\": null,\n");
  fprintf(fp, "  \"options\": {\n");
  SceneOptionsJson(s, fp, "    ");
  fprintf(fp, "  },\n  \"solver_options\": {\n");
  SolverOptionsJson(fp, "    ");
  fprintf(fp, "  },\n");
  fprintf(fp, "  \"converged\": %s", (fab->stats.converged && !error && (done == s->load.load_steps || fab->stats.rupture.rupture_step))
                                        ? "true"
                                        : "false");
  if (error) {
    fprintf(fp, ",\n  \"error\": ");
    JsonString(fp, error);
  }
  fprintf(fp, "\n}\n");
  write_error = ferror(fp);
  if (fclose(fp) || write_error) { /* a full disk: keep the summary.json there is, if any */
    status[0] = SUMMARY_WRITE, status[1] = errno ? errno : EIO; /* a write error fclose did not report again */
    (void) unlink(tmp);
    return;
  }
  if (rename(tmp, file)) status[0] = SUMMARY_RENAME, status[1] = errno;
}

/* summary.json: written at the end of a run, or with "error" when a run stops on an error. together: every rank
   calls it, and every rank stops alike if rank 0 could not write it (at the end of a run: the other ranks would
   go on into a collective and wait); otherwise rank 0 alone (a run's error, which may be rank 0's alone) */
PetscErrorCode OutputSummary(Fabric fab, const char *error, PetscBool together)
{
  const char *dir       = fab->s.out.output_dir;
  int         status[2] = {SUMMARY_OK, 0};

  PetscFunctionBeginUser;
  if (!dir[0] || (!together && fab->rank != 0)) PetscFunctionReturn(0);
  if (fab->rank == 0) SummaryWrite(fab, error, status);
  if (together) PetscCall(BroadcastFromRoot(fab->comm, status, 2, MPI_INT));
  fab->stats.summary_failed = status[0] != SUMMARY_OK ? PETSC_TRUE : PETSC_FALSE;
  PetscCheck(status[0] == SUMMARY_OK, together ? fab->comm : PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE,
             "-output_dir %s: cannot %s (%s)", dir,
             status[0] == SUMMARY_OPEN ? "create summary.json"
                                       : (status[0] == SUMMARY_WRITE ? "write summary.json" : "rename summary.json into place"),
             strerror(status[1]));
  PetscFunctionReturn(0);
}

/* final positions in natural (i fastest) order, PETSc binary: the rank-independence test */
PetscErrorCode OutputPositions(Fabric fab, const char *file)
{
  Vec         N;
  PetscViewer v;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(EV_Output, 0, 0, 0, 0));
  PetscCall(DMDACreateNaturalVector(fab->grid.da, &N));
  PetscCall(NaturalOrder(fab->grid.da, fab->state.X, N));
  PetscCall(PetscViewerCreate(fab->comm, &v));
  PetscCall(PetscViewerSetType(v, PETSCVIEWERBINARY));
  PetscCall(PetscViewerBinarySetSkipInfo(v, PETSC_TRUE));
  PetscCall(PetscViewerFileSetMode(v, FILE_MODE_WRITE));
  PetscCall(PetscViewerFileSetName(v, file));
  PetscCall(VecView(N, v));
  PetscCall(PetscViewerDestroy(&v));
  PetscCall(VecDestroy(&N));
  PetscCall(PetscLogEventEnd(EV_Output, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}
