/* main.c - fabric: the woven-fabric crossing-point solver.
 *
 *   mpiexec -n P build/fabric -scene inputs/strip_warp.yaml -output_dir DIR [options]
 *
 * Phases: options and scene -> build the fabric -> run the load program -> report.
 */
#include "fabric.h"

static const char help[] = "fabric: woven-fabric mechanics at the yarn-crossing scale (explicit, MPI-parallel).\n"
                           "  mpiexec -n P fabric -scene inputs/strip_warp.yaml [-output_dir DIR] [options]\n"
                           "Any scene key can be overridden on the command line. Units are in the option names.\n\n";

/* One clear line per error on the rank that reports it (rank 0 for collective errors). */
static PetscErrorCode OneLineErrorHandler(MPI_Comm comm, int line, const char *fun, const char *file, PetscErrorCode n, PetscErrorType p, const char *mess, void *ctx)
{
  PetscMPIInt rank = 0;
  (void)line;
  (void)fun;
  (void)file;
  (void)ctx;
  if (p != PETSC_ERROR_INITIAL) return n;
  if (comm != MPI_COMM_NULL) MPI_Comm_rank(comm, &rank);
  if (rank == 0) {
    if (mess && mess[0]) fprintf(stderr, "fabric: error: %s\n", mess);
    else {
      const char *text = NULL;
      PetscErrorMessage(n, &text, NULL);
      fprintf(stderr, "fabric: error: %s (in %s, %s:%d)\n", text ? text : "unknown", fun, file, line);
    }
    fflush(stderr);
  }
  return n;
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
    PetscCall(FabricDestroy(&fab));
    PetscFunctionReturn(0);
  }
  PetscCall(SceneCheckUnused(PETSC_COMM_WORLD));
  if (!fab->s.quiet)
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fabric: scene %s, %" PetscInt_FMT " x %" PetscInt_FMT " crossings (%" PetscInt_FMT " points) on %d ranks, %s integrator, prediction %s, %" PetscInt_FMT " load steps to %.3g %% elongation\n", fab->s.name, fab->s.nx, fab->s.ny, fab->points, fab->size,
                          IntegratorNames[fab->s.integrator], PredictNames[fab->s.predict], fab->s.load_steps, (double)(100 * fab->s.elongation)));
  ierr = FabricRun(fab);
  if (ierr) { /* a run that stops on an error still says so in summary.json */
    const char *text;
    char       *specific = NULL;
    PetscErrorMessage(ierr, &text, &specific);
    OutputSummary(fab, specific && specific[0] ? specific : text);
    FabricDestroy(&fab);
    return ierr;
  }
  if (fab->s.output_dir[0]) {
    PetscReal peak = 0;
    for (PetscInt k = 0; k < fab->s.load_steps; k++) peak = PetscMax(peak, fab->curve[k].force);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fabric: done in %.2f s: %" PetscInt64_FMT " te steps, %.3e point updates/s; peak force %.4g N at %.3g %% elongation; %s\n", (double)fab->wall, fab->te_steps, fab->wall > 0 ? (double)fab->point_updates / fab->wall : 0.0, (double)peak,
                          (double)(100 * fab->curve[fab->s.load_steps - 1].elongation), fab->converged ? "every load step balanced" : "some load steps did NOT balance (see curve.csv residual)"));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fabric: results in %s/ (curve.csv, summary.json)\n", fab->s.output_dir));
  }
  PetscCall(FabricDestroy(&fab));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  PetscErrorCode ierr;

  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  PetscCall(PetscPushErrorHandler(OneLineErrorHandler, NULL));
  ierr = Run(argc, argv);
  PetscCall(PetscPopErrorHandler());
  PetscCall(PetscFinalize());
  return ierr ? 1 : 0;
}
