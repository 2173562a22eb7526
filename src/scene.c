/* scene.c - the scene: every parameter from the PETSc options database.
 *
 * A scene file is a YAML option file (-scene inputs/X.yaml); the command line
 * overrides it. Textile units at the edges (tex, threads/cm, %, cN/tex, mm),
 * converted here, once, to SI. -help lists every option with unit and default.
 */
#include "fabric.h"

#include <math.h>
#include <string.h>

const char *const PullAxisNames[]   = {"warp", "weft", "PullAxis", "PULL_", NULL};
const char *const IntegratorNames[] = {"damped", "paper", "IntegratorType", "INTEGRATOR_", NULL};
const char *const PredictNames[]    = {"none", "linear", "extrapolate", "PredictType", "PREDICT_", NULL};

#define CHECK_POSITIVE(v, opt) PetscCheck(isfinite((double)(v)) && (v) > 0, comm, PETSC_ERR_USER_INPUT, "%s must be a positive number, got %g", opt, (double)(v))
#define CHECK_NONNEG(v, opt)   PetscCheck(isfinite((double)(v)) && (v) >= 0, comm, PETSC_ERR_USER_INPUT, "%s must be zero or positive, got %g", opt, (double)(v))

static PetscErrorCode YarnOptions(MPI_Comm comm, PetscOptionItems *PetscOptionsObject, YarnLaw *y, const char *name, PetscReal crimp_pct)
{
  char      opt[64], help[256];
  PetscReal modulus = 260.0, ratio = 0.05, brk = 0.0;

  PetscFunctionBeginUser;
  y->name = name;
  y->tex  = 20.0;
  y->k_comp = 1e-3;
  y->bending = 2e-9;
#define YOPT(suffix) (PetscSNPrintf(opt, sizeof opt, "-%s_" suffix, name), opt)
#define YHELP(text)  (PetscSNPrintf(help, sizeof help, "%s yarn: " text, name), help)
  PetscCall(PetscOptionsReal(YOPT("tex"), YHELP("linear density, tex (g/km)"), NULL, y->tex, &y->tex, NULL));
  CHECK_POSITIVE(y->tex, opt);
  PetscCall(PetscOptionsReal(YOPT("crimp_pct"), YHELP("crimp: extra yarn length between crossings (%%)"), NULL, crimp_pct, &crimp_pct, NULL));
  PetscCheck(isfinite(crimp_pct) && crimp_pct >= 0 && crimp_pct < 100, comm, PETSC_ERR_USER_INPUT, "%s must be in [0,100), got %g", opt, (double)crimp_pct);
  y->crimp = crimp_pct / 100.0;
  PetscCall(PetscOptionsReal(YOPT("modulus_cN_tex"), YHELP("yarn modulus of the linear law (cN/tex): EA = modulus * tex"), NULL, modulus, &modulus, NULL));
  CHECK_POSITIVE(modulus, opt);
  y->EA = modulus * 1e-2 * y->tex;
  PetscCall(PetscOptionsReal(YOPT("decrimp_ratio"), YHELP("de-crimping stiffness Ec as a fraction of EA"), NULL, ratio, &ratio, NULL));
  CHECK_NONNEG(ratio, opt);
  PetscCall(PetscOptionsReal(YOPT("compression_ratio"), YHELP("compression stiffness as a fraction of EA (yarns buckle)"), NULL, y->k_comp, &y->k_comp, NULL));
  CHECK_NONNEG(y->k_comp, opt);
  {
    PetscReal contact = 50;
    PetscCall(PetscOptionsReal(YOPT("contact_pct"), YHELP("chord compression at which neighbouring crossings touch (%%): below it the chord is as stiff as the yarn"), NULL, contact, &contact, NULL));
    PetscCheck(isfinite(contact) && contact > 0 && contact < 100, comm, PETSC_ERR_USER_INPUT, "%s must be in (0,100), got %g", opt, (double)contact);
    y->e_contact = -contact / 100.0;
  }
  {
    PetscReal smooth = 0;
    PetscCall(PetscOptionsReal(YOPT("law_smoothing_pct"), YHELP("half-width of the C1 blend at each kink of the tension law (%% chord strain); 0 = sharp kinks"), NULL, smooth, &smooth, NULL));
    PetscCheck(isfinite(smooth) && smooth >= 0 && smooth < 5, comm, PETSC_ERR_USER_INPUT, "%s must be in [0,5), got %g", opt, (double)smooth);
    y->smoothing = smooth / 100.0;
  }
  PetscCall(PetscOptionsReal(YOPT("bending_Nm2"), YHELP("bending rigidity B per yarn (N m^2)"), NULL, y->bending, &y->bending, NULL));
  CHECK_NONNEG(y->bending, opt);
  PetscCall(PetscOptionsReal(YOPT("break_pct"), YHELP("yarn breaking strain (%%), 0 = never breaks"), NULL, brk, &brk, NULL));
  CHECK_NONNEG(brk, opt);
  y->break_ey = brk / 100.0;
  y->csv[0]   = 0;
  PetscCall(PetscOptionsString(YOPT("law_csv"), YHELP("tabulated yarn law, CSV 'strain_pct,force_cN' (empty = linear EA)"), NULL, y->csv, y->csv, sizeof y->csv, NULL));
  PetscCall(YarnLawSetUp(y, comm));
  y->Ec = ratio * (y->ntab ? y->EA : modulus * 1e-2 * y->tex);
#undef YOPT
#undef YHELP
  PetscFunctionReturn(0);
}

/* -scene FILE: insert the YAML option file, then the command line again so that it wins */
PetscErrorCode SceneInsertFile(MPI_Comm comm, int argc, char **argv)
{
  char           file[PETSC_MAX_PATH_LEN];
  PetscBool      set, exists;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", file, sizeof file, &set));
  if (!set) PetscFunctionReturn(0);
  PetscCheck(file[0], comm, PETSC_ERR_USER_INPUT, "-scene needs a file name");
  PetscCall(PetscTestFile(file, 'r', &exists));
  PetscCheck(exists, comm, PETSC_ERR_FILE_OPEN, "-scene %s: no such file, or not readable", file);
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = PetscOptionsInsertFileYAML(comm, NULL, file, PETSC_TRUE);
  PetscCall(PetscPopErrorHandler());
  if (ierr) {
    const char *text;
    char       *specific = NULL;
    PetscCall(PetscErrorMessage(ierr, &text, &specific));
    SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED, "-scene %s: not a valid YAML option file: %s", file, specific && specific[0] ? specific : text);
  }
  PetscCall(PetscOptionsInsertArgs(NULL, argc - 1, argv + 1));
  PetscFunctionReturn(0);
}

/* A misspelt option would otherwise be ignored silently: refuse it. */
PetscErrorCode SceneCheckUnused(MPI_Comm comm)
{
  PetscInt n;
  char   **names, **values;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsLeftGet(NULL, &n, &names, &values));
  if (n > 0) {
    char name[256];
    PetscCall(PetscStrncpy(name, names[0], sizeof name));
    PetscCall(PetscOptionsLeftRestore(NULL, &n, &names, &values));
    SETERRQ(comm, PETSC_ERR_USER_INPUT, "unknown option -%s (run with -help for the list)", name);
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &n, &names, &values));
  PetscFunctionReturn(0);
}

PetscErrorCode SceneLoad(MPI_Comm comm, Scene *s)
{
  PetscReal ends_cm = 24, picks_cm = 24, gauge_mm = 200, width_mm = 50, elong_pct = 13, speed_mm_min = 100;
  PetscInt  n3 = 3, n2 = 2;
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(s, sizeof *s));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", s->file, sizeof s->file, NULL));
  {
    const char *base = strrchr(s->file, '/');
    base             = base ? base + 1 : s->file;
    PetscCall(PetscStrncpy(s->name, base[0] ? base : "default", sizeof s->name));
    char *dot = strrchr(s->name, '.');
    if (dot && dot != s->name) *dot = 0;
  }

  PetscOptionsBegin(comm, NULL, "Specimen: ISO 13934-1 strip between a clamped and a moving jaw", NULL);
  PetscCall(PetscOptionsString("-scene", "scene file (YAML options); the command line overrides it", NULL, s->file, s->file, sizeof s->file, NULL));
  PetscCall(PetscOptionsReal("-ends_per_cm", "warp density (ends/cm): warp yarns run along x, spaced along y", NULL, ends_cm, &ends_cm, NULL));
  CHECK_POSITIVE(ends_cm, "-ends_per_cm");
  PetscCall(PetscOptionsReal("-picks_per_cm", "weft density (picks/cm): weft yarns run along y, spaced along x", NULL, picks_cm, &picks_cm, NULL));
  CHECK_POSITIVE(picks_cm, "-picks_per_cm");
  PetscCall(PetscOptionsReal("-gauge_mm", "gauge length between the jaws (mm)", NULL, gauge_mm, &gauge_mm, NULL));
  CHECK_POSITIVE(gauge_mm, "-gauge_mm");
  PetscCall(PetscOptionsReal("-width_mm", "strip width (mm)", NULL, width_mm, &width_mm, NULL));
  CHECK_POSITIVE(width_mm, "-width_mm");
  PetscCall(PetscOptionsInt("-yarns", "yarns across the strip (0 = width * density)", NULL, s->yarns, &s->yarns, NULL));
  PetscCheck(s->yarns >= 0, comm, PETSC_ERR_USER_INPUT, "-yarns must be zero or positive, got %" PetscInt_FMT, s->yarns);
  s->pull = PULL_WARP;
  PetscCall(PetscOptionsEnum("-pull", "yarn family pulled by the jaws", NULL, PullAxisNames, (PetscEnum)s->pull, (PetscEnum *)&s->pull, NULL));
  PetscOptionsEnd();

  PetscOptionsBegin(comm, NULL, "Yarns (warp along x, weft along y)", NULL);
  PetscCall(YarnOptions(comm, PetscOptionsObject, &s->warp, "warp", 8.0));
  PetscCall(YarnOptions(comm, PetscOptionsObject, &s->weft, "weft", 5.0));
  PetscOptionsEnd();

  PetscOptionsBegin(comm, NULL, "Fabric terms (each can be switched off)", NULL);
  s->traction = s->bending = s->shear = PETSC_TRUE;
  PetscCall(PetscOptionsBool("-traction", "yarn traction (MODEL.md 5.1)", NULL, s->traction, &s->traction, NULL));
  PetscCall(PetscOptionsBool("-bending", "yarn bending along both families (MODEL.md 5.2)", NULL, s->bending, &s->bending, NULL));
  PetscCall(PetscOptionsBool("-shear", "in-plane shear with jamming (MODEL.md 5.3)", NULL, s->shear, &s->shear, NULL));
  s->shear_G    = 50.0;
  s->lock_deg   = 35.0;
  s->jam_factor = 100.0;
  PetscCall(PetscOptionsReal("-shear_G_N_m", "in-plane shear rigidity G (N/m per radian)", NULL, s->shear_G, &s->shear_G, NULL));
  CHECK_NONNEG(s->shear_G, "-shear_G_N_m");
  PetscCall(PetscOptionsReal("-shear_lock_deg", "jamming (locking) shear angle (degrees)", NULL, s->lock_deg, &s->lock_deg, NULL));
  PetscCheck(isfinite(s->lock_deg) && s->lock_deg > 0 && s->lock_deg < 90, comm, PETSC_ERR_USER_INPUT, "-shear_lock_deg must be in (0,90), got %g", (double)s->lock_deg);
  PetscCall(PetscOptionsReal("-jam_factor", "jamming stiffness as a multiple of the shear stiffness (0 = no jamming)", NULL, s->jam_factor, &s->jam_factor, NULL));
  CHECK_NONNEG(s->jam_factor, "-jam_factor");
  s->gravity[2] = -9.81;
  PetscCall(PetscOptionsRealArray("-gravity", "gravity vector gx,gy,gz (m/s^2); 0,0,0 = off", NULL, s->gravity, &n3, &set));
  PetscCheck(!set || n3 == 3, comm, PETSC_ERR_USER_INPUT, "-gravity needs three components gx,gy,gz, got %" PetscInt_FMT, n3);
  for (int d = 0; d < 3; d++) PetscCheck(isfinite(s->gravity[d]), comm, PETSC_ERR_USER_INPUT, "-gravity component %d is not a finite number", d);
  PetscCall(PetscOptionsReal("-nu", "air viscosity per point (N s/m), the paper's coefficient", NULL, s->nu, &s->nu, NULL));
  CHECK_NONNEG(s->nu, "-nu");
  s->damping_ratio = 1.0;
  PetscCall(PetscOptionsReal("-damping_ratio", "mass-proportional damping as a fraction of critical for the slowest mode along the pull (0 = off)", NULL, s->damping_ratio, &s->damping_ratio, NULL));
  CHECK_NONNEG(s->damping_ratio, "-damping_ratio");
  PetscOptionsEnd();

  PetscOptionsBegin(comm, NULL, "Load program", NULL);
  PetscCall(PetscOptionsReal("-elongation_pct", "final elongation: grip travel / gauge length (%)", NULL, elong_pct, &elong_pct, NULL));
  PetscCheck(isfinite(elong_pct) && elong_pct >= 0 && elong_pct <= 100, comm, PETSC_ERR_USER_INPUT, "-elongation_pct must be in [0,100], got %g", (double)elong_pct);
  PetscCall(PetscOptionsReal("-speed_mm_min", "test speed of the moving jaw (mm/min); gives time_s", NULL, speed_mm_min, &speed_mm_min, NULL));
  CHECK_POSITIVE(speed_mm_min, "-speed_mm_min");
  PetscCall(PetscOptionsRealArray("-point_load_N", "final point load fx,fy,fz (N), ramped with the load steps", NULL, s->point_load, &n3, &set));
  PetscCheck(!set || n3 == 3, comm, PETSC_ERR_USER_INPUT, "-point_load_N needs three components fx,fy,fz, got %" PetscInt_FMT, n3);
  s->load_at[0] = s->load_at[1] = -1;
  n2 = 2;
  PetscCall(PetscOptionsIntArray("-point_load_at", "crossing i,j of the point load (default: the centre)", NULL, s->load_at, &n2, &set));
  PetscCheck(!set || n2 == 2, comm, PETSC_ERR_USER_INPUT, "-point_load_at needs two indices i,j, got %" PetscInt_FMT, n2);
  s->load_steps      = 50;
  s->max_inner_steps = 20000;
  PetscCall(PetscOptionsInt("-load_steps", "number of load steps K", NULL, s->load_steps, &s->load_steps, NULL));
  PetscCheck(s->load_steps >= 1, comm, PETSC_ERR_USER_INPUT, "-load_steps must be at least 1, got %" PetscInt_FMT, s->load_steps);
  PetscCall(PetscOptionsInt("-max_inner_steps", "te steps per load step N (the most if it balances earlier)", NULL, s->max_inner_steps, &s->max_inner_steps, NULL));
  PetscCheck(s->max_inner_steps >= 1, comm, PETSC_ERR_USER_INPUT, "-max_inner_steps must be at least 1, got %" PetscInt_FMT, s->max_inner_steps);
  PetscOptionsEnd();

  PetscOptionsBegin(comm, NULL, "Numerics", NULL);
  s->integrator = INTEGRATOR_DAMPED;
  PetscCall(PetscOptionsEnum("-integrator", "damped: damped central differences; paper: the paper's eq. (10)", NULL, IntegratorNames, (PetscEnum)s->integrator, (PetscEnum *)&s->integrator, NULL));
  PetscCall(PetscOptionsReal("-te", "time step te (s); 0 = from the stable bound", NULL, s->te_user, &s->te_user, NULL));
  CHECK_NONNEG(s->te_user, "-te");
  s->te_safety = 0.9;
  PetscCall(PetscOptionsReal("-te_safety", "te = safety * stable bound (Gershgorin)", NULL, s->te_safety, &s->te_safety, NULL));
  PetscCheck(isfinite(s->te_safety) && s->te_safety > 0 && s->te_safety <= 1, comm, PETSC_ERR_USER_INPUT, "-te_safety must be in (0,1], got %g", (double)s->te_safety);
  s->te_check = PETSC_TRUE;
  PetscCall(PetscOptionsBool("-te_check", "refuse a -te above the stable bound (0: experts and stability tests only)", NULL, s->te_check, &s->te_check, NULL));
  s->te_window = 1.0;
  PetscCall(PetscOptionsReal("-te_strain_window", "chord-strain margin around each segment's strain over which the yarn tangent is maximised for the bound (smaller: larger te while yarns are crimped, but a load step that straightens them further can go unstable)", NULL, s->te_window, &s->te_window, NULL));
  CHECK_NONNEG(s->te_window, "-te_strain_window");
  s->early_exit = PETSC_TRUE;
  PetscCall(PetscOptionsBool("-early_exit", "end a load step as soon as the balance test passes (modified multi-sampling)", NULL, s->early_exit, &s->early_exit, NULL));
  s->balance_tol = 1e-3;
  PetscCall(PetscOptionsReal("-balance_tol", "balance: max residual force on a free point / largest yarn tension", NULL, s->balance_tol, &s->balance_tol, NULL));
  CHECK_POSITIVE(s->balance_tol, "-balance_tol");
  PetscCall(PetscOptionsReal("-speed_tol", "balance: max speed of a free point (m/s); 0 = the test speed", NULL, s->speed_tol, &s->speed_tol, NULL));
  CHECK_NONNEG(s->speed_tol, "-speed_tol");
  s->predict = PREDICT_LINEAR;
  PetscCall(PetscOptionsEnum("-predict", "displacement prediction at each load step", NULL, PredictNames, (PetscEnum)s->predict, (PetscEnum *)&s->predict, NULL));
  s->grip_ramp = -1;
  PetscCall(PetscOptionsInt("-grip_ramp_steps", "te steps over which the jaw moves to each load step's position (cosine ramp); -1 = half a period of the slowest mode without prediction, 0 (a jump) with it", NULL, s->grip_ramp, &s->grip_ramp, NULL));
  PetscCheck(s->grip_ramp >= -1, comm, PETSC_ERR_USER_INPUT, "-grip_ramp_steps must be -1 (auto) or >= 0, got %" PetscInt_FMT, s->grip_ramp);
  PetscCall(PetscOptionsBool("-front", "rank propagation: compute only the points a load change can have reached", NULL, s->front, &s->front, NULL));
  PetscCall(PetscOptionsReal("-sleep_tol", "sleeping: skip points whose residual (relative, like -balance_tol) and speed stay below this, with asleep neighbours; 0 = off", NULL, s->sleep_tol, &s->sleep_tol, NULL));
  CHECK_NONNEG(s->sleep_tol, "-sleep_tol");
  PetscCheck(s->sleep_tol <= s->balance_tol, comm, PETSC_ERR_USER_INPUT, "-sleep_tol %g is above -balance_tol %g: points would sleep before they balance", (double)s->sleep_tol, (double)s->balance_tol);
  PetscOptionsEnd();

  PetscOptionsBegin(comm, NULL, "Output", NULL);
  PetscCall(PetscSNPrintf(s->output_dir, sizeof s->output_dir, "results/%s", s->name));
  PetscCall(PetscOptionsString("-output_dir", "directory for curve.csv and summary.json (\"none\": write nothing)", NULL, s->output_dir, s->output_dir, sizeof s->output_dir, NULL));
  if (!strcmp(s->output_dir, "none")) s->output_dir[0] = 0;
  PetscCall(PetscOptionsString("-positions_out", "write the final positions (natural order, PETSc binary) to this file", NULL, s->positions_out, s->positions_out, sizeof s->positions_out, NULL));
  PetscCall(PetscOptionsBool("-quiet", "no progress line per load step", NULL, s->quiet, &s->quiet, NULL));
  PetscOptionsEnd();

  /* derived: SI, grid */
  s->ends_per_m  = ends_cm * 100.0;
  s->picks_per_m = picks_cm * 100.0;
  s->elongation  = elong_pct / 100.0;
  s->speed       = speed_mm_min * 1e-3 / 60.0;
  if (s->speed_tol == 0) s->speed_tol = s->speed;
  {
    const PetscReal along_density = s->pull == PULL_WARP ? s->picks_per_m : s->ends_per_m;
    const PetscReal across_density = s->pull == PULL_WARP ? s->ends_per_m : s->picks_per_m;
    const PetscReal n_along = round(gauge_mm * 1e-3 * along_density) + 1;
    const PetscReal n_across = s->yarns ? (PetscReal)s->yarns : round(width_mm * 1e-3 * across_density);
    PetscCheck(n_along >= 3, comm, PETSC_ERR_USER_INPUT, "grid too small: -gauge_mm %g at %g threads/cm gives %g crossings along the pull, at least 3 are needed", (double)gauge_mm, (double)(along_density / 100), (double)n_along);
    PetscCheck(n_across >= 1, comm, PETSC_ERR_USER_INPUT, "grid too small: -width_mm %g at %g threads/cm gives no yarn across the strip", (double)width_mm, (double)(across_density / 100));
    PetscCheck(n_along * n_across < 2.0e9, comm, PETSC_ERR_USER_INPUT, "grid too large: %g x %g crossings", (double)n_along, (double)n_across);
    s->nx    = (PetscInt)(s->pull == PULL_WARP ? n_along : n_across);
    s->ny    = (PetscInt)(s->pull == PULL_WARP ? n_across : n_along);
    s->gauge = (n_along - 1) / along_density;
    s->width = n_across / across_density;
  }
  if (s->load_at[0] < 0) {
    s->load_at[0] = s->nx / 2;
    s->load_at[1] = s->ny / 2;
  }
  PetscCheck(s->load_at[0] < s->nx && s->load_at[1] >= 0 && s->load_at[1] < s->ny, comm, PETSC_ERR_USER_INPUT, "-point_load_at %" PetscInt_FMT ",%" PetscInt_FMT " is outside the %" PetscInt_FMT " x %" PetscInt_FMT " grid", s->load_at[0], s->load_at[1], s->nx, s->ny);
  PetscFunctionReturn(0);
}

PetscErrorCode SceneDestroy(Scene *s)
{
  PetscFunctionBeginUser;
  PetscCall(YarnLawDestroy(&s->warp));
  PetscCall(YarnLawDestroy(&s->weft));
  PetscFunctionReturn(0);
}
