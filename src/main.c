/* main.c - fabric: the woven-fabric crossing-point solver.
 *
 *   mpiexec -n P build/fabric -scene inputs/strip_warp.yaml -output_dir DIR [options]
 *
 * Phases: options and scene -> build the fabric -> run the load program -> report.
 */
#include "relax.h"
#include "static.h"
#include "static_options.h"
#include "checkpoint.h"
#include "frames.h"
#include "load.h"
#include "measure.h"
#include "report.h"
#include "scene.h"
#include "scenefile.h"

#include <ctype.h>
#include <math.h> /* isfinite */
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h> /* access */

static const char help[] = "fabric: woven-fabric mechanics at the yarn-crossing scale (explicit relaxation or a quasi-static Newton-Krylov solve, MPI-parallel).\n"
                           "  mpiexec -n P fabric -scene inputs/strip_warp.yaml [-output_dir DIR] [options]\n"
                           "Any scene key can be overridden on the command line. Units are in the option names.\n\n";

/* PETSc's "Input string abc has no numeric value" (or "integer value"), "Unable to find requested
   KSP type abc", "Unknown vector type: abc" and "Unknown logical value: 2" do not say which option:
   find the one given that value, of the class the message names where it names one (-ksp_type cg
   -pc_type cg: the PC's); a yes/no value, a solver's option first (a name holding snes_, ksp_, pc_,
   ... anywhere: -sub_pc_ too), since the fabric's own yes/no options say their errors themselves. PETSc's
   "Newly set value -1 less than allowed bound 0" (-da_refine -1, -da_overlap -1): the option given that
   integer, a PETSc option first likewise. */
static int PetscsOwn(const char *nm)
{
  static const char *const part[] = {"snes_", "ksp_", "pc_", "mg_", "tao_", "mat_", "da_", "dm_"};
  for (size_t k = 0; k < sizeof part / sizeof part[0]; k++)
    if (strstr(nm, part[k])) return 1;
  return 0;
}

/* the given option whose value is the integer v (as PETSc reads one), a PETSc option first; "" if none */
static void GivenInteger(long long v, char *found, size_t len)
{
  OptionsGiven g;
  found[0] = 0;
  if (OptionsGivenGet(&g)) return;
  for (int pass = 0; pass < 2 && !found[0]; pass++)
    for (PetscInt q = 0; q < g.n && !found[0]; q++) {
      char     *end;
      long long w = strtoll(g.value[q], &end, 10);
      if (end == g.value[q] || *end || w != v || (!pass && !PetscsOwn(g.name[q]))) continue;
      snprintf(found, len, "%s", g.name[q]);
    }
  OptionsGivenFree(&g);
}

static void NameTheOption(const char *mess, char *out, size_t len)
{
  static const char *const classes[][2] = {
      {"requested KSP type", "ksp_type"},          {"requested PC type", "pc_type"},
      {"requested SNES type", "snes_type"},        {"requested Line Search type", "linesearch_type"},
      {"requested PetscSF type", "sf_type"},       {"requested Tao type", "tao_type"},
      {"Unknown vector type", "vec_type"},         {"requested Mat type", "mat_type"},
      {"requested KSPGuess type", "ksp_guess_type"}};
  const char  *pre = "Input string ", *last = strrchr(mess, ' ');
  const char  *post = strstr(mess, " has no numeric value") ? " has no numeric value" : " has no integer value";
  const int    number = !strncmp(mess, pre, strlen(pre)) && strstr(mess, post);
  const char  *want   = "type"; /* any type's option, unless the message names its class */
  char         value[256], found[256] = "";
  OptionsGiven g;

  snprintf(out, len, "%s", mess);
  if (!strncmp(mess, "Unknown logical value: ", 23)) { /* PETSc's yes/no options (-mg_line_smoother 2): said as the
                                                           fabric's own are */
    snprintf(value, sizeof value, "%s", mess + 23);
    if (OptionsGivenGet(&g)) return;
    for (int pass = 0; pass < 2 && !found[0]; pass++) /* a solver's option first: the fabric's own say their errors */
      for (PetscInt q = 0; q < g.n && !found[0]; q++) {
        const char *nm = g.name[q];
        if (strcmp(g.value[q], value)) continue;
        if (!pass && !PetscsOwn(nm)) continue;
        snprintf(found, sizeof found, "%s", nm);
      }
    OptionsGivenFree(&g);
    if (found[0]) snprintf(out, len, "%s %s: not a yes/no value (use 1 or 0, true or false)", found, value);
    return;
  }
  {
    long long v, bound;
    char      rel[16];
    if (sscanf(mess, "Newly set value %lld %15s than allowed bound %lld", &v, rel, &bound) == 3) {
      GivenInteger(v, found, sizeof found);
      if (found[0])
        snprintf(out, len, "%s %lld: PETSc takes %s %lld for it", found, v, strcmp(rel, "less") ? "at most" : "at least",
                 bound);
      return;
    }
  }
  if (!strncmp(mess, "Cannot create VECSEQ on more than one process", 45)) { /* -dm_vec_type seq on 2 ranks */
    if (OptionsGivenGet(&g)) return;
    for (PetscInt q = 0; q < g.n && !found[0]; q++)
      if (OptionIs(g.name[q], "vec_type") && !strcasecmp(g.value[q], "seq")) snprintf(found, sizeof found, "%s", g.name[q]);
    OptionsGivenFree(&g);
    if (found[0]) snprintf(out, len, "%s seq: a sequential vector lives on one rank, and this run has more (leave %s unset)", found, found);
    return;
  }
  if (number)
    snprintf(value, sizeof value, "%.*s", (int) (strstr(mess, post) - mess - strlen(pre)), mess + strlen(pre));
  else if (last && (!strncmp(mess, "Unable to find requested ", 25) || !strncmp(mess, "Unknown ", 8)) &&
           strstr(mess, " type"))
    snprintf(value, sizeof value, "%s", last + 1);
  else
    return;
  for (size_t c = 0; c < sizeof classes / sizeof classes[0]; c++)
    if (strstr(mess, classes[c][0])) want = classes[c][1];
  if (OptionsGivenGet(&g)) return;
  for (PetscInt q = 0; q < g.n; q++) {
    if (strcmp(g.value[q], value)) continue;
    if (number || OptionIs(g.name[q], want)) { /* the class's own option */
      snprintf(found, sizeof found, "%s", g.name[q]);
      break;
    }
    if (!found[0] && OptionIs(g.name[q], "type")) snprintf(found, sizeof found, "%s", g.name[q]); /* else any type's */
  }
  OptionsGivenFree(&g);
  if (found[0] && number)
    snprintf(out, len, "%s %s: %s", found, value,
             !strstr(post, "integer") ? "not a number" : strpbrk(value, "eE.") ? "not an integer (integers are read in digits only, with no exponent or decimal point)" : "not an integer");
  else if (found[0]) snprintf(out, len, "%s %s: %s", found, value, mess);
}

/* An error raised inside PETSc's solvers (KSP, PC, SNES, TAO, Mat: their sources' paths) names no option of
   the run: " (in PETSc's solvers; the solver options given: -ksp_type minres ...)", or "" if none was
   given or the error is not theirs */
static const char *SolverErrorCause(const char *file)
{
  static char cause[512];
  char        given[448];

  cause[0] = 0;
  if (!file ||
      !(strstr(file, "src/ksp/") || strstr(file, "src/snes/") || strstr(file, "src/tao/") || strstr(file, "src/mat/") ||
        strstr(file, "src/dm/")))
    return cause;
  SolverOptionsGiven(given, sizeof given);
  if (given[0]) snprintf(cause, sizeof cause, " (in PETSc's solvers; the solver options given: %s)", given);
  return cause;
}

/* An MPI call failed: what the options asked of MPI that it may not offer ("" if nothing) */
static const char *MpiErrorCause(void)
{
  static char cause[320];
  char        type[256];
  PetscBool   set = PETSC_FALSE;

  cause[0] = 0;
  if (!PetscOptionsGetString(NULL, NULL, "-sf_type", type, sizeof type, &set) && set)
    snprintf(cause, sizeof cause, " (with -sf_type %s: this MPI may not run it; leave -sf_type unset)", type);
  return cause;
}

/* One clear line per error. Input errors are seen by every rank alike, so rank 0 says them;
   other ranks speak only of errors that are theirs alone (memory, numerics, library, MPI). An
   MPI error stops every rank, as MPI's own handler did before it was set to return them. */
static char unsaid[1024]; /* this rank's error, when rank 0 was to say it (StopTogether: if rank 0 did not have it) */

/* a message on one line: a value's line breaks (a YAML block scalar's) shown as \n and \r */
static void OneLine(char *text, size_t len)
{
  char   out[2048];
  size_t o = 0;
  for (const char *c = text; *c && o + 2 < sizeof out; c++) {
    if (*c == '\n' || *c == '\r') out[o++] = '\\', out[o++] = *c == '\n' ? 'n' : 'r';
    else out[o++] = *c;
  }
  if (o > len - 1) o = len - 1; /* cut, as the message was to its buffer */
  memcpy(text, out, o);
  text[o] = 0;
}

static PetscErrorCode OneLineErrorHandler(MPI_Comm comm, int line, const char *fun, const char *file, PetscErrorCode n,
                                          PetscErrorType p, const char *mess, void *ctx)
{
  PetscMPIInt rank = 0, world = 0;
  int         says, oom; /* this rank says the error; out of memory */
  char        text[1024];
  (void) ctx;
  if (p != PETSC_ERROR_INITIAL) return n;
  if (comm != MPI_COMM_NULL) MPI_Comm_rank(comm, &rank);
  MPI_Comm_rank(PETSC_COMM_WORLD, &world);
  if (n == PETSC_ERR_MPI && world) sleep(1); /* rank 0 says it and stops every rank, if it has it too */
  /* an allocation that failed (the grid's own needs are checked before it is made, fabric.c): PETSc 3.18's
     PetscMallocAlign raises it with its arguments shifted (the code is its caller's line, the message its name) */
  oom  = n == PETSC_ERR_MEM || (fun && !strcmp(fun, "PetscMallocAlign"));
  says = world == 0 || (rank == 0 && (oom || n == PETSC_ERR_PLIB || n == PETSC_ERR_LIB || n == PETSC_ERR_SYS ||
                                      n == PETSC_ERR_MPI));
  if (oom)
    snprintf(text, sizeof text,
             "out of memory (in %s): this run needs more memory than the node or its limit (ulimit -v) gives a rank; "
             "run fewer crossings per rank (more ranks or nodes)",
             fun && strcmp(fun, "PetscMallocAlign") ? fun : mess && mess[0] ? mess : "an allocation");
  if (!says && mess && mess[0] && !unsaid[0]) {
    if (!oom) NameTheOption(mess, text, sizeof text);
    OneLine(text, sizeof text);
    snprintf(unsaid, sizeof unsaid, "%s", text);
  }
  if (says) {
    fflush(stdout); /* what it printed (-help's list) first: the error line starts a line of its own */
    if (oom) fprintf(stderr, "fabric: error: %s\n", text);
    else if (mess && mess[0]) {
      NameTheOption(mess, text, sizeof text);
      OneLine(text, sizeof text);
      fprintf(stderr, "fabric: error: %s%s\n", text, n == PETSC_ERR_MPI ? MpiErrorCause() : SolverErrorCause(file));
    } else {
      const char *text = NULL;
      PetscErrorMessage(n, &text, NULL);
      fprintf(stderr, "fabric: error: %s (in %s, %s:%d)\n", text ? text : "unknown", fun, file, line);
    }
    fflush(stderr);
  }
  if (n == PETSC_ERR_MPI) MPI_Abort(MPI_COMM_WORLD, 1); /* as MPI would have: no rank is left waiting */
  return n;
}

static int stop_signals_caught; /* CatchStopSignals installed its handler */

/* SIGTERM (a batch system's wall-time limit) or SIGUSR1 (forwarded to the ranks by mpiexec): the run writes
   a checkpoint at its next te step and stops with exit status 3 (checkpoint.c). Only with an output
   directory to write it to; the handler only sets a flag. */
static PetscErrorCode CatchStopSignals(Fabric fab)
{
  struct sigaction sa;

  PetscFunctionBeginUser;
  if (!fab->s.out.output_dir[0]) PetscFunctionReturn(0);
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = CheckpointSignal;
  sa.sa_flags   = SA_RESTART;
  sigemptyset(&sa.sa_mask);
  PetscCheck(!sigaction(SIGTERM, &sa, NULL) && !sigaction(SIGUSR1, &sa, NULL), PETSC_COMM_SELF, PETSC_ERR_SYS,
             "cannot catch SIGTERM and SIGUSR1");
  stop_signals_caught = 1;
  PetscFunctionReturn(0);
}

static PetscErrorCode Run(int argc, char **argv)
{
  Fabric         fab  = NULL;
  PetscBool      help = PETSC_FALSE;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(SceneInsertFile(PETSC_COMM_WORLD, argc, argv));
  PetscCall(FabricCreate(PETSC_COMM_WORLD, &fab));
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  if (help) {
    PetscCall(StaticOptionsCheck(PETSC_COMM_WORLD)); /* the quasi-static solver's own options */
    PetscCall(FabricDestroy(&fab));
    PetscCall(SceneCheckUnused(PETSC_COMM_WORLD, PETSC_TRUE)); /* a misspelt option beside -help: after the list */
    PetscFunctionReturn(0);
  }
  if (fab->s.test == TEST_DRAPE) PetscCall(DrapeSetUp(fab)); /* the flat specimen's outline, wider than its support */
  if (fab->s.num.solver == SOLVER_STATIC) PetscCall(StaticOptionsCheck(PETSC_COMM_WORLD)); /* reads -static_* */
  PetscCall(SceneCheckUnused(PETSC_COMM_WORLD, fab->s.num.solver == SOLVER_STATIC));
  if (!fab->s.out.quiet) {
    char travel[48] = ""; /* the drape moves nothing: gravity alone */
    if (fab->s.test != TEST_DRAPE)
      PetscCall(PetscSNPrintf(travel, sizeof travel, ", %.3g mm of travel", (double) (1e3 * LoadTravel(&fab->s))));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                          "fabric: scene %s, %" PetscInt_FMT " x %" PetscInt_FMT " crossings (%" PetscInt_FMT
                          " points) on %d rank%s, %s %s, prediction %s, %" PetscInt_FMT " load step%s, test %s%s\n",
                          fab->s.out.name, fab->s.spec.nx, fab->s.spec.ny, fab->grid.points, fab->size,
                          fab->size == 1 ? "" : "s",
                          fab->s.num.solver == SOLVER_STATIC ? "static" : IntegratorNames[fab->s.num.integrator],
                          fab->s.num.solver == SOLVER_STATIC ? "solver" : "integrator", PredictNames[fab->s.num.predict],
                          fab->s.load.load_steps, fab->s.load.load_steps == 1 ? "" : "s", TestNames[fab->s.test], travel));
  }
  PetscCall(CatchStopSignals(fab));
  ierr = FabricRun(fab);
  if (ierr) { /* a run that stops on an error still says so in summary.json */
    const char *text;
    char       *specific = NULL;
    PetscErrorMessage(ierr, &text, &specific);
    if (PetscTime(&fab->stats.wall) == 0) fab->stats.wall -= fab->stats.wall_start; /* the time it ran */
    if (fab->stats.curve_fp && !fab->stats.summary_failed) OutputSummary(fab, specific && specific[0] ? specific : text, PETSC_FALSE);
    FabricDestroy(&fab);
    return ierr;
  }
  if (fab->s.num.solver == SOLVER_STATIC) PetscCall(SceneWarnUnused(PETSC_COMM_WORLD, "")); /* misspelt -snes_* */
  if (CheckpointStopped()) { /* stopped by a signal after its checkpoint: no results yet */
    PetscCall(FabricDestroy(&fab));
    PetscFunctionReturn(0);
  }
  { /* the end line, with or without an output directory */
    const RuptureState *r    = &fab->stats.rupture;
    const PetscReal     peak = r->peak_force;
    const PetscInt      K    = r->rupture_step ? r->rupture_step : fab->s.load.load_steps;
    char                where[160], work[128], force[96];
    const CurveRow     *last = &fab->stats.curve[K - 1];
    /* the jaw tests end at an elongation, the others at a travel (sphere, load point, drop) */
    if (JawTest(&fab->s))
      PetscCall(PetscSNPrintf(where, sizeof where, "%s at %.4g %% elongation (maximum force at %.4g %%)",
                              r->rupture_step ? "ruptured" : "last load step", (double) (100 * last->elongation),
                              (double) (100 * r->at_peak)));
    else /* the drape's travel is its largest drop (curve.csv drop_mm) */
      PetscCall(PetscSNPrintf(where, sizeof where, "%s at %.4g mm %s", r->rupture_step ? "burst" : "last load step",
                              (double) (1e3 * last->travel), fab->s.test == TEST_DRAPE ? "drop" : "travel"));
    if (fab->s.num.solver == SOLVER_STATIC)
      PetscCall(PetscSNPrintf(work, sizeof work,
                              "%" PetscInt64_FMT " Newton steps, %" PetscInt64_FMT " Krylov iterations",
                              fab->stats.nonlinear_iterations, fab->stats.linear_iterations));
    else
      PetscCall(PetscSNPrintf(work, sizeof work, "%" PetscInt64_FMT " te steps, %.3e point updates/s",
                              fab->stats.te_steps,
                              fab->stats.wall > 0 ? (double) fab->stats.point_updates / fab->stats.wall : 0.0));
    if (fab->s.test == TEST_DRAPE) /* nothing pulls a drape: its result is the outline */
      PetscCall(PetscSNPrintf(force, sizeof force, "drape coefficient %.4g %%, %" PetscInt_FMT " folds",
                              (double) fab->meas.drape_pct, fab->meas.folds));
    else
      PetscCall(PetscSNPrintf(force, sizeof force, "peak force %.4g N%s", (double) peak,
                              r->peak_balanced ? "" : " (from a load step that did not balance)"));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fabric: done in %.2f s: %s; %s, %s; %s\n", (double) fab->stats.wall,
                          work, force, where,
                          fab->stats.converged         ? "every load step balanced"
                          : fab->s.out.output_dir[0] ? "some load steps did NOT balance (see curve.csv residual)"
                                                     : "some load steps did NOT balance"));
    if (fab->s.test == TEST_PUSHING && peak == 0 && fab->stats.converged) { /* a result, but not a pushing test's (an
                                                                                unbalanced run's 0 N has other causes) */
      const Bodies *b = &fab->s.bodies;
      PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                            "fabric: warning: the ball touched the fabric in no load step (peak force 0 N): its path from "
                            "-sphere_start_mm %g,%g,%g along -sphere_direction %g,%g,%g for -sphere_travel_mm %g misses "
                            "the specimen\n",
                            (double) (1e3 * b->sphere_start[0]), (double) (1e3 * b->sphere_start[1]),
                            (double) (1e3 * b->sphere_start[2]), (double) b->sphere_dir[0], (double) b->sphere_dir[1],
                            (double) b->sphere_dir[2], (double) (1e3 * b->sphere_travel)));
    }
    if (fab->s.num.solver != SOLVER_STATIC) { /* unbalanced below the force test: say what else held them */
      PetscInt n = 0;
      for (PetscInt k = 0; k < K; k++)
        n += !fab->stats.curve[k].balanced && fab->stats.curve[k].residual <= fab->s.num.balance_tol && k + 1 != r->rupture_step;
      if (n)
        PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                              "fabric: %" PetscInt_FMT " load step%s did not balance with a residual below -balance_tol %g: "
                              "crossings still moved faster than -speed_tol %g m/s, the grip's ramp had not ended, or a "
                              "crossing's own forces did not balance within -max_inner_steps %" PetscInt_FMT "\n",
                              n, n == 1 ? "" : "s", (double) fab->s.num.balance_tol, (double) fab->s.num.speed_tol,
                              fab->s.load.max_inner_steps));
    }
  }
  if (fab->s.out.output_dir[0]) {
    char files[256];
    PetscCall(IODescribe(fab->io, fab->s.out.output_dir, RestartsFrom(fab->s.out.output_dir, fab->s.out.restart), files,
                         sizeof files));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fabric: results in %s/ (%s)\n", fab->s.out.output_dir, files));
  }
  PetscCall(FabricDestroy(&fab));
  PetscFunctionReturn(0);
}

/* A run stopped on an error on this rank; do the other ranks stop with it? An error every rank
   sees (bad input, a value that is not finite) meets here at once, on a communicator of its own. An
   error of this rank alone (a PETSc solver that fails on one rank) leaves the others waiting in the
   run's next collective for ever: after STOP_WAIT_S seconds this rank stops them all. */
#define STOP_WAIT_S 10.0
static MPI_Comm stop_comm = MPI_COMM_NULL;

static void StopTogether(void)
{
  MPI_Request req;
  int         size = 1, done = 0;
  double      t0 = MPI_Wtime();

  MPI_Comm_size(stop_comm, &size);
  if (size == 1) return;
  if (MPI_Ibarrier(stop_comm, &req) != MPI_SUCCESS) MPI_Abort(MPI_COMM_WORLD, 1);
  while (!done && MPI_Wtime() - t0 < STOP_WAIT_S)
    if (MPI_Test(&req, &done, MPI_STATUS_IGNORE) != MPI_SUCCESS || !done) usleep(1000);
  if (done) return;
  if (unsaid[0]) { /* an error of this rank alone (a file only rank 0 sees, say), which rank 0 was to say */
    int world = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &world);
    fprintf(stderr, "fabric: error on rank %d: %s\n", world, unsaid);
  }
  fprintf(stderr, "fabric: error: the other ranks did not stop with this one within %g s: stopping them\n",
          STOP_WAIT_S);
  MPI_Abort(MPI_COMM_WORLD, 1);
}

/* The files PETSc opens within PetscInitialize: -options_file and -options_file_yaml (read: those of
   the command line by rank 0, those named in PETSC_OPTIONS or in an option file by every rank),
   -history, -info and -log_trace (written; -log_trace F writes F.0, F.1, ...). A missing one stops
   the run there with PETSc's traceback, or worse (-history: a segmentation fault). Rank 0 looks
   first, says why, and every rank takes its verdict. An option file's own options are looked at as
   the command line's (PETSc reads a -options_file named in one, and one that names itself
   recursed until it crashed): depth counts the files within files, reading[] holds them. Option
   names are PETSc's, whatever their case; a file name with ${...} in it is left to PETSc, which
   puts in its own and the environment's variables there. The -scene file that PETSc will read after its start
   (SceneInsertFile) is looked at here for its "$$name: !include F" lines only (SceneIncludeProblem, once every source
   of options has been walked); the rest of it is SceneInsertFile's to judge. */
#define OPTION_FILES_NESTED_MAX 64
static struct stat reading[OPTION_FILES_NESTED_MAX];
static int         only_files; /* within a scene's !include files, or a YAML file included under a key's prefix:
                                  only the files read are looked at (PETSc takes no start-up option, -history ...,
                                  from a scene, and an included file's keys under a prefix are other options) */
static struct {    /* the -scene PETSc will take: the last of the strongest source (InitFileProblem's passes);
                      file "" if none */
  char file[4096], where[4096];
  int  source;
} scene_named;
static int option_source; /* the pass under way: 0 PETSc's start-up files, 1 PETSC_OPTIONS, 2 PETSC_OPTIONS_YAML,
                             3 the command line (PETSc's order: each later one wins) */

static int FileOptionProblem(int n, char **tok, const char *where, int depth);

/* a file's size bytes and a NUL after them, NULL if they cannot be read; the caller frees it */
static char *ReadText(const char *file, off_t size)
{
  FILE *fp   = fopen(file, "rb");
  char *text = fp ? calloc((size_t) size + 1, 1) : NULL;
  if (text && fread(text, 1, (size_t) size, fp) != (size_t) size) free(text), text = NULL;
  if (fp) fclose(fp);
  return text;
}

/* a YAML file's options as PETSc would set them (YamlOptionsProblem), none if it cannot be read; why: its problem
   ("" if none, or if it cannot be read: its reader says why) */
static void ReadYamlOptions(const char *file, struct stat *st, char ***opts, int *nopts, char *why, size_t len, int *include)
{
  char *text;

  *opts = NULL, *nopts = 0, why[0] = 0, *include = 0;
  if (stat(file, st) || !S_ISREG(st->st_mode)) return;
  text = ReadText(file, st->st_size);
  if (text && !memchr(text, '\0', (size_t) st->st_size)) {
    (void) YamlOptionsProblem(text, why, len, opts, nopts);
    *include = strstr(text, "!include") != NULL;
  }
  free(text);
}

typedef struct { /* the options a scene and its !include files set so far, the file of each, and the files read */
  char **name, **file;
  int    n, cap;
} KeysSeen;

static int KeysAdd(KeysSeen *seen, const char *name, const char *file)
{
  char *a, *b;
  if (seen->n == seen->cap) {
    const int cap = 2 * seen->cap + 16;
    char    **n2  = realloc(seen->name, (size_t) cap * sizeof *n2), **f2;
    if (!n2) return 1;
    seen->name = n2;
    if (!(f2 = realloc(seen->file, (size_t) cap * sizeof *f2))) return 1;
    seen->file = f2, seen->cap = cap;
  }
  a = strdup(name), b = strdup(file);
  if (!a || !b) {
    free(a), free(b);
    return 1;
  }
  seen->name[seen->n] = a, seen->file[seen->n] = b, seen->n++;
  return 0;
}

/* An option that the scene and a file it includes (or two such files) both set: PETSc keeps the one it reads last,
   which depends on where the !include lines stand. An included file's scene: key, which PETSc would read as -scene
   and never look at. A "$$name: !include F" under a key's mapping reads F's options under that key's prefix
   (YamlFlatten gives it as -options_file_yaml F, "-$$prefix" P); a file read again under the same prefix adds
   nothing to look at (its own lines were looked at the first time). Out of memory: the rest of this file is not
   looked at. */
static int IncludedKeysProblem(const char *scene, const char *file, const char *prefix, char **opts, int nopts, KeysSeen *seen,
                               KeysSeen *files, int depth)
{
  for (int k = 0; k + 1 < nopts; k += 2) {
    if (!strcmp(opts[k], "-$$prefix")) continue;
    if (!strcmp(opts[k], "-options_file_yaml")) {
      struct stat st;
      char      **sub, id[4200], why[512], pre[4200];
      int         nsub, bad, include;
      snprintf(pre, sizeof pre, "%s%s", prefix, k + 3 < nopts && !strcmp(opts[k + 2], "-$$prefix") ? opts[k + 3] : "");
      if (strstr(opts[k + 1], "${") || depth + 1 >= OPTION_FILES_NESTED_MAX) continue; /* PETSc's; a loop: said before */
      if (stat(opts[k + 1], &st)) continue;
      snprintf(id, sizeof id, "%lu:%lu:%.4000s", (unsigned long) st.st_dev, (unsigned long) st.st_ino, pre);
      for (int q = 0; q < files->n; q++)
        if (!strcasecmp(files->name[q], id)) id[0] = 0; /* an option's name, and so a prefix, has no case */
      if (!id[0]) continue;
      if (KeysAdd(files, id, "")) return 0; /* the file and its prefix: its name is not needed again */
      ReadYamlOptions(opts[k + 1], &st, &sub, &nsub, why, sizeof why, &include);
      bad = IncludedKeysProblem(scene, opts[k + 1], pre, sub, nsub, seen, files, depth + 1);
      OptionFileFree(sub, nsub);
      if (bad) return 1;
      continue;
    }
    {
      char name[4200];
      snprintf(name, sizeof name, "-%s%s", prefix, opts[k] + 1);
      if (depth > 0 && !strcasecmp(name, "-scene")) {
        fprintf(stderr, "fabric: error: -scene %s: its !include %s names a scene (scene: %s); a scene file cannot name another scene\n",
                scene, file, opts[k + 1]);
        return 1;
      }
      for (int q = 0; q < seen->n; q++)
        if (!strcasecmp(seen->name[q], name)) {
          fprintf(stderr, "fabric: error: -scene %s: %s is set twice, in %s and in %s (the scene and the files it includes): PETSc keeps the one it reads last; set it once\n",
                  scene, name, seen->file[q], file);
          return 1;
        }
      if (KeysAdd(seen, name, file)) return 0;
    }
  }
  return 0;
}

/* A scene's "$$name: !include F" lines: PETSc reads each as -options_file_yaml F, so they are looked at as option
   files within the scene file (a scene that included itself recursed until it crashed), then for options set twice
   across the files. A scene that PETSc would refuse as malformed is SceneInsertFile's to judge, unless it includes:
   PETSc reads a YAML file a document at a time, and followed the includes of the documents before the malformed one. */
static int SceneIncludeProblem(const char *file, const char *where)
{
  struct stat st;
  char      **opts, **inc, in[8400], why[512];
  int         nopts, ninc = 0, bad = 0, include;

  ReadYamlOptions(file, &st, &opts, &nopts, why, sizeof why, &include);
  if (why[0] && include) {
    fprintf(stderr, "fabric: error: -scene %s%s: not a valid YAML option file: %s\n", file, where, why);
    return 1;
  }
  inc = nopts ? calloc((size_t) nopts, sizeof *inc) : NULL;
  for (int k = 0; inc && k + 1 < nopts; k += 2)
    if (!strcmp(opts[k], "-options_file_yaml")) inc[ninc++] = opts[k], inc[ninc++] = opts[k + 1];
  if (ninc) {
    KeysSeen seen = {0}, files = {0};
    snprintf(in, sizeof in, " (a !include of -scene %.4000s%.4000s)", file, where);
    reading[0] = st;
    only_files++;
    bad = FileOptionProblem(ninc, inc, in, 1);
    only_files--;
    if (!bad) bad = IncludedKeysProblem(file, file, "", opts, nopts, &seen, &files, 0);
    for (int q = 0; q < seen.n; q++) free(seen.name[q]), free(seen.file[q]);
    for (int q = 0; q < files.n; q++) free(files.name[q]), free(files.file[q]);
    free(seen.name), free(seen.file), free(files.name), free(files.file);
  }
  free(inc);
  OptionFileFree(opts, nopts);
  return bad;
}

static int FileOptionProblem(int n, char **tok, const char *where, int depth)
{
  for (int k = 0; k < n; k++) {
    const int   plain = !strcasecmp(tok[k], "-options_file"), read = plain || !strcasecmp(tok[k], "-options_file_yaml");
    const int   history = !strcasecmp(tok[k], "-history"), info = !strcasecmp(tok[k], "-info");
    const int   write = history || info || !strcasecmp(tok[k], "-log_trace");
    const char *f        = k + 1 < n ? tok[k + 1] : "";
    const int   prefixed = read && k + 3 < n && !strcmp(tok[k + 2], "-$$prefix"); /* a YAML !include under a key */
    struct stat st;
    if (only_files && !read) continue;
    if (!strcasecmp(tok[k], "-log_view") && k + 1 < n && tok[k + 1][0] != '-') { /* parsed by PetscInitialize */
      char why[1024];
      if (ViewerValueProblem("log_view", tok[k + 1], why, sizeof why)) {
        fprintf(stderr, "fabric: error: %s%s\n", why, where);
        return 1;
      }
    }
    if (!strcasecmp(tok[k], "-petsc_sleep")) { /* PetscInitialize sleeps that long: NaN for ever */
      const char  *v = k + 1 < n && !(tok[k + 1][0] == '-' && isalpha((unsigned char) tok[k + 1][1])) ? tok[k + 1] : "";
      char        *end;
      const double s = strtod(v, &end);
      if (end == v || *end || !isfinite(s)) {
        fprintf(stderr, "fabric: error: -petsc_sleep '%s'%s: PetscInitialize sleeps that many seconds: give a finite number\n",
                v, where);
        return 1;
      }
    }
    if (!strcasecmp(tok[k], "-scene") && f[0] && f[0] != '-' && option_source >= scene_named.source) {
      snprintf(scene_named.file, sizeof scene_named.file, "%s", f);
      snprintf(scene_named.where, sizeof scene_named.where, "%s", where);
      scene_named.source = option_source;
    }
    if (!read && !write) continue;
    if (!f[0] || f[0] == '-' || (info && f[0] == ':')) { /* -info :sys: classes, no file */
      if (!read) continue; /* -history, -info and -log_trace without one write to PETSc's default */
      fprintf(stderr, "fabric: error: %s needs a file name%s\n", tok[k], where);
      return 1;
    }
    if (strstr(f, "${")) continue; /* PETSc's substitution: its file, not this name */
    if (read) { /* -options_file F is YAML to PETSc (as -options_file_yaml F) if named F.yaml, F.yml, F.json or
                   F:yaml, or if it starts with "%YAML " or "---" (PetscOptionsFilename; -options_file_yaml F:yaml
                   is the file of that name) */
      const size_t n   = strlen(f);
      const int    tag = plain && n > 5 && !strcmp(f + n - 5, ":yaml");
      int          yaml = !plain || tag || (n > 4 && !strcmp(f + n - 4, ".yml")) ||
                 (n > 5 && !strcmp(f + n - 5, ".yaml")) || (n > 5 && !strcmp(f + n - 5, ".json"));
      char         name[4096], why[512] = "", **opts = NULL;
      int          nopts = 0, bad = 0;
      char        *text;
      snprintf(name, sizeof name, "%.*s", (int) (tag ? n - 5 : n), f);
      if (stat(name, &st) || !S_ISREG(st.st_mode) || access(name, R_OK)) {
        fprintf(stderr, "fabric: error: %s %s%s: no such file, or not a readable file\n", tok[k], f, where);
        return 1;
      }
      /* PETSc refuses a malformed one with a traceback */
      if ((text = ReadText(name, st.st_size))) {
        const char *nul = memchr(text, '\0', (size_t) st.st_size); /* PETSc reads the file as a string: up to it */
        yaml            = yaml || !strncmp(text, "%YAML ", 6) || !strncmp(text, "---", 3);
        if (nul)
          snprintf(why, sizeof why, "byte %ld is a NUL (a binary file?); PETSc would read nothing after it",
                   (long) (nul - text) + 1);
        else
          (void) (yaml ? YamlOptionsProblem(text, why, sizeof why, &opts, &nopts)
                       : OptionFileProblem(text, why, sizeof why, &opts, &nopts));
      }
      free(text);
      if (why[0]) {
        fprintf(stderr, "fabric: error: %s %s%s: not a valid %s option file: %s\n", tok[k], f, where, yaml ? "YAML" : "PETSc",
                why);
        return 1;
      }
      for (int d = 0; d < depth && !bad; d++)
        if (reading[d].st_dev == st.st_dev && reading[d].st_ino == st.st_ino) {
          fprintf(stderr, "fabric: error: %s %s%s: the file is read within itself (PETSc would read it for ever)\n", tok[k], f,
                  where);
          bad = 1;
        }
      if (!bad && nopts) { /* the file's own -options_file, -history, ... */
        char in[8192];
        snprintf(in, sizeof in, " (in %s%s)", f, where);
        if (depth + 1 < OPTION_FILES_NESTED_MAX) {
          reading[depth] = st;
          only_files += prefixed;
          bad = FileOptionProblem(nopts, opts, in, depth + 1);
          only_files -= prefixed;
        } else {
          fprintf(stderr, "fabric: error: %s %s%s: option files nested %d deep\n", tok[k], f, where, OPTION_FILES_NESTED_MAX);
          bad = 1;
        }
      }
      OptionFileFree(opts, nopts);
      if (bad) return 1;
    }
    if (write) { /* -log_trace F and -info F write F.0 first (-info F:classes: the file is F) */
      char path[4096], msg[8192];
      snprintf(path, sizeof path, "%.*s%s", (int) (info ? strcspn(f, ":") : strlen(f)), f, history ? "" : ".0");
      ProbeFile(tok[k] + 1, path, "", msg, sizeof msg);
      if (msg[0]) {
        fprintf(stderr, "fabric: error: %s%s\n", msg, where);
        return 1;
      }
    }
  }
  return 0;
}

/* PETSc's own option files, read at every start unless the command line says -skip_petscrc (alone, or true):
   ~/.petscrc, then .petscrc and petscrc in the working directory (PetscOptionsInsert); one that is not there,
   or not a readable file, is passed over */
static int RcFileProblem(int argc, char **argv)
{
  const char *home = getenv("HOME");
  char        path[3][4096];

  int skip = 0;
  for (int k = 1; k < argc; k++) /* the last one decides; a value as PETSc's PetscOptionsStringToBool reads it */
    if (!strcasecmp(argv[k], "-skip_petscrc")) {
      const char *v = k + 1 < argc ? argv[k + 1] : "";
      skip = !v[0] || v[0] == '-' || !strcasecmp(v, "true") || !strcasecmp(v, "yes") || !strcasecmp(v, "on") ||
             !strcmp(v, "1");
    }
  if (skip) return 0;
  snprintf(path[0], sizeof path[0], "%s/.petscrc", home ? home : "");
  snprintf(path[1], sizeof path[1], ".petscrc");
  snprintf(path[2], sizeof path[2], "petscrc");
  for (int k = home && home[0] ? 0 : 1; k < 3; k++) {
    struct stat st;
    char       *tok[2] = {"-options_file", path[k]};
    if (stat(path[k], &st) || !S_ISREG(st.st_mode) || access(path[k], R_OK)) continue;
    if (FileOptionProblem(2, tok, " (PETSc's own start-up file, read at every start; -skip_petscrc leaves it out)", 0)) return 1;
  }
  return 0;
}

/* ... on the command line, in PETSc's own option files and in PETSC_OPTIONS and PETSC_OPTIONS_YAML */
static int InitFileProblem(int argc, char **argv)
{
  const char *env = getenv("PETSC_OPTIONS");
  char       *copy, *tok[1024];
  int         n = 0, bad;

  option_source = 3;
  if (FileOptionProblem(argc - 1, argv + 1, "", 0)) return 1;
  option_source = 0;
  if (RcFileProblem(argc, argv)) return 1;
  option_source = 2;
  { /* PETSc refuses malformed YAML there with a traceback; its -history, -info, ... are looked at as the command
       line's */
    const char *yaml = getenv("PETSC_OPTIONS_YAML");
    char        why[512] = "", **opts = NULL;
    int         nopts = 0;
    if (yaml && YamlOptionsProblem(yaml, why, sizeof why, &opts, &nopts)) {
      fprintf(stderr, "fabric: error: PETSC_OPTIONS_YAML: not valid YAML options: %s\n", why);
      return 1;
    }
    bad = FileOptionProblem(nopts, opts, " (in PETSC_OPTIONS_YAML)", 0);
    OptionFileFree(opts, nopts);
    if (bad) return 1;
  }
  option_source = 1;
  if (env && (copy = strdup(env))) {
    for (char *t = strtok(copy, " \t\n"); t && n < 1024; t = strtok(NULL, " \t\n")) tok[n++] = t;
    bad = FileOptionProblem(n, tok, " (in PETSC_OPTIONS)", 0);
    free(copy);
    if (bad) return 1;
  }
  return scene_named.file[0] ? SceneIncludeProblem(scene_named.file, scene_named.where) : 0;
}

int main(int argc, char **argv)
{
  PetscErrorCode ierr;

  /* MPI before PETSc: the option files are looked at first, and an MPI call that fails (an MPI
     that cannot run the -sf_type asked for, say) returns its error to PETSc, which then stops
     the run with one line, instead of MPI aborting it with no word of which option caused it */
#if defined(OPEN_MPI)
  /* Open MPI 4.1's shared-file-pointer component "lockedfile" writes the name of the file being
     opened into a fixed buffer: a long -output_dir or -restart path (251 characters did)
     overflows it and aborts the run inside MPI_File_open (open-mpi/ompi#13565). The solver never
     uses shared file pointers: leave that component out, unless the user chose the components. */
  setenv("OMPI_MCA_sharedfp", "^lockedfile", 0);
#endif
  if (MPI_Init(&argc, &argv) != MPI_SUCCESS) return 1;
  /* PetscInitialize prints the help with its signal handler on: a reader that has read enough (fabric -help | head)
     would get "Caught signal number 13 Broken Pipe" and an MPI_ABORT. A help run has nothing else to catch. */
  int help_run = 0;
  for (int k = 1; k < argc; k++) { /* the usual spellings of PETSc's -help: "unknown option --help" helped no one */
    static char help_option[] = "-help";
    if (!strcmp(argv[k], "--help") || !strcmp(argv[k], "-h")) argv[k] = help_option;
    help_run = help_run || !strcasecmp(argv[k], "-help");
  }
  /* a word -help in PETSC_OPTIONS too, read as PETSc reads it: words between spaces, a word in double quotes to the
     closing quote (a quoted "-help" is -help, a value "/a -help b" is not) */
  for (const char *at = getenv("PETSC_OPTIONS"); at && *at && !help_run;) {
    const char *word, *end;
    while (*at == ' ') at++;
    if (!*at) break;
    if (*at == '"') {
      word = ++at;
      end  = strchr(at, '"');
      if (!end) end = at + strlen(at);
      at = *end ? end + 1 : end;
    } else {
      word = at;
      end = at = at + strcspn(at, " ");
    }
    help_run = end - word == 5 && !strncasecmp(word, "-help", 5);
  }
  if (help_run && PetscOptionsSetValue(NULL, "-no_signal_handler", NULL)) return 1;
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_set_errhandler(MPI_COMM_SELF, MPI_ERRORS_RETURN);
  MPI_Comm_dup(MPI_COMM_WORLD, &stop_comm);
  {
    int rank = 0, bad = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (!rank) bad = InitFileProblem(argc, argv);
    MPI_Bcast(&bad, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (bad) {
      MPI_Comm_free(&stop_comm);
      MPI_Finalize();
      return 1;
    }
  }
  /* an error within PetscInitialize (an option file's content) gets PETSc's own message; rank 0
     reads an option file alone while the others wait for it, so every rank stops */
  if (PetscInitialize(&argc, &argv, NULL, help)) MPI_Abort(MPI_COMM_WORLD, 1);
  /* a reader that has read enough (fabric ... | head): end quietly, as any Unix tool does, not with PETSc's "Caught
     signal number 13 Broken Pipe" and an MPI_ABORT */
  signal(SIGPIPE, SIG_DFL);
  PetscCall(PetscPushErrorHandler(OneLineErrorHandler, NULL));
  ierr = Run(argc, argv);
  if (ierr) {
    StopTogether();
    /* no profile or report of a failed run (a scene's -memory_view, refused, would stop PetscFinalize too: the
       memory was never measured) */
    static const char *const report[] = {"-log_view",    "-log_all",        "-log_summary", "-memory_view",
                                         "-malloc_view", "-malloc_dump",    "-malloc_info", "-objects_dump",
                                         "-options_view", "-get_total_flops", "-options_left"};
    for (size_t k = 0; k < sizeof report / sizeof report[0]; k++) PetscCall(PetscOptionsClearValue(NULL, report[k]));
  }
  PetscCall(PetscPopErrorHandler());
  { /* PetscFinalize gives SIGTERM back its default action: a SIGTERM then (a batch system's limit as the run
       ends) would kill a rank whose run is done, and mpiexec would say it failed. The stop signals wait
       across it and come to the handler again, which only sets a flag, which nothing reads any more. */
    sigset_t stop, was;
    sigemptyset(&stop);
    sigaddset(&stop, SIGTERM);
    sigaddset(&stop, SIGUSR1);
    if (stop_signals_caught) sigprocmask(SIG_BLOCK, &stop, &was);
    PetscCall(PetscFinalize());
    if (stop_signals_caught) {
      signal(SIGTERM, CheckpointSignal);
      sigprocmask(SIG_SETMASK, &was, NULL);
    }
  }
  MPI_Comm_free(&stop_comm);
  MPI_Finalize();
  return ierr ? 1 : CheckpointStopped() ? CHECKPOINT_STOPPED : 0;
}
