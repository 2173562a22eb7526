/* scene.c - the scene: every parameter from the PETSc options database.
 *
 * A scene file is a YAML option file (-scene inputs/X.yaml); the command line
 * overrides it. Textile units at the edges (tex, threads/cm, %, cN/tex, mm),
 * converted here, once, to SI. -help lists every option with unit and default.
 */
#include "scene.h"

#include <math.h>
#include <string.h>

const char *const PullAxisNames[]   = {"warp", "weft", "PullAxis", "PULL_", NULL};
const char *const IntegratorNames[] = {"damped", "paper", "IntegratorType", "INTEGRATOR_", NULL};
const char *const PredictNames[]    = {"none", "linear", "extrapolate", "PredictType", "PREDICT_", NULL};
const char *const TestNames[]       = {"strip", "square", "pushing", "bias", "drape", "TestType", "TEST_", NULL};
const char *const ShapeNames[]      = {"rectangle", "disc", "bias", "ShapeType", "SHAPE_", NULL};
const char *const ClampNames[]      = {"jaw", "edge", "ring", "none", "ClampType", "CLAMP_", NULL};

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

/* -clamp_line_mm / -grip_line_mm x,y,angle_deg,half_width_mm[,x,y,...]: up to MAX_LINES lines, in SI */
static PetscErrorCode LineOptions(MPI_Comm comm, PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, PetscInt *nlines, PetscReal line[][4])
{
  PetscReal v[4 * MAX_LINES + 1];
  PetscInt  n = 4 * MAX_LINES + 1;
  PetscBool set;

  PetscFunctionBeginUser;
  *nlines = 0;
  PetscCall(PetscOptionsRealArray(opt, help, NULL, v, &n, &set));
  if (!set) PetscFunctionReturn(0);
  PetscCheck(n > 0 && n % 4 == 0 && n <= 4 * MAX_LINES, comm, PETSC_ERR_USER_INPUT, "%s needs x,y,angle_deg,half_width_mm for each line (4 numbers per line, 1 to %d lines), got %" PetscInt_FMT " numbers", opt, MAX_LINES, n);
  for (PetscInt k = 0; k < n / 4; k++) {
    const PetscReal *l = v + 4 * k;
    PetscCheck(isfinite(l[0]) && isfinite(l[1]) && isfinite(l[2]), comm, PETSC_ERR_USER_INPUT, "%s line %" PetscInt_FMT ": x, y and the angle must be finite numbers, got %g,%g,%g", opt, k + 1, (double)l[0], (double)l[1], (double)l[2]);
    PetscCheck(isfinite(l[3]) && l[3] > 0, comm, PETSC_ERR_USER_INPUT, "%s line %" PetscInt_FMT ": the half-width must be a positive number of mm, got %g", opt, k + 1, (double)l[3]);
    line[k][0] = 1e-3 * l[0];
    line[k][1] = 1e-3 * l[1];
    line[k][2] = l[2] * PETSC_PI / 180.0;
    line[k][3] = 1e-3 * l[3];
  }
  *nlines = n / 4;
  PetscFunctionReturn(0);
}

/* -grip_path_mm dx,dy,dz[,dx,dy,dz...]: the grip's waypoints (mm) after the start (0,0,0), in
   SI, with the length along the path to each */
static PetscErrorCode PathOptions(MPI_Comm comm, PetscOptionItems *PetscOptionsObject, Scene *s)
{
  PetscReal v[3 * MAX_WAYPOINTS + 1], at = 0;
  PetscInt  n = 3 * MAX_WAYPOINTS + 1;
  PetscBool set;

  PetscFunctionBeginUser;
  s->load.waypoints = 0;
  PetscCall(PetscOptionsRealArray("-grip_path_mm", "the grip's path, replacing the straight pull of -elongation_pct: waypoints dx,dy,dz (mm, displacements from the grip's rest position, x along the warp, y along the weft) joined by straight lines from 0,0,0 and travelled at the test speed; the load steps divide its length equally; curve.csv's elongation is the displacement along the pull / gauge, force_N the reaction along the pull", NULL, v, &n, &set));
  if (!set) PetscFunctionReturn(0);
  PetscCheck(n > 0 && n % 3 == 0 && n <= 3 * MAX_WAYPOINTS, comm, PETSC_ERR_USER_INPUT, "-grip_path_mm needs dx,dy,dz for each waypoint (3 numbers per waypoint, 1 to %d waypoints), got %" PetscInt_FMT " numbers", MAX_WAYPOINTS, n);
  for (PetscInt k = 0; k < n / 3; k++) {
    PetscReal len2 = 0;
    for (int d = 0; d < 3; d++) {
      PetscCheck(isfinite(v[3 * k + d]), comm, PETSC_ERR_USER_INPUT, "-grip_path_mm waypoint %" PetscInt_FMT ": not a finite displacement", k + 1);
      s->load.waypoint[k][d] = 1e-3 * v[3 * k + d];
      len2 += PetscSqr(s->load.waypoint[k][d] - (k ? s->load.waypoint[k - 1][d] : 0.0));
    }
    PetscCheck(len2 > 0, comm, PETSC_ERR_USER_INPUT, "-grip_path_mm waypoint %" PetscInt_FMT " (%g,%g,%g mm) repeats the point before it: a path segment of zero length", k + 1, (double)v[3 * k], (double)v[3 * k + 1], (double)v[3 * k + 2]);
    at += PetscSqrtReal(len2);
    s->load.path_at[k] = at;
  }
  s->load.waypoints = n / 3;
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
  PetscReal disc_mm = 0, ring_mm[2] = {0, 0}, sphere_mm = 0, start_mm[3] = {0, 0, 0}, travel_mm = 0, thick_mm = 0.3, kc = 0;
  PetscBool start_set;
  PetscReal jaw_mm = 2;
  PetscInt  n3 = 3, n2 = 2;
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(s, sizeof *s));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", s->out.file, sizeof s->out.file, NULL));
  {
    const char *base = strrchr(s->out.file, '/');
    base             = base ? base + 1 : s->out.file;
    PetscCall(PetscStrncpy(s->out.name, base[0] ? base : "default", sizeof s->out.name));
    char *dot = strrchr(s->out.name, '.');
    if (dot && dot != s->out.name) *dot = 0;
  }

  PetscOptionsBegin(comm, NULL, "Specimen: ISO 13934-1 strip between a clamped and a moving jaw", NULL);
  PetscCall(PetscOptionsString("-scene", "scene file (YAML options); the command line overrides it", NULL, s->out.file, s->out.file, sizeof s->out.file, NULL));
  PetscCall(PetscOptionsReal("-ends_per_cm", "warp density (ends/cm): warp yarns run along x, spaced along y", NULL, ends_cm, &ends_cm, NULL));
  CHECK_POSITIVE(ends_cm, "-ends_per_cm");
  PetscCall(PetscOptionsReal("-picks_per_cm", "weft density (picks/cm): weft yarns run along y, spaced along x", NULL, picks_cm, &picks_cm, NULL));
  CHECK_POSITIVE(picks_cm, "-picks_per_cm");
  PetscCall(PetscOptionsReal("-gauge_mm", "gauge length between the jaws (mm)", NULL, gauge_mm, &gauge_mm, NULL));
  CHECK_POSITIVE(gauge_mm, "-gauge_mm");
  PetscCall(PetscOptionsReal("-width_mm", "strip width (mm)", NULL, width_mm, &width_mm, NULL));
  CHECK_POSITIVE(width_mm, "-width_mm");
  PetscCall(PetscOptionsInt("-yarns", "yarns across the strip (0 = width * density)", NULL, s->spec.yarns, &s->spec.yarns, NULL));
  PetscCheck(s->spec.yarns >= 0, comm, PETSC_ERR_USER_INPUT, "-yarns must be zero or positive, got %" PetscInt_FMT, s->spec.yarns);
  s->spec.pull = PULL_WARP;
  PetscCall(PetscOptionsEnum("-pull", "yarn family pulled by the jaws", NULL, PullAxisNames, (PetscEnum)s->spec.pull, (PetscEnum *)&s->spec.pull, NULL));
  PetscOptionsEnd();

  PetscOptionsBegin(comm, NULL, "Test, shape and clamps (strip: the jaws; square: a net of -gauge_mm x -width_mm clamped on its edges)", NULL);
  s->test = TEST_STRIP;
  PetscCall(PetscOptionsEnum("-test", "drape: Cusick drape, a disc specimen held between discs (-clamp_ring_mm 0,D) under gravity ramped with the load steps; strip: ISO 13934-1 strip between jaws; square: clamped net of gauge x width (mm) under the point load, no jaws; pushing: a rigid sphere pushed through the clamped fabric", NULL, TestNames, (PetscEnum)s->test, (PetscEnum *)&s->test, NULL));
  s->spec.shape = s->test == TEST_BIAS ? SHAPE_BIAS : (s->test == TEST_DRAPE ? SHAPE_DISC : SHAPE_RECTANGLE);
  if (s->test == TEST_DRAPE) gauge_mm = width_mm = 300, ring_mm[1] = 180; /* Cusick: 30 cm specimen held between 18 cm discs */
  PetscCall(PetscOptionsEnum("-shape", "specimen shape cut from the grid: rectangle (the whole grid), disc (centred) or bias (-gauge_mm x -width_mm between jaws, its length at 45 degrees to the yarns)", NULL, ShapeNames, (PetscEnum)s->spec.shape, (PetscEnum *)&s->spec.shape, NULL));
  PetscCall(PetscOptionsReal("-disc_diameter_mm", "disc specimen diameter (mm), centred on the grid; 0 = the smaller grid side", NULL, disc_mm, &disc_mm, NULL));
  CHECK_NONNEG(disc_mm, "-disc_diameter_mm");
  PetscCall(PetscOptionsReal("-jaw_depth_mm", "bias specimen: length held in each jaw beyond the gauge length (mm)", NULL, jaw_mm, &jaw_mm, NULL));
  CHECK_POSITIVE(jaw_mm, "-jaw_depth_mm");
  s->clamps.clamp = JawTest(s) ? CLAMP_JAW : (s->test == TEST_DRAPE ? CLAMP_RING : CLAMP_EDGE);
  PetscCall(PetscOptionsEnum("-clamp", "clamped crossings: jaw (the strip's or bias specimen's fixed jaw; the other end is the moving jaw), edge (every crossing of the shape's outline), ring (an annulus around the grid centre), none", NULL, ClampNames, (PetscEnum)s->clamps.clamp, (PetscEnum *)&s->clamps.clamp, NULL));
  {
    PetscInt  n = 2;
    PetscBool rset;
    PetscCall(PetscOptionsRealArray("-clamp_ring_mm", "inner,outer diameter of the clamping ring (mm), centred on the grid", NULL, ring_mm, &n, &rset));
    PetscCheck(!rset || n == 2, comm, PETSC_ERR_USER_INPUT, "-clamp_ring_mm needs two diameters inner,outer, got %" PetscInt_FMT, n);
    PetscCheck(s->clamps.clamp != CLAMP_RING || ((rset || s->test == TEST_DRAPE) && ring_mm[0] >= 0 && ring_mm[1] > ring_mm[0] && isfinite(ring_mm[1])), comm, PETSC_ERR_USER_INPUT, "-clamp ring needs -clamp_ring_mm inner,outer with 0 <= inner < outer, got %g,%g", (double)ring_mm[0], (double)ring_mm[1]);
  }
  PetscCall(LineOptions(comm, PetscOptionsObject, "-clamp_line_mm", "clamp lines across the grid, on top of -clamp: x,y,angle_deg,half_width_mm per line (a point from the grid centre in mm, the angle to the warp (x) axis, the band's half-width in mm); the existing crossings within the band never move", &s->clamps.clamp_lines, s->clamps.clamp_line));
  PetscCall(LineOptions(comm, PetscOptionsObject, "-grip_line_mm", "grip lines across the grid (strip and bias tests): x,y,angle_deg,half_width_mm per line, as -clamp_line_mm; the existing crossings within the band move with the grip", &s->clamps.grip_lines, s->clamps.grip_line));
  PetscOptionsEnd();

  PetscOptionsBegin(comm, NULL, "Rigid bodies with penalty contact (MODEL.md 5.5): a sphere (centre = grid centre + start + d * direction, d = 0 .. travel over the load steps), a plane, a pedestal; Coulomb friction", NULL);
  if (s->test == TEST_PUSHING) sphere_mm = 25.4, travel_mm = 20;
  PetscCall(PetscOptionsReal("-sphere_diameter_mm", "sphere diameter (mm), 0 = no sphere (pushing: ASTM D3787's 25.4 mm ball)", NULL, sphere_mm, &sphere_mm, NULL));
  CHECK_NONNEG(sphere_mm, "-sphere_diameter_mm");
  PetscCall(PetscOptionsReal("-thickness_mm", "fabric thickness (mm): a crossing touches a body at half of it", NULL, thick_mm, &thick_mm, NULL));
  CHECK_NONNEG(thick_mm, "-thickness_mm");
  s->bodies.sphere_dir[2] = 1;
  {
    PetscInt n = 3;
    PetscBool dset;
    PetscCall(PetscOptionsRealArray("-sphere_direction", "direction of the sphere's straight path x,y,z (normalised)", NULL, s->bodies.sphere_dir, &n, &dset));
    PetscCheck(!dset || n == 3, comm, PETSC_ERR_USER_INPUT, "-sphere_direction needs three components x,y,z, got %" PetscInt_FMT, n);
    const PetscReal norm = PetscSqrtReal(PetscSqr(s->bodies.sphere_dir[0]) + PetscSqr(s->bodies.sphere_dir[1]) + PetscSqr(s->bodies.sphere_dir[2]));
    PetscCheck(isfinite(norm) && norm > 0, comm, PETSC_ERR_USER_INPUT, "-sphere_direction must be a finite non-zero vector, got %g,%g,%g", (double)s->bodies.sphere_dir[0], (double)s->bodies.sphere_dir[1], (double)s->bodies.sphere_dir[2]);
    for (int d = 0; d < 3; d++) s->bodies.sphere_dir[d] /= norm;
    n = 3;
    PetscCall(PetscOptionsRealArray("-sphere_start_mm", "sphere centre at the start, x,y,z from the grid centre (mm); default: touching the fabric from behind along -sphere_direction", NULL, start_mm, &n, &start_set));
    PetscCheck(!start_set || n == 3, comm, PETSC_ERR_USER_INPUT, "-sphere_start_mm needs three components x,y,z, got %" PetscInt_FMT, n);
  }
  PetscCall(PetscOptionsReal("-sphere_travel_mm", "sphere travel along its path over the load steps (mm)", NULL, travel_mm, &travel_mm, NULL));
  CHECK_NONNEG(travel_mm, "-sphere_travel_mm");
  PetscCall(PetscOptionsReal("-contact_stiffness_N_m", "penalty stiffness of the contact per crossing (N/m); 0 = the warp yarn segment's EA/L0 (enters the stable step)", NULL, kc, &kc, NULL));
  CHECK_NONNEG(kc, "-contact_stiffness_N_m");
  PetscCall(PetscOptionsBool("-plane", "a rigid plane (table) with penalty contact: the fabric stays on the side -plane_normal points to", NULL, s->bodies.plane, &s->bodies.plane, NULL));
  s->bodies.plane_normal[2] = 1;
  {
    PetscInt  n = 3;
    PetscBool nset;
    PetscCall(PetscOptionsRealArray("-plane_point_mm", "a point of the plane, x,y,z from the grid centre (mm)", NULL, s->bodies.plane_point, &n, &nset));
    PetscCheck(!nset || n == 3, comm, PETSC_ERR_USER_INPUT, "-plane_point_mm needs three components x,y,z, got %" PetscInt_FMT, n);
    for (int d = 0; d < 3; d++) s->bodies.plane_point[d] *= 1e-3;
    n = 3;
    PetscCall(PetscOptionsRealArray("-plane_normal", "the plane's normal x,y,z, towards the fabric (normalised)", NULL, s->bodies.plane_normal, &n, &nset));
    PetscCheck(!nset || n == 3, comm, PETSC_ERR_USER_INPUT, "-plane_normal needs three components x,y,z, got %" PetscInt_FMT, n);
    const PetscReal norm = PetscSqrtReal(PetscSqr(s->bodies.plane_normal[0]) + PetscSqr(s->bodies.plane_normal[1]) + PetscSqr(s->bodies.plane_normal[2]));
    PetscCheck(isfinite(norm) && norm > 0, comm, PETSC_ERR_USER_INPUT, "-plane_normal must be a finite non-zero vector, got %g,%g,%g", (double)s->bodies.plane_normal[0], (double)s->bodies.plane_normal[1], (double)s->bodies.plane_normal[2]);
    for (int d = 0; d < 3; d++) s->bodies.plane_normal[d] /= norm;
  }
  {
    PetscReal ped_mm = s->test == TEST_DRAPE ? 180 : 0, ped_h_mm = 50, top_mm[3] = {0, 0, 0};
    PetscInt  n = 3;
    PetscBool tset;
    PetscCall(PetscOptionsReal("-pedestal_diameter_mm", "a rigid pedestal (disc, flat cylinder with a vertical axis) with penalty contact on its top face, rim and edge: its diameter (mm), 0 = none (drape: Cusick's 180 mm support disc)", NULL, ped_mm, &ped_mm, NULL));
    CHECK_NONNEG(ped_mm, "-pedestal_diameter_mm");
    PetscCall(PetscOptionsReal("-pedestal_height_mm", "the pedestal's height below its top face (mm)", NULL, ped_h_mm, &ped_h_mm, NULL));
    CHECK_POSITIVE(ped_h_mm, "-pedestal_height_mm");
    PetscCall(PetscOptionsRealArray("-pedestal_top_mm", "centre of the pedestal's top face x,y,z from the grid centre (mm); default: under the centre, touching the fabric at rest (z = -thickness/2)", NULL, top_mm, &n, &tset));
    PetscCheck(!tset || n == 3, comm, PETSC_ERR_USER_INPUT, "-pedestal_top_mm needs three components x,y,z, got %" PetscInt_FMT, n);
    for (int d = 0; d < 3; d++) PetscCheck(isfinite(top_mm[d]), comm, PETSC_ERR_USER_INPUT, "-pedestal_top_mm component %d is not a finite number", d);
    s->bodies.pedestal_radius = 0.5e-3 * ped_mm;
    s->bodies.pedestal_height = 1e-3 * ped_h_mm;
    for (int d = 0; d < 3; d++) s->bodies.pedestal_top[d] = tset ? 1e-3 * top_mm[d] : (d == 2 ? -0.5e-3 * thick_mm : 0.0);
  }
  PetscCall(PetscOptionsReal("-friction_mu", "Coulomb friction coefficient between the fabric and every rigid body (stick spring of the contact stiffness, slip at mu times the normal force); 0 = frictionless", NULL, s->bodies.friction_mu, &s->bodies.friction_mu, NULL));
  CHECK_NONNEG(s->bodies.friction_mu, "-friction_mu");
  PetscCheck(s->test != TEST_PUSHING || sphere_mm > 0, comm, PETSC_ERR_USER_INPUT, "-test pushing needs a sphere: -sphere_diameter_mm must be positive, got %g", (double)sphere_mm);
  PetscCheck(s->test == TEST_PUSHING || sphere_mm == 0, comm, PETSC_ERR_USER_INPUT, "-sphere_diameter_mm %g: the sphere is the pushing test's punch (-test pushing)", (double)sphere_mm);
  PetscOptionsEnd();

  PetscOptionsBegin(comm, NULL, "Clamps", NULL);
  PetscCheck((s->clamps.clamp == CLAMP_JAW) == JawTest(s) || (s->clamps.clamp == CLAMP_NONE && s->clamps.grip_lines > 0), comm, PETSC_ERR_USER_INPUT, "-clamp %s with -test %s: the jaws are the strip and bias tests' clamps, and only theirs (without jaws, these tests need -grip_line_mm)", ClampNames[s->clamps.clamp], TestNames[s->test]);
  PetscCheck(s->clamps.grip_lines == 0 || JawTest(s), comm, PETSC_ERR_USER_INPUT, "-grip_line_mm with -test %s: only the strip and bias tests move grips", TestNames[s->test]);
  PetscCheck((s->spec.shape == SHAPE_BIAS) == (s->test == TEST_BIAS), comm, PETSC_ERR_USER_INPUT, "-shape %s with -test %s: the bias shape is the bias test's, and it needs it", ShapeNames[s->spec.shape], TestNames[s->test]);
  PetscCheck(s->test != TEST_STRIP || (s->spec.shape == SHAPE_RECTANGLE && (s->clamps.clamp == CLAMP_JAW || (s->clamps.clamp == CLAMP_NONE && s->clamps.grip_lines > 0))), comm, PETSC_ERR_USER_INPUT, "-test strip is a rectangle between jaws: -shape %s and -clamp %s are for the other tests (a strip without jaws: -clamp none and -grip_line_mm)", ShapeNames[s->spec.shape], ClampNames[s->clamps.clamp]);
  PetscOptionsEnd();

  PetscOptionsBegin(comm, NULL, "Yarns (warp along x, weft along y)", NULL);
  PetscCall(YarnOptions(comm, PetscOptionsObject, &s->yarns.warp, "warp", 8.0));
  PetscCall(YarnOptions(comm, PetscOptionsObject, &s->yarns.weft, "weft", 5.0));
  PetscOptionsEnd();

  PetscOptionsBegin(comm, NULL, "Fabric terms (each can be switched off)", NULL);
  s->terms.traction = s->terms.bending = s->terms.shear = PETSC_TRUE;
  PetscCall(PetscOptionsBool("-traction", "yarn traction (MODEL.md 5.1)", NULL, s->terms.traction, &s->terms.traction, NULL));
  PetscCall(PetscOptionsBool("-bending", "yarn bending along both families (MODEL.md 5.2)", NULL, s->terms.bending, &s->terms.bending, NULL));
  PetscCall(PetscOptionsBool("-shear", "in-plane shear with jamming (MODEL.md 5.3)", NULL, s->terms.shear, &s->terms.shear, NULL));
  s->terms.shear_G    = 50.0;
  s->terms.lock_deg   = 35.0;
  s->terms.jam_factor = 100.0;
  PetscCall(PetscOptionsReal("-shear_G_N_m", "in-plane shear rigidity G (N/m per radian)", NULL, s->terms.shear_G, &s->terms.shear_G, NULL));
  CHECK_NONNEG(s->terms.shear_G, "-shear_G_N_m");
  PetscCall(PetscOptionsReal("-shear_lock_deg", "jamming (locking) shear angle (degrees)", NULL, s->terms.lock_deg, &s->terms.lock_deg, NULL));
  PetscCheck(isfinite(s->terms.lock_deg) && s->terms.lock_deg > 0 && s->terms.lock_deg < 90, comm, PETSC_ERR_USER_INPUT, "-shear_lock_deg must be in (0,90), got %g", (double)s->terms.lock_deg);
  PetscCall(PetscOptionsReal("-jam_factor", "jamming stiffness as a multiple of the shear stiffness (0 = no jamming)", NULL, s->terms.jam_factor, &s->terms.jam_factor, NULL));
  CHECK_NONNEG(s->terms.jam_factor, "-jam_factor");
  s->terms.gravity[2] = -9.81;
  PetscCall(PetscOptionsRealArray("-gravity", "gravity vector gx,gy,gz (m/s^2); 0,0,0 = off", NULL, s->terms.gravity, &n3, &set));
  PetscCheck(!set || n3 == 3, comm, PETSC_ERR_USER_INPUT, "-gravity needs three components gx,gy,gz, got %" PetscInt_FMT, n3);
  for (int d = 0; d < 3; d++) PetscCheck(isfinite(s->terms.gravity[d]), comm, PETSC_ERR_USER_INPUT, "-gravity component %d is not a finite number", d);
  PetscCall(PetscOptionsReal("-nu", "air viscosity per point (N s/m), the paper's coefficient", NULL, s->num.nu, &s->num.nu, NULL));
  CHECK_NONNEG(s->num.nu, "-nu");
  s->num.damping_ratio = 1.0;
  PetscCall(PetscOptionsReal("-damping_ratio", "mass-proportional damping as a fraction of critical for the slowest mode along the pull (0 = off)", NULL, s->num.damping_ratio, &s->num.damping_ratio, NULL));
  CHECK_NONNEG(s->num.damping_ratio, "-damping_ratio");
  PetscOptionsEnd();

  PetscOptionsBegin(comm, NULL, "Load program", NULL);
  if (s->test != TEST_STRIP && s->test != TEST_BIAS) elong_pct = 0; /* no jaws */
  PetscCall(PetscOptionsReal("-elongation_pct", "final elongation: grip travel / gauge length (%)", NULL, elong_pct, &elong_pct, NULL));
  PetscCheck(isfinite(elong_pct) && elong_pct >= 0 && elong_pct <= 100, comm, PETSC_ERR_USER_INPUT, "-elongation_pct must be in [0,100], got %g", (double)elong_pct);
  PetscCheck(JawTest(s) || elong_pct == 0, comm, PETSC_ERR_USER_INPUT, "-elongation_pct %g: -test %s has no jaws to pull", (double)elong_pct, TestNames[s->test]);
  PetscCall(PetscOptionsReal("-speed_mm_min", "test speed of the moving jaw (mm/min); gives time_s", NULL, speed_mm_min, &speed_mm_min, NULL));
  CHECK_POSITIVE(speed_mm_min, "-speed_mm_min");
  PetscCall(PetscOptionsRealArray("-point_load_N", "final point load fx,fy,fz (N), ramped with the load steps", NULL, s->load.point_load, &n3, &set));
  PetscCheck(!set || n3 == 3, comm, PETSC_ERR_USER_INPUT, "-point_load_N needs three components fx,fy,fz, got %" PetscInt_FMT, n3);
  s->load.load_at[0] = s->load.load_at[1] = -1;
  n2 = 2;
  PetscCall(PetscOptionsIntArray("-point_load_at", "crossing i,j of the point load (default: the centre)", NULL, s->load.load_at, &n2, &set));
  PetscCheck(!set || n2 == 2, comm, PETSC_ERR_USER_INPUT, "-point_load_at needs two indices i,j, got %" PetscInt_FMT, n2);
  PetscCall(PathOptions(comm, PetscOptionsObject, s));
  PetscCheck(s->load.waypoints == 0 || JawTest(s), comm, PETSC_ERR_USER_INPUT, "-grip_path_mm with -test %s: only the strip and bias tests move grips", TestNames[s->test]);
  s->load.load_steps      = 50;
  s->load.max_inner_steps = 20000;
  PetscCall(PetscOptionsInt("-load_steps", "number of load steps K", NULL, s->load.load_steps, &s->load.load_steps, NULL));
  PetscCheck(s->load.load_steps >= 1, comm, PETSC_ERR_USER_INPUT, "-load_steps must be at least 1, got %" PetscInt_FMT, s->load.load_steps);
  PetscCall(PetscOptionsInt("-max_inner_steps", "te steps per load step N (the most if it balances earlier)", NULL, s->load.max_inner_steps, &s->load.max_inner_steps, NULL));
  PetscCheck(s->load.max_inner_steps >= 1, comm, PETSC_ERR_USER_INPUT, "-max_inner_steps must be at least 1, got %" PetscInt_FMT, s->load.max_inner_steps);
  PetscOptionsEnd();

  PetscOptionsBegin(comm, NULL, "Numerics", NULL);
  s->num.integrator = INTEGRATOR_DAMPED;
  PetscCall(PetscOptionsEnum("-integrator", "damped: damped central differences; paper: the paper's eq. (10)", NULL, IntegratorNames, (PetscEnum)s->num.integrator, (PetscEnum *)&s->num.integrator, NULL));
  PetscCall(PetscOptionsReal("-te", "time step te (s); 0 = from the stable bound", NULL, s->num.te_user, &s->num.te_user, NULL));
  CHECK_NONNEG(s->num.te_user, "-te");
  s->num.te_safety = 0.9;
  PetscCall(PetscOptionsReal("-te_safety", "te = safety * stable bound (Gershgorin)", NULL, s->num.te_safety, &s->num.te_safety, NULL));
  PetscCheck(isfinite(s->num.te_safety) && s->num.te_safety > 0 && s->num.te_safety <= 1, comm, PETSC_ERR_USER_INPUT, "-te_safety must be in (0,1], got %g", (double)s->num.te_safety);
  s->num.te_check = PETSC_TRUE;
  PetscCall(PetscOptionsBool("-te_check", "refuse a -te above the stable bound (0: experts and stability tests only)", NULL, s->num.te_check, &s->num.te_check, NULL));
  s->num.te_window = 1.0;
  PetscCall(PetscOptionsReal("-te_strain_window", "chord-strain margin around each segment's strain over which the yarn tangent is maximised for the bound, and margin in sin(shear angle) below the locking angle from which the jamming stiffness counts (smaller: larger te while yarns are crimped and crossings far from locking, but a load step that straightens or shears them further can go unstable; 1 = the whole law)", NULL, s->num.te_window, &s->num.te_window, NULL));
  CHECK_NONNEG(s->num.te_window, "-te_strain_window");
  s->num.early_exit = PETSC_TRUE;
  PetscCall(PetscOptionsBool("-early_exit", "end a load step as soon as the balance test passes (modified multi-sampling)", NULL, s->num.early_exit, &s->num.early_exit, NULL));
  s->num.balance_tol = 1e-3;
  PetscCall(PetscOptionsReal("-balance_tol", "balance: max residual force on a free point / largest yarn tension", NULL, s->num.balance_tol, &s->num.balance_tol, NULL));
  CHECK_POSITIVE(s->num.balance_tol, "-balance_tol");
  PetscCall(PetscOptionsReal("-speed_tol", "balance: max speed of a free point (m/s); 0 = the test speed", NULL, s->num.speed_tol, &s->num.speed_tol, NULL));
  CHECK_NONNEG(s->num.speed_tol, "-speed_tol");
  s->num.predict = PREDICT_LINEAR;
  PetscCall(PetscOptionsEnum("-predict", "displacement prediction at each load step", NULL, PredictNames, (PetscEnum)s->num.predict, (PetscEnum *)&s->num.predict, NULL));
  s->num.grip_ramp = -1;
  PetscCall(PetscOptionsInt("-grip_ramp_steps", "te steps over which the jaw (or the sphere) moves to each load step's position (cosine ramp); -1 = half a period of the slowest mode without prediction or with a sphere, 0 (a jump) with prediction", NULL, s->num.grip_ramp, &s->num.grip_ramp, NULL));
  PetscCheck(s->num.grip_ramp >= -1, comm, PETSC_ERR_USER_INPUT, "-grip_ramp_steps must be -1 (auto) or >= 0, got %" PetscInt_FMT, s->num.grip_ramp);
  PetscCall(PetscOptionsBool("-front", "rank propagation: compute only the points a load change can have reached", NULL, s->num.front, &s->num.front, NULL));
  PetscCall(PetscOptionsReal("-sleep_tol", "sleeping: skip points whose residual (relative, like -balance_tol) and speed stay below this, with asleep neighbours; 0 = off", NULL, s->num.sleep_tol, &s->num.sleep_tol, NULL));
  CHECK_NONNEG(s->num.sleep_tol, "-sleep_tol");
  PetscCall(PetscOptionsBool("-kinetic_damping", "kinetic damping (Cundall's dynamic relaxation): all velocities are set to zero whenever the total kinetic energy has passed a peak (an exact sum: the same on any number of ranks); for scenes relaxed to rest (drape)", NULL, s->num.kinetic_damping, &s->num.kinetic_damping, NULL));
  PetscCheck(!s->num.kinetic_damping || s->num.integrator == INTEGRATOR_DAMPED, comm, PETSC_ERR_USER_INPUT, "-kinetic_damping needs -integrator damped (the paper's integrator keeps two velocity chains), got -integrator %s", IntegratorNames[s->num.integrator]);
  PetscCheck(s->num.sleep_tol <= s->num.balance_tol, comm, PETSC_ERR_USER_INPUT, "-sleep_tol %g is above -balance_tol %g: points would sleep before they balance", (double)s->num.sleep_tol, (double)s->num.balance_tol);
  PetscOptionsEnd();

  PetscOptionsBegin(comm, NULL, "Output", NULL);
  PetscCall(PetscSNPrintf(s->out.output_dir, sizeof s->out.output_dir, "results/%s", s->out.name));
  PetscCall(PetscOptionsString("-output_dir", "directory for curve.csv and summary.json (\"none\": write nothing)", NULL, s->out.output_dir, s->out.output_dir, sizeof s->out.output_dir, NULL));
  if (!strcmp(s->out.output_dir, "none")) s->out.output_dir[0] = 0;
  PetscCall(PetscOptionsString("-positions_out", "write the final positions (natural order, PETSc binary) to this file", NULL, s->out.positions_out, s->out.positions_out, sizeof s->out.positions_out, NULL));
  PetscCall(PetscOptionsBool("-quiet", "no progress line per load step", NULL, s->out.quiet, &s->out.quiet, NULL));
  PetscOptionsEnd();

  /* derived: SI, grid */
  s->spec.ends_per_m  = ends_cm * 100.0;
  s->spec.picks_per_m = picks_cm * 100.0;
  s->load.elongation  = elong_pct / 100.0;
  s->bodies.sphere_radius = 0.5e-3 * sphere_mm;
  s->bodies.thickness     = 1e-3 * thick_mm;
  s->bodies.sphere_travel = 1e-3 * travel_mm;
  for (int d = 0; d < 3; d++) s->bodies.sphere_start[d] = start_set ? 1e-3 * start_mm[d] : -(s->bodies.sphere_radius + 0.5 * s->bodies.thickness) * s->bodies.sphere_dir[d];
  s->bodies.contact_k = kc > 0 ? kc : s->yarns.warp.EA * s->spec.picks_per_m; /* EA / L0 of a warp segment */
  PetscCheck((s->bodies.sphere_radius == 0 && !s->bodies.plane && s->bodies.pedestal_radius == 0) || (!s->num.front && s->num.sleep_tol == 0), comm, PETSC_ERR_USER_INPUT, "-front and -sleep_tol follow the jaws and the point load only: switch them off with a sphere, a plane or a pedestal");
  s->load.speed       = speed_mm_min * 1e-3 / 60.0;
  if (s->num.speed_tol == 0) s->num.speed_tol = s->load.speed;
  if (s->test == TEST_BIAS && ends_cm == picks_cm) {
    /* The grid covers the specimen and its jaws, rotated by 45 degrees. With equal densities
       the outline lies on grid diagonals, h = spacing/sqrt(2) apart: the jaw lines at
       i + j - c = +-J (c = nx - 1), the long edges at j - i = +-E, the ends of the jaws at
       +-(J + Jd), and c has the parity of J + E, so that the jaw lines meet the edges at
       crossings. Each yarn then has exactly (gauge - width)/(sqrt(2) spacing) free segments
       between the jaws: D of the kinematic formula (MODEL.md 11) is the grid's own. (A jaw
       line between diagonals, or corners between crossings, leaves up to two more free
       segments per yarn: D was 12 % too long for 60 mm x 30 mm at 8 threads/cm.) The gauge
       length, width and jaw depth are rounded to the diagonals, as the strip's gauge length
       is rounded to its crossings. */
    const PetscReal h = 1.0 / (PetscSqrtReal(2.0) * s->spec.picks_per_m);
    const PetscReal J = round(0.5e-3 * gauge_mm / h), E = round(0.5e-3 * width_mm / h), Jd = PetscMax(1.0, round(1e-3 * jaw_mm / h));
    const PetscReal n = J + E + Jd + fmod(Jd, 2.0) + 1;
    PetscCheck(E >= 1 && J > E, comm, PETSC_ERR_USER_INPUT, "bias specimen too small or too wide: -gauge_mm %g, -width_mm %g at %g threads/cm (the gauge length must exceed the width by at least one yarn spacing)", (double)gauge_mm, (double)width_mm, (double)picks_cm);
    PetscCheck(n * n < 2.0e9, comm, PETSC_ERR_USER_INPUT, "grid too large: %g x %g crossings", n, n);
    s->spec.nx        = (PetscInt)n;
    s->spec.ny        = (PetscInt)n;
    s->spec.gauge     = 2 * J * h; /* free length between the jaws, along the specimen */
    s->spec.width     = 2 * E * h;
    s->spec.jaw_depth = Jd * h;
  } else if (s->test == TEST_BIAS) { /* unequal densities: the diagonals are not at 45 degrees */
    const PetscReal side = (gauge_mm + 2 * jaw_mm + width_mm) * 1e-3 / PetscSqrtReal(2.0);
    const PetscReal nx = round(side * s->spec.picks_per_m) + 1, ny = round(side * s->spec.ends_per_m) + 1;
    PetscCheck(nx >= 5 && ny >= 5 && width_mm < gauge_mm, comm, PETSC_ERR_USER_INPUT, "bias specimen too small or too wide: -gauge_mm %g, -width_mm %g (the gauge length must exceed the width) give %g x %g crossings", (double)gauge_mm, (double)width_mm, nx, ny);
    PetscCheck(nx * ny < 2.0e9, comm, PETSC_ERR_USER_INPUT, "grid too large: %g x %g crossings", nx, ny);
    s->spec.nx        = (PetscInt)nx;
    s->spec.ny        = (PetscInt)ny;
    s->spec.gauge     = gauge_mm * 1e-3; /* free length between the jaws, along the specimen */
    s->spec.width     = width_mm * 1e-3;
    s->spec.jaw_depth = jaw_mm * 1e-3;
  } else if (s->test != TEST_STRIP) { /* a gauge x width net with crossings on all four edges */
    const PetscReal nx = round(gauge_mm * 1e-3 * s->spec.picks_per_m) + 1, ny = round(width_mm * 1e-3 * s->spec.ends_per_m) + 1;
    PetscCheck(nx >= 3 && ny >= 3, comm, PETSC_ERR_USER_INPUT, "grid too small: -gauge_mm %g x -width_mm %g gives %g x %g crossings, at least 3 x 3 are needed", (double)gauge_mm, (double)width_mm, nx, ny);
    PetscCheck(nx * ny < 2.0e9, comm, PETSC_ERR_USER_INPUT, "grid too large: %g x %g crossings", nx, ny);
    s->spec.nx    = (PetscInt)nx;
    s->spec.ny    = (PetscInt)ny;
    s->spec.gauge = (nx - 1) / s->spec.picks_per_m;
    s->spec.width = (ny - 1) / s->spec.ends_per_m;
    s->spec.disc_radius = disc_mm > 0 ? 0.5e-3 * disc_mm : 0.5 * PetscMin(s->spec.gauge, s->spec.width);
    s->clamps.ring[0] = 0.5e-3 * ring_mm[0];
    s->clamps.ring[1] = 0.5e-3 * ring_mm[1];
  } else {
    const PetscReal along_density = s->spec.pull == PULL_WARP ? s->spec.picks_per_m : s->spec.ends_per_m;
    const PetscReal across_density = s->spec.pull == PULL_WARP ? s->spec.ends_per_m : s->spec.picks_per_m;
    const PetscReal n_along = round(gauge_mm * 1e-3 * along_density) + 1;
    const PetscReal n_across = s->spec.yarns ? (PetscReal)s->spec.yarns : round(width_mm * 1e-3 * across_density);
    PetscCheck(n_along >= 3, comm, PETSC_ERR_USER_INPUT, "grid too small: -gauge_mm %g at %g threads/cm gives %g crossings along the pull, at least 3 are needed", (double)gauge_mm, (double)(along_density / 100), (double)n_along);
    PetscCheck(n_across >= 1, comm, PETSC_ERR_USER_INPUT, "grid too small: -width_mm %g at %g threads/cm gives no yarn across the strip", (double)width_mm, (double)(across_density / 100));
    PetscCheck(n_along * n_across < 2.0e9, comm, PETSC_ERR_USER_INPUT, "grid too large: %g x %g crossings", (double)n_along, (double)n_across);
    s->spec.nx    = (PetscInt)(s->spec.pull == PULL_WARP ? n_along : n_across);
    s->spec.ny    = (PetscInt)(s->spec.pull == PULL_WARP ? n_across : n_along);
    s->spec.gauge = (n_along - 1) / along_density;
    s->spec.width = n_across / across_density;
  }
  if (s->load.load_at[0] < 0) {
    s->load.load_at[0] = s->spec.nx / 2;
    s->load.load_at[1] = s->spec.ny / 2;
  }
  PetscCheck(s->load.load_at[0] < s->spec.nx && s->load.load_at[1] >= 0 && s->load.load_at[1] < s->spec.ny, comm, PETSC_ERR_USER_INPUT, "-point_load_at %" PetscInt_FMT ",%" PetscInt_FMT " is outside the %" PetscInt_FMT " x %" PetscInt_FMT " grid", s->load.load_at[0], s->load.load_at[1], s->spec.nx, s->spec.ny);
  PetscFunctionReturn(0);
}

PetscErrorCode SceneDestroy(Scene *s)
{
  PetscFunctionBeginUser;
  PetscCall(YarnLawDestroy(&s->yarns.warp));
  PetscCall(YarnLawDestroy(&s->yarns.weft));
  PetscFunctionReturn(0);
}
