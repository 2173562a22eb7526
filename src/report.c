/* output.c - everything the run writes: curve.csv, summary.json, progress, positions.
 *
 * Rank 0 writes the small text files; curve.csv gets one row per load step as the run
 * goes (flushed, so a long run can be watched). Nothing is created before the scene
 * has been read and checked, so bad input leaves no output behind.
 */
#include "report.h"
#include "comm.h"
#include "events.h"
#include "frames.h"
#include "load.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>

/* mkdir -p */
static int MakeDirs(const char *path)
{
  char   buf[PETSC_MAX_PATH_LEN];
  size_t n = strlen(path);
  if (n == 0 || n >= sizeof buf) return -1;
  memcpy(buf, path, n + 1);
  for (char *p = buf + 1; *p; p++) {
    if (*p != '/') continue;
    *p = 0;
    if (mkdir(buf, 0755) && errno != EEXIST) return -1;
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
  if (s->test == TEST_DRAPE) return "load_step,time_s,drop_mm,force_N,inner_steps,residual";
  if (s->test == TEST_STRIP) return "load_step,time_s,elongation_pct,force_N,inner_steps,residual";
  if (s->test == TEST_BIAS)
    return "load_step,time_s,elongation_pct,force_N,inner_steps,residual,travel_mm,center_shear_deg";
  return "load_step,time_s,travel_mm,force_N,inner_steps,residual";
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
    fprintf(fp, "%" PetscInt_FMT ",%.9g,%.9g,%.9g,%" PetscInt_FMT ",%.6e,%.9g,%.9g", r->load_step, (double) r->time,
            (double) (100.0 * r->elongation), (double) r->force, r->inner_steps, (double) r->residual,
            (double) (1e3 * r->elongation * s->spec.gauge), (double) r->center_shear);
  else if (s->test != TEST_STRIP)
    fprintf(fp, "%" PetscInt_FMT ",%.9g,%.9g,%.9g,%" PetscInt_FMT ",%.6e", r->load_step, (double) r->time,
            (double) (1e3 * r->travel), (double) r->force, r->inner_steps, (double) r->residual);
  else
    fprintf(fp, "%" PetscInt_FMT ",%.9g,%.9g,%.9g,%" PetscInt_FMT ",%.6e", r->load_step, (double) r->time,
            (double) (100.0 * r->elongation), (double) r->force, r->inner_steps, (double) r->residual);
  WriteSupports(s, fp, r);
  fputc('\n', fp);
}

/* curve.csv: the header, and after a restart the rows before the checkpoint */
PetscErrorCode OutputOpen(Fabric fab)
{
  const char *dir = fab->s.out.output_dir;
  int         ok  = 1;

  PetscFunctionBeginUser;
  if (!dir[0]) PetscFunctionReturn(0);
  if (fab->rank == 0) {
    char file[PETSC_MAX_PATH_LEN];
    ok = MakeDirs(dir) == 0;
    if (ok) {
      PetscCall(PetscSNPrintf(file, sizeof file, "%s/curve.csv", dir));
      fab->stats.curve_fp = fopen(file, "w");
      ok                  = fab->stats.curve_fp != NULL;
      if (ok) {
        fprintf(fab->stats.curve_fp, "%s", CurveHeader(&fab->s));
        WriteSupportsHeader(&fab->s, fab->stats.curve_fp);
        fputc('\n', fab->stats.curve_fp);
        for (PetscInt k = 0; k < fab->load.load_step; k++)
          WriteCurveRow(&fab->s, fab->stats.curve_fp, &fab->stats.curve[k]);
        fflush(fab->stats.curve_fp);
      }
    }
  }
  PetscCallMPI(MPI_Bcast(&ok, 1, MPI_INT, 0, fab->comm));
  PetscCheck(ok, fab->comm, PETSC_ERR_FILE_OPEN, "-output_dir %s: cannot create the directory or write curve.csv in it",
             dir);
  PetscFunctionReturn(0);
}

PetscErrorCode OutputCurveRow(Fabric fab, const CurveRow *r)
{
  PetscFunctionBeginUser;
  if (!fab->stats.curve_fp) PetscFunctionReturn(0);
  PetscCall(PetscLogEventBegin(EV_Output, 0, 0, 0, 0));
  WriteCurveRow(&fab->s, fab->stats.curve_fp, r);
  fflush(fab->stats.curve_fp);
  PetscCall(PetscLogEventEnd(EV_Output, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputProgress(Fabric fab, const CurveRow *r)
{
  const PetscInt  K   = fab->s.load.load_steps;
  const PetscReal eta = fab->stats.wall / r->load_step * (K - r->load_step);

  PetscFunctionBeginUser;
  if (fab->s.out.quiet) PetscFunctionReturn(0);
  if (!JawTest(&fab->s)) { /* no jaws: the load point's or the ball's travel, the drape's drop */
    PetscCall(PetscPrintf(
        fab->comm,
        "load step %4" PetscInt_FMT "/%" PetscInt_FMT "  travel %8.3f mm  force %10.4f N  N' %6" PetscInt_FMT
        "%s  residual %.2e  te %.3g s  elapsed %.1f s  ETA %.1f s\n",
        r->load_step, K, (double) (1e3 * r->travel), (double) r->force, r->inner_steps, r->balanced ? " " : "*",
        (double) r->residual, (double) fab->step.te, (double) fab->stats.wall, (double) eta));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscPrintf(
      fab->comm,
      "load step %4" PetscInt_FMT "/%" PetscInt_FMT "  elongation %7.3f %%  force %10.4f N  N' %6" PetscInt_FMT
      "%s  residual %.2e  te %.3g s  elapsed %.1f s  ETA %.1f s\n",
      r->load_step, K, (double) (100.0 * r->elongation), (double) r->force, r->inner_steps, r->balanced ? " " : "*",
      (double) r->residual, (double) fab->step.te, (double) fab->stats.wall, (double) eta));
  PetscFunctionReturn(0);
}

static void JsonString(FILE *fp, const char *s)
{
  fputc('"', fp);
  for (; *s; s++) {
    if (*s == '"' || *s == '\\') fputc('\\', fp);
    if (*s == '\n') {
      fputs("\\n", fp);
      continue;
    }
    fputc(*s, fp);
  }
  fputc('"', fp);
}

/* summary.json: written at the end of a run, or with "error" when a run stops on an error */
PetscErrorCode OutputSummary(Fabric fab, const char *error)
{
  const Scene *s = &fab->s;
  char         file[PETSC_MAX_PATH_LEN], tmp[PETSC_MAX_PATH_LEN];
  FILE        *fp;
  PetscReal    peak = 0;
  PetscInt     done = 0;

  PetscFunctionBeginUser;
  if (!s->out.output_dir[0] || fab->rank != 0) PetscFunctionReturn(0);
  for (PetscInt k = 0; k < s->load.load_steps; k++)
    if (fab->stats.curve[k].load_step) {
      peak = PetscMax(peak, fab->stats.curve[k].force);
      done++;
    }
  PetscCall(PetscSNPrintf(file, sizeof file, "%s/summary.json", s->out.output_dir));
  PetscCall(PetscSNPrintf(tmp, sizeof tmp, "%s/.summary.json.tmp", s->out.output_dir));
  fp = fopen(tmp, "w");
  PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "-output_dir %s: cannot write summary.json", s->out.output_dir);
  fprintf(fp, "{\n  \"scene\": ");
  JsonString(fp, s->out.name);
  fprintf(fp,
          ",\n  \"ranks\": %d,\n  \"grid\": [%" PetscInt_FMT ", %" PetscInt_FMT "],\n  \"points\": %" PetscInt_FMT
          ",\n",
          fab->size, s->spec.nx, s->spec.ny, fab->grid.points);
  fprintf(fp, "  \"integrator\": \"%s\",\n  \"predict\": \"%s\",\n  \"early_exit\": %s,\n",
          IntegratorNames[s->num.integrator], PredictNames[s->num.predict], s->num.early_exit ? "true" : "false");
  fprintf(fp,
          "  \"te_s\": %.6e,\n  \"te_bound_s\": %.6e,\n  \"load_steps\": %" PetscInt_FMT
          ",\n  \"load_steps_done\": %" PetscInt_FMT ",\n",
          (double) fab->step.te, (double) fab->step.te_bound, s->load.load_steps, done);
  fprintf(fp,
          "  \"te_steps\": %" PetscInt64_FMT ",\n  \"point_updates\": %" PetscInt64_FMT
          ",\n  \"wall_s\": %.6f,\n  \"point_updates_per_s\": %.6e,\n",
          fab->stats.te_steps, fab->stats.point_updates, (double) fab->stats.wall,
          fab->stats.wall > 0 ? (double) fab->stats.point_updates / fab->stats.wall : 0.0);
  fprintf(fp, "  \"gauge_mm\": %.6g,\n  \"width_mm\": %.6g,\n  \"peak_force_N\": %.9g,\n",
          (double) (s->spec.gauge * 1e3), (double) (s->spec.width * 1e3), (double) peak);
  if (s->num.kinetic_damping)
    fprintf(fp, "  \"kinetic_damping_resets\": %" PetscInt64_FMT ",\n", (PetscInt64) fab->step.ke_resets);
  if (s->test == TEST_DRAPE)
    fprintf(fp, "  \"drape_coefficient_pct\": %.6g,\n  \"folds\": %" PetscInt_FMT ",\n", (double) fab->meas.drape_pct,
            fab->meas.folds);
  fprintf(fp, "  \"options\": {\n");
  SceneOptionsJson(s, fp, "    ");
  fprintf(fp, "  },\n");
  fprintf(fp, "  \"converged\": %s", (fab->stats.converged && !error && done == s->load.load_steps) ? "true" : "false");
  if (error) {
    fprintf(fp, ",\n  \"error\": ");
    JsonString(fp, error);
  }
  fprintf(fp, "\n}\n");
  fclose(fp);
  PetscCheck(!rename(tmp, file), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE,
             "-output_dir %s: cannot rename summary.json into place", s->out.output_dir);
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
  PetscCall(DMDAGlobalToNaturalBegin(fab->grid.da, fab->state.X, INSERT_VALUES, N));
  PetscCall(DMDAGlobalToNaturalEnd(fab->grid.da, fab->state.X, INSERT_VALUES, N));
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
