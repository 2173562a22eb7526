/* scene.c - the scene: every parameter of a run, from the PETSc options database.
 *
 * One table of option descriptors (Options[]) drives reading the options, -help, and the
 * values that checkpoints and summary.json record. A scene file is a YAML option file
 * (-scene inputs/X.yaml); the command line overrides it. Options are read as text and parsed
 * here, so that every bad value (empty, not a number, NaN or Inf, an integer out of range, a
 * choice that does not exist, an array of the wrong length) is refused with the option's name.
 * Defaults that depend on the test (-test drape: a 300 mm disc on a 180 mm pedestal) are
 * resolved before the options that use them are read, so a value given on the command line
 * always wins and -help shows the true default. Textile units at the edges (tex, threads/cm,
 * %, cN/tex, mm) are converted here, once, to SI (SceneDerive). The scene file's checks before PETSc reads
 * it, and the options nothing reads, are scenefile.c's.
 */
#include "scene.h"
#include <petscsf.h> /* the star forests' type names (CheckStarForest) */
#include "comm.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

const char *const PullAxisNames[]   = {"warp", "weft", "PullAxis", "PULL_", NULL};
const char *const SolverNames[]     = {"explicit", "static", "SolverType", "SOLVER_", NULL};
const char *const IntegratorNames[] = {"damped", "paper", "fire", "IntegratorType", "INTEGRATOR_", NULL};
const char *const PredictNames[]    = {"none", "linear", "extrapolate", "PredictType", "PREDICT_", NULL};
const char *const TestNames[]       = {"strip", "square", "pushing", "bias", "drape", "TestType", "TEST_", NULL};
const char *const ShapeNames[]      = {"rectangle", "disc", "bias", "ShapeType", "SHAPE_", NULL};
const char *const ClampNames[]      = {"jaw", "edge", "ring", "none", "ClampType", "CLAMP_", NULL};

typedef enum { OPT_REAL, OPT_INT, OPT_BOOL, OPT_ENUM, OPT_STRING, OPT_REALS, OPT_INTS } OptType;
typedef enum { ANY, POSITIVE, NONNEG, RANGE } OptCheck; /* RANGE: lo <= v <= hi, ends open by lo_open/hi_open */

typedef struct {
  const char        *group; /* -help group, "" = same as the entry before */
  const char        *name;  /* without the dash; "%s_..." is a yarn option (warp_..., weft_...) */
  OptType            type;
  size_t             at;      /* offsetof(SceneInput, field), or of YarnInput for yarn options */
  size_t             at_n;    /* arrays: offsetof the count (0 = none) */
  PetscReal          def[3];  /* default (option units); yarn options: warp, weft; arrays: the values */
  PetscInt           ndef;    /* arrays: default count */
  const PetscReal   *by_test; /* defaults by test (TEST_COUNT values; arrays: the default count), NULL = def */
  OptCheck           check;
  PetscReal          lo, hi;
  int                lo_open, hi_open;
  const char        *must;      /* what a failed check says the value must be */
  const char *const *choices;   /* enum names */
  PetscInt           per, nmax; /* arrays: values per item (count a multiple of it), most values */
  const char        *needs;     /* arrays: what a bad count says is needed */
  const char        *help;
} OptionDesc;

#define IN(f)      offsetof(SceneInput, f)
#define YIN(f)     offsetof(YarnInput, f)
#define NONE       0, {0, 0, 0}, 0, NULL
#define DEF(v)     0, {v, v, 0}, 0, NULL
#define YDEF(w, f) 0, {w, f, 0}, 0, NULL
#define TDEF(tab)  0, {0, 0, 0}, 0, tab
#define REAL(g, n, f, d, chk, must, help)                                   \
  {                                                                         \
    g, n, OPT_REAL, IN(f), d, chk, 0, 0, 0, 0, must, NULL, 0, 0, NULL, help \
  }
#define RANGED(g, n, f, d, lo, hi, lo_open, hi_open, must, help)                            \
  {                                                                                         \
    g, n, OPT_REAL, IN(f), d, RANGE, lo, hi, lo_open, hi_open, must, NULL, 0, 0, NULL, help \
  }
#define INT(g, n, f, d, lo, must, help)                                                   \
  {                                                                                       \
    g, n, OPT_INT, IN(f), d, RANGE, lo, PETSC_MAX_INT, 0, 0, must, NULL, 0, 0, NULL, help \
  }
#define TEXT_(x)       #x
#define TEXT(x)        TEXT_(x)
#define INT_TO(g, n, f, d, lo, hi, must, help)                                 \
  {                                                                            \
    g, n, OPT_INT, IN(f), d, RANGE, lo, hi, 0, 0, must, NULL, 0, 0, NULL, help \
  }
#define BOOL(g, n, f, d, help)                                              \
  {                                                                         \
    g, n, OPT_BOOL, IN(f), d, ANY, 0, 0, 0, 0, NULL, NULL, 0, 0, NULL, help \
  }
#define ENUM(g, n, f, d, names, help)                                        \
  {                                                                          \
    g, n, OPT_ENUM, IN(f), d, ANY, 0, 0, 0, 0, NULL, names, 0, 0, NULL, help \
  }
#define STRING(g, n, f, help)                                                    \
  {                                                                              \
    g, n, OPT_STRING, IN(f), NONE, ANY, 0, 0, 0, 0, NULL, NULL, 0, 0, NULL, help \
  }
#define REALS(g, n, f, nd, d0, d1, d2, per, nmax, needs, help)                                                     \
  {                                                                                                                \
    g, n, OPT_REALS, IN(f), IN(n_##f), {d0, d1, d2}, nd, NULL, ANY, 0, 0, 0, 0, NULL, NULL, per, nmax, needs, help \
  }
#define YREAL(n, f, d, chk, lo, hi, lo_open, hi_open, must, help)                           \
  {                                                                                         \
    "", n, OPT_REAL, YIN(f), d, chk, lo, hi, lo_open, hi_open, must, NULL, 0, 0, NULL, help \
  }

#define POS_MUST    "a positive number"
#define NONNEG_MUST "zero or positive"
#define XYZ         "three components x,y,z"

/* test-dependent defaults, indexed by TestType: strip, square, pushing, bias, drape */
static const PetscReal GaugeByTest[TEST_COUNT]    = {200, 200, 200, 200, 300}; /* Cusick: a 30 cm specimen */
static const PetscReal WidthByTest[TEST_COUNT]    = {50, 50, 50, 50, 300};
static const PetscReal ShapeByTest[TEST_COUNT]    = {SHAPE_RECTANGLE, SHAPE_RECTANGLE, SHAPE_RECTANGLE, SHAPE_BIAS,
                                                     SHAPE_DISC};
static const PetscReal ClampByTest[TEST_COUNT]    = {CLAMP_JAW, CLAMP_EDGE, CLAMP_EDGE, CLAMP_JAW, CLAMP_RING};
static const PetscReal SphereByTest[TEST_COUNT]   = {0, 0, 25.4, 0, 0}; /* ASTM D3787's ball */
static const PetscReal TravelByTest[TEST_COUNT]   = {0, 0, 20, 0, 0};
static const PetscReal PedestalByTest[TEST_COUNT] = {0, 0, 0, 0, 180}; /* Cusick: the 18 cm support disc */
static const PetscReal ElongByTest[TEST_COUNT]    = {13, 0, 0, 13, 0}; /* only the jaw tests pull */
static const PetscReal RingByTest[TEST_COUNT] = {0, 0, 0, 0, 2}; /* values of -clamp_ring_mm's default (0,180) */

static const OptionDesc Options[] = {
    /* the test first: the defaults of the options below depend on it */
    ENUM("Test", "test", test, DEF(TEST_STRIP), TestNames,
         "strip: ISO 13934-1 strip between jaws; square: clamped net of gauge x width (mm) under the point load, no "
         "jaws; "
         "pushing: a rigid sphere pushed through the clamped fabric (ASTM D3787); bias: a 45 degree specimen between "
         "jaws; drape: Cusick drape, a disc specimen on a pedestal under gravity"),
    STRING("", "scene", scene, "scene file (YAML options); the command line overrides it"),
    REAL("Specimen", "ends_per_cm", ends_per_cm, DEF(24), POSITIVE, POS_MUST,
         "warp density (ends/cm): warp yarns run along x, spaced along y"),
    REAL("", "picks_per_cm", picks_per_cm, DEF(24), POSITIVE, POS_MUST,
         "weft density (picks/cm): weft yarns run along y, spaced along x"),
    REAL("", "gauge_mm", gauge_mm, TDEF(GaugeByTest), POSITIVE, POS_MUST,
         "gauge length between the jaws; the net's or disc grid's length along x (mm)"),
    REAL("", "width_mm", width_mm, TDEF(WidthByTest), POSITIVE, POS_MUST, "strip width; the net's length along y (mm)"),
    INT("", "yarns", yarns, DEF(0), 0, NONNEG_MUST, "yarns across the strip (0 = width * density)"),
    ENUM("", "pull", pull, DEF(PULL_WARP), PullAxisNames, "yarn family pulled by the jaws"),
    ENUM("", "shape", shape, TDEF(ShapeByTest), ShapeNames,
         "specimen shape cut from the grid: rectangle (the whole grid), disc (centred) or bias (-gauge_mm x -width_mm "
         "between jaws, its length at 45 degrees to the yarns)"),
    REAL("", "disc_diameter_mm", disc_diameter_mm, DEF(0), NONNEG, NONNEG_MUST,
         "disc specimen diameter (mm), centred on the grid; 0 = the smaller grid side"),
    REAL("", "jaw_depth_mm", jaw_depth_mm, DEF(2), POSITIVE, POS_MUST,
         "bias specimen: length held in each jaw beyond the gauge length (mm)"),
    ENUM("Clamps", "clamp", clamp, TDEF(ClampByTest), ClampNames,
         "clamped crossings: jaw (the strip's or bias specimen's fixed jaw; the other end is the moving jaw), edge "
         "(every crossing of the shape's outline), ring (an annulus around the grid centre), none"),
    {"",
     "clamp_ring_mm",
     OPT_REALS,
     IN(clamp_ring_mm),
     IN(n_clamp_ring_mm),
     {0, 180, 0},
     0,
     RingByTest,
     ANY,
     0,
     0,
     0,
     0,
     NULL,
     NULL,
     2,
     2,
     "two diameters inner,outer",
     "inner,outer diameter of the clamping ring (mm), centred on the grid (drape default: 0,180)"},
    REALS("", "clamp_line_mm", clamp_line_mm, 0, 0, 0, 0, 4, 4 * MAX_LINES,
          "x,y,angle_deg,half_width_mm for each line (4 numbers per line, 1 to 8 lines)",
          "clamp lines across the grid, on top of -clamp: x,y,angle_deg,half_width_mm per line (a point from the grid "
          "centre in mm, the angle to the warp (x) axis, the band's half-width in mm); its crossings never move"),
    REALS("", "grip_line_mm", grip_line_mm, 0, 0, 0, 0, 4, 4 * MAX_LINES,
          "x,y,angle_deg,half_width_mm for each line (4 numbers per line, 1 to 8 lines)",
          "grip lines across the grid (strip and bias tests): x,y,angle_deg,half_width_mm per line, as -clamp_line_mm; "
          "its crossings move with the grip"),
    REAL("Rigid bodies (MODEL.md 5.5)", "sphere_diameter_mm", sphere_diameter_mm, TDEF(SphereByTest), NONNEG,
         NONNEG_MUST, "sphere diameter (mm), 0 = no sphere (pushing: ASTM D3787's 25.4 mm ball)"),
    REAL("", "thickness_mm", thickness_mm, DEF(0.3), NONNEG, NONNEG_MUST,
         "fabric thickness (mm): a crossing touches a body at half of it"),
    REALS("", "sphere_direction", sphere_direction, 3, 0, 0, 1, 3, 3, XYZ,
          "direction of the sphere's straight path x,y,z (normalised)"),
    REALS("", "sphere_start_mm", sphere_start_mm, 0, 0, 0, 0, 3, 3, XYZ,
          "sphere centre at the start, x,y,z from the grid centre (mm); default: on the path's line through the grid "
          "centre, touching the fabric's plane from behind"),
    REAL("", "sphere_travel_mm", sphere_travel_mm, TDEF(TravelByTest), NONNEG, NONNEG_MUST,
         "sphere travel along its path over the load steps (mm)"),
    REAL("", "contact_stiffness_N_m", contact_stiffness_N_m, DEF(0), NONNEG, NONNEG_MUST,
         "penalty stiffness of the contact per crossing (N/m); 0 = the warp yarn segment's EA/L0"),
    BOOL("", "plane", plane, DEF(0), "a rigid plane (table): the fabric stays on the side -plane_normal points to"),
    REALS("", "plane_point_mm", plane_point_mm, 3, 0, 0, 0, 3, 3, XYZ,
          "a point of the plane, x,y,z from the grid centre (mm)"),
    REALS("", "plane_normal", plane_normal, 3, 0, 0, 1, 3, 3, XYZ,
          "the plane's normal x,y,z, towards the fabric (normalised)"),
    REAL("", "pedestal_diameter_mm", pedestal_diameter_mm, TDEF(PedestalByTest), NONNEG, NONNEG_MUST,
         "a rigid pedestal (disc, flat cylinder with a vertical axis) with contact on its top face, rim and edge: its "
         "diameter (mm), 0 = none (drape: Cusick's 180 mm support disc)"),
    REAL("", "pedestal_height_mm", pedestal_height_mm, DEF(50), POSITIVE, POS_MUST,
         "the pedestal's height below its top face (mm)"),
    REALS("", "pedestal_top_mm", pedestal_top_mm, 0, 0, 0, 0, 3, 3, XYZ,
          "centre of the pedestal's top face x,y,z from the grid centre (mm); default: under the centre, touching the "
          "fabric at rest (z = -thickness/2)"),
    REAL("", "friction_mu", friction_mu, DEF(0), NONNEG, NONNEG_MUST,
         "Coulomb friction coefficient between the fabric and every rigid body; 0 = frictionless"),
    /* yarn options: "%s" is warp or weft */
    YREAL("%s_tex", tex, DEF(20), POSITIVE, 0, 0, 0, 0, POS_MUST, "linear density, tex (g/km)"),
    YREAL("%s_crimp_pct", crimp_pct, YDEF(8, 5), RANGE, 0, 100, 0, 1, "in [0,100)",
          "crimp: extra yarn length between crossings (%)"),
    YREAL("%s_modulus_cN_tex", modulus_cN_tex, DEF(260), POSITIVE, 0, 0, 0, 0, POS_MUST,
          "yarn modulus of the linear law (cN/tex): EA = modulus * tex"),
    YREAL("%s_decrimp_ratio", decrimp_ratio, DEF(0.05), NONNEG, 0, 0, 0, 0, NONNEG_MUST,
          "de-crimping stiffness Ec as a fraction of EA"),
    YREAL("%s_compression_ratio", compression_ratio, DEF(1e-3), NONNEG, 0, 0, 0, 0, NONNEG_MUST,
          "compression stiffness as a fraction of EA (yarns buckle)"),
    YREAL("%s_contact_pct", contact_pct, DEF(50), RANGE, 0, 100, 1, 1, "in (0,100)",
          "chord compression at which neighbouring crossings touch (%): below it the chord is as stiff as the yarn"),
    YREAL("%s_law_smoothing_pct", law_smoothing_pct, DEF(0), RANGE, 0, 5, 0, 1, "in [0,5)",
          "half-width of the C1 blend at each kink of the tension law (% chord strain); 0 = sharp kinks"),
    YREAL("%s_bending_Nm2", bending_Nm2, DEF(2e-9), NONNEG, 0, 0, 0, 0, NONNEG_MUST,
          "bending rigidity B per yarn (N m^2)"),
    YREAL("%s_break_pct", break_pct, DEF(0), NONNEG, 0, 0, 0, 0, NONNEG_MUST,
          "yarn breaking strain (%): the mean at the yarn test's gauge (-break_gauge_mm); 0 = never breaks"),
    YREAL("%s_break_cv_pct", break_cv_pct, DEF(0), RANGE, 0, 100, 0, 1, "in [0,100)",
          "coefficient of variation of the yarn breaking strain (%) at -break_gauge_mm: each segment's breaking strain "
          "is drawn from a Weibull distribution (weakest link); 0 = every segment breaks at the mean"),
    {"", "%s_law_csv", OPT_STRING, YIN(law_csv), NONE, ANY, 0, 0, 0, 0, NULL, NULL, 0, 0, NULL,
     "tabulated yarn law, CSV 'strain_pct,force_cN' (empty = linear EA)"},
    BOOL("Fabric terms (each can be switched off)", "traction", traction, DEF(1), "yarn traction (MODEL.md 5.1)"),
    BOOL("", "bending", bending, DEF(1), "yarn bending along both families (MODEL.md 5.2)"),
    BOOL("", "shear", shear, DEF(1), "in-plane shear with jamming (MODEL.md 5.3)"),
    REAL("", "shear_G_N_m", shear_G_N_m, DEF(50), NONNEG, NONNEG_MUST, "in-plane shear rigidity G (N/m per radian)"),
    RANGED("", "shear_lock_deg", shear_lock_deg, DEF(35), 0, 90, 1, 1, "in (0,90)",
           "jamming (locking) shear angle (degrees)"),
    REAL("", "jam_factor", jam_factor, DEF(100), NONNEG, NONNEG_MUST,
         "jamming stiffness as a multiple of the shear stiffness (0 = no jamming)"),
    REALS("", "gravity", gravity, 3, 0, 0, -9.81, 3, 3, "three components gx,gy,gz",
          "gravity vector gx,gy,gz (m/s^2); 0,0,0 = off"),
    REAL("", "nu", nu, DEF(0), NONNEG, NONNEG_MUST, "air viscosity per point (N s/m), the paper's coefficient"),
    REAL("", "damping_ratio", damping_ratio, DEF(1), NONNEG, NONNEG_MUST,
         "mass-proportional damping as a fraction of critical for the slowest mode along the pull (0 = off)"),
    RANGED("Load program", "elongation_pct", elongation_pct, TDEF(ElongByTest), 0, 100, 0, 0, "in [0,100]",
           "final elongation: grip travel / gauge length (%)"),
    RANGED("", "speed_mm_min", speed_mm_min, DEF(100), 1e-6, 1e9, 0, 0, "from 1e-6 to 1e9 (tensile testers run 1 to 1000)",
           "test speed of the moving jaw (mm/min); gives time_s"),
    REALS("", "point_load_N", point_load_N, 3, 0, 0, 0, 3, 3, "three components fx,fy,fz",
          "final point load fx,fy,fz (N), ramped with the load steps"),
    {"",
     "point_load_at",
     OPT_INTS,
     IN(point_load_at),
     IN(n_point_load_at),
     {0, 0, 0},
     0,
     NULL,
     ANY,
     0,
     0,
     0,
     0,
     NULL,
     NULL,
     2,
     2,
     "two indices i,j",
     "crossing i,j of the point load (default: the centre)"},
    REALS(
        "", "grip_path_mm", grip_path_mm, 0, 0, 0, 0, 3, 3 * MAX_WAYPOINTS,
        "dx,dy,dz for each waypoint (3 numbers per waypoint, 1 to 32 waypoints)",
        "the grip's path, replacing the straight pull of -elongation_pct: waypoints dx,dy,dz (mm, from the grip's rest "
        "position) joined by straight lines from 0,0,0 and travelled at the test speed; the load steps divide its "
        "length equally; curve.csv's elongation is the displacement along the pull / gauge"),
    INT_TO("", "load_steps", load_steps, DEF(50), 1, MAX_LOAD_STEPS, "from 1 to " TEXT(MAX_LOAD_STEPS),
           "number of load steps K (at most " TEXT(MAX_LOAD_STEPS) ": the run keeps a row of the curve per step)"),
    INT("", "max_inner_steps", max_inner_steps, DEF(20000), 1, "at least 1",
        "te steps per load step N (the most if it balances earlier)"),
    ENUM("Numerics", "solver", solver, DEF(SOLVER_EXPLICIT), SolverNames,
         "explicit: te steps relaxed to balance (the paper's scheme and its speed-ups); static: each load step's "
         "balance as a minimum of the potential energy, by Newton-Krylov with multigrid (PETSc's -snes_*, -ksp_*, "
         "-pc_* options apply)"),
    ENUM("", "integrator", integrator, DEF(INTEGRATOR_FIRE), IntegratorNames,
         "fire: FIRE, the relaxation that needs no damping to be set (velocities steered along the force, stopped "
         "when the power F.v turns negative; MODEL.md 15); damped: damped central differences with -damping_ratio; "
         "paper: the paper's eq. (10)"),
    REAL("", "te", te, DEF(0), NONNEG, NONNEG_MUST, "time step te (s); 0 = from the stable bound"),
    RANGED("", "te_safety", te_safety, DEF(0), 0, 1, 0, 0, "in [0,1]",
           "te = safety * stable bound; 0 = by the integrator: 0.8 with fire, 0.65 with damped and paper (a tear: "
           "-tear_te_safety)"),
    BOOL("", "te_check", te_check, DEF(1), "refuse a -te above the stable bound (0: experts and stability tests only)"),
    INT("", "te_measure", te_measure, DEF(0), 0, "0 (never) or a number of load steps",
        "measure the true largest eigenvalue of M^-1 K (Lanczos on the tangent stiffness) at the start and end of "
        "load step 1, of every this many load steps and of the last: te against 2/omega_max in summary.json"),
    REAL("", "te_strain_window", te_strain_window, DEF(0), NONNEG, NONNEG_MUST,
         "margin (chord strain, and sin(shear angle)) around the state's range of each yarn family's strains and of "
         "the shear that the stable bound covers; a te step that leaves it takes the bound again; 0 = by the "
         "integrator: 0.005 with fire, 1 (the whole yarn law) with damped and paper"),
    BOOL("", "early_exit", early_exit, DEF(1),
         "end a load step as soon as the balance test passes (modified multi-sampling)"),
    RANGED("", "balance_tol", balance_tol, DEF(1e-3), 0, 1, 1, 1,
           "in (0,1): a fraction of the largest yarn tension (1 or more passes any state)",
           "balance: max residual force on a free point / largest yarn tension"),
    REAL("", "speed_tol", speed_tol, DEF(0), NONNEG, NONNEG_MUST,
         "balance: max speed of a free point (m/s); 0 = the test speed"),
    INT("", "balance_hold", balance_hold, DEF(3), 1, "at least 1",
        "balance: te steps in a row the balance test must pass before the test per crossing ends the load step"),
    REAL("", "balance_floor", balance_floor, DEF(1e-3), NONNEG, NONNEG_MUST,
         "balance per crossing: a crossing's residual over the sum of the magnitudes of its own forces must be below "
         "-balance_tol, that sum never taken below this fraction of the largest yarn tension (0: the force floor "
         "only)"),
    REAL("", "energy_watch", energy_watch, DEF(0.5), NONNEG, NONNEG_MUST,
         "damped and paper integrators: stop a relaxation whose mechanical energy grows, with nothing doing work on "
         "the fabric, by more than this fraction of the energy it has released (0 = no watch)"),
    ENUM("", "predict", predict, DEF(PREDICT_LINEAR), PredictNames,
         "displacement prediction at each load step: none (from the last balanced state), linear (each point moves "
         "by its share of the grip step, from its distances to the clamped and moved points), extrapolate (the last "
         "load step's increment repeated)"),
    INT("", "grip_ramp_steps", grip_ramp_steps, DEF(-1), -1, "-1 (auto) or >= 0",
        "te steps over which the jaw (or the sphere) moves to each load step's position (cosine ramp); -1 = half a "
        "period of the slowest mode without prediction or with a sphere, 0 (a jump) with prediction"),
    BOOL("", "front", front, DEF(0), "rank propagation: compute only the points a load change can have reached"),
    REAL("", "sleep_tol", sleep_tol, DEF(0), NONNEG, NONNEG_MUST,
         "sleeping: skip points whose residual (relative, like -balance_tol) and speed stay below this; 0 = off"),
    BOOL("", "kinetic_damping", kinetic_damping, DEF(0),
         "kinetic damping: all velocities are set to zero whenever the total kinetic energy has passed a peak"),
    REAL("Rupture", "break_gauge_mm", break_gauge_mm, DEF(500), POSITIVE, POS_MUST,
         "gauge length of the yarn test the breaking strain's mean and CV come from (mm; ISO 2062: 500)"),
    INT("", "break_seed", break_seed, DEF(1), 0, "zero or positive",
        "seed of the segments' breaking strains: each is drawn from the seed and the segment's global index"),
    RANGED("", "rupture_drop_pct", rupture_drop_pct, DEF(90), 0, 100, 0, 1,
           "in [0,100) (at 100 the force of a broken specimen, 0 to rounding, would have to fall below 0)",
           "break detection: once a yarn has broken, the specimen has ruptured and the test ends when the force has "
           "fallen by this % of its maximum (0 = never ends early)"),
    RANGED("", "break_locate_pct", break_locate_pct, DEF(0.05), 0, 100, 0, 1, "in [0,100)",
           "locate each break: a balanced state with a segment past its breaking strain by more than this % of it is "
           "solved again at the load between it and the last state below every breaking strain, until within it, and "
           "yarns break there (0 = they break on the load step's state)"),
    REAL("", "tear_wave_crossings", tear_wave_crossings, DEF(2), POSITIVE, POS_MUST,
         "a tear (the dynamics after a yarn broke) ends when no segment broke while a yarn's stress wave crossed the "
         "specimen this many times"),
    REAL("", "tear_max_ms", tear_max_ms, DEF(20), POSITIVE, POS_MUST, "the longest tear, ms of test time"),
    REAL("", "tear_damping_ratio", tear_damping_ratio, DEF(0.05), NONNEG, NONNEG_MUST,
         "damping of a tear as a fraction of critical at the slowest mode (the yarns' own loss, not -damping_ratio's "
         "numerical damping)"),
    RANGED("", "tear_te_safety", tear_te_safety, DEF(0.9), 0, 1, 1, 0, "in (0,1]",
           "te of a tear = safety * stable bound over the whole yarn law (the relaxation's is -te_safety)"),
    STRING("Output", "output_dir", output_dir,
           "directory for the results (\"none\": write nothing); default results/SCENE"),
    STRING("", "positions_out", positions_out, "write the final positions (natural order, PETSc binary) to this file"),
    BOOL("", "quiet", quiet, DEF(0), "no progress line per load step"),
    INT("", "output_every", output_every, DEF(-1), 0, "0 (no frames) or a number of load steps",
        "write a frame to fabric.h5 every K load steps and at the last one (0 = no frames; default: about 10 frames)"),
    INT("", "output_te_every", output_te_every, DEF(0), 0, "0 (off) or a number of te steps",
        "also write a frame every M te steps within each load step, for dynamic scenes (0 = off)"),
    INT("", "output_tear_every", output_tear_every, DEF(0), 0, "0 (off) or a number of te steps",
        "write a frame every M te steps of a tear, the dynamics after a yarn broke (0 = off)"),
    INT("", "checkpoint_every", checkpoint_every, DEF(0), 0, "0 (never) or a number of load steps",
        "write DIR/checkpoint.h5 every K load steps (0 = never)"),
    INT("", "checkpoint_every_te", checkpoint_every_te, DEF(0), 0, "0 (never) or a number of te steps",
        "also write DIR/checkpoint.h5 within a load step every K te steps (0 = never)"),
    REAL("", "checkpoint_every_s", checkpoint_every_s, DEF(0), NONNEG, "0 (never) or a number of seconds",
         "also write DIR/checkpoint.h5 within a load step once S seconds of wall-clock time have passed since the last "
         "one (0 = never); SIGTERM or SIGUSR1 write one and stop the run (exit status 3)"),
    STRING("", "restart", restart,
           "continue the run saved in this checkpoint file (written by -checkpoint_every, -checkpoint_every_te, "
           "-checkpoint_every_s or a signal), appending to -output_dir"),
};
#define NOPTIONS ((PetscInt) (sizeof Options / sizeof Options[0]))

/* ---------------- reading one option ---------------- */

static void *Field(void *base, const OptionDesc *o)
{
  return (char *) base + o->at;
}

static const char *YarnName(int y)
{
  return y ? "weft" : "warp";
}

/* the option's name with its yarn filled in */
static void OptName(const OptionDesc *o, int yarn, char name[64])
{
  if (strncmp(o->name, "%s", 2) == 0)
    snprintf(name, 64, "%s%s", YarnName(yarn), o->name + 2);
  else
    snprintf(name, 64, "%s", o->name);
}

static PetscReal DefaultOf(const OptionDesc *o, const SceneInput *in, int yarn)
{
  if (o->by_test) return o->by_test[in->test];
  if (!strcmp(o->name, "output_every"))
    return (PetscReal) PetscMax(1, (in->load_steps + 9) / 10); /* about ten frames */
  return o->def[yarn];
}

/* PETSc keeps an error message's first 1023 characters: a value or file name of a kilobyte or more took the reason
   with it. In a message, a text longer than SHOWN_MAX keeps its first and last 100 bytes with "..." between (not
   inside a UTF-8 character) */
const char *ShowText(const char *text, Shown *sh)
{
  const size_t n = strlen(text);
  size_t       head = 100, tail = n - 100;
  if (n <= SHOWN_MAX - 1) return text;
  while (head > 0 && ((unsigned char) text[head] & 0xC0) == 0x80) head--;
  while (tail < n && ((unsigned char) text[tail] & 0xC0) == 0x80) tail++;
  snprintf(sh->text, sizeof sh->text, "%.*s...%s", (int) head, text, text + tail);
  return sh->text;
}

/* FILE (of option OPT) is a readable regular file: a directory said "no such file" */
PetscErrorCode SceneCheckReadable(MPI_Comm comm, const char *opt, const char *file)
{
  Shown     sh;
  PetscBool exists, dir;

  PetscFunctionBeginUser;
  PetscCall(PetscTestDirectory(file, 'r', &dir));
  PetscCheck(!dir, comm, PETSC_ERR_FILE_OPEN, "%s %s: a directory, not a file", opt, ShowText(file, &sh));
  { /* a device or a pipe (/dev/zero, a shell's <(...)): PETSc's test said "no such file"; it is read more than once */
    struct stat st;
    PetscCheck(stat(file, &st) || S_ISREG(st.st_mode), comm, PETSC_ERR_FILE_OPEN,
               "%s %s: not a regular file (a device or a pipe: give a file)", opt, ShowText(file, &sh));
  }
  PetscCall(PetscTestFile(file, 'r', &exists));
  PetscCheck(exists, comm, PETSC_ERR_FILE_OPEN, "%s %s: no such file, or not readable", opt, ShowText(file, &sh));
  PetscFunctionReturn(0);
}

/* a real number of the option (text as given), or an error naming both */
static PetscErrorCode ParseReal(MPI_Comm comm, const char *name, const char *text, PetscReal *v)
{
  Shown  sh;
  char  *end;
  double d;

  PetscFunctionBeginUser;
  errno = 0;
  d     = strtod(text, &end);
  while (*end == ' ') end++;
  PetscCheck(end != text && !*end, comm, PETSC_ERR_USER_INPUT, "-%s %s: not a number", name, ShowText(text, &sh));
  PetscCheck(isfinite(d) && !(errno == ERANGE && fabs(d) > 1), comm, PETSC_ERR_USER_INPUT,
             "-%s %s: not a finite number", name, ShowText(text, &sh));
  /* strtod flags a result below the smallest normal double (2.2e-308): a value that small makes
     every product with it lose its digits, or vanish */
  PetscCheck(errno != ERANGE, comm, PETSC_ERR_USER_INPUT,
             "-%s %s: too small for a double (non-zero values must exceed 2.2e-308 in magnitude)", name,
             ShowText(text, &sh));
  *v = (PetscReal) d;
  PetscFunctionReturn(0);
}

static PetscErrorCode ParseInt(MPI_Comm comm, const char *name, const char *text, PetscInt *v)
{
  Shown     sh;
  char     *end;
  long long l;

  PetscFunctionBeginUser;
  errno = 0;
  l     = strtoll(text, &end, 10);
  while (*end == ' ') end++;
  PetscCheck(end != text && !*end, comm, PETSC_ERR_USER_INPUT, "-%s %s: not an integer%s", name, ShowText(text, &sh),
             strpbrk(text, "eE.") ? " (integers are read in digits only, with no exponent or decimal point)" : "");
  PetscCheck(errno != ERANGE && l <= PETSC_MAX_INT && l >= PETSC_MIN_INT, comm, PETSC_ERR_USER_INPUT,
             "-%s %s: out of range (integers from %d to %d)", name, ShowText(text, &sh), (int) PETSC_MIN_INT, (int) PETSC_MAX_INT);
  *v = (PetscInt) l;
  PetscFunctionReturn(0);
}

static PetscErrorCode ParseBool(MPI_Comm comm, const char *name, const char *text, PetscBool *v)
{
  Shown       sh;
  const char *yes[] = {"", "1", "true", "yes", "on"}, *no[] = {"0", "false", "no", "off"};

  PetscFunctionBeginUser;
  for (int k = 0; k < 5; k++)
    if (!strcasecmp(text, yes[k])) *v = PETSC_TRUE;
  for (int k = 0; k < 4; k++)
    if (!strcasecmp(text, no[k])) *v = PETSC_FALSE;
  for (int k = 0; k < 5; k++)
    if (!strcasecmp(text, yes[k]) || (k < 4 && !strcasecmp(text, no[k]))) PetscFunctionReturn(0);
  SETERRQ(comm, PETSC_ERR_USER_INPUT, "-%s %s: not a yes/no value (use 1 or 0, true or false)", name, ShowText(text, &sh));
}

static PetscErrorCode ParseEnum(MPI_Comm comm, const char *name, const char *text, const char *const *choices,
                                PetscInt *v)
{
  Shown sh;
  char list[256] = "";
  int  n         = 0;

  PetscFunctionBeginUser;
  while (choices[n + 2]) n++; /* PETSc's enum arrays end with the type name, the prefix and NULL */
  for (int k = 0; k < n; k++) {
    if (!strcasecmp(text, choices[k])) {
      *v = k;
      PetscFunctionReturn(0);
    }
    PetscCall(PetscStrlcat(list, k ? ", " : "", sizeof list));
    PetscCall(PetscStrlcat(list, choices[k], sizeof list));
  }
  SETERRQ(comm, PETSC_ERR_USER_INPUT, "-%s %s: unknown choice (one of %s)", name, ShowText(text, &sh), list);
}

/* comma-separated numbers into v (at most nmax), their count into n */
static PetscErrorCode ParseArray(MPI_Comm comm, const OptionDesc *o, const char *name, const char *text, void *v,
                                 PetscInt *n)
{
  Shown sh;
  char buf[4096], *next = buf;

  PetscFunctionBeginUser; /* text fits: ReadOption refuses a longer value */
  if (strpbrk(text, "[]")) { /* YAML's list on the command line: the numbers alone are meant */
    Shown  sh2;
    size_t m = 0;
    for (const char *c = text; *c && m + 1 < sizeof buf; c++)
      if (*c != '[' && *c != ']' && *c != ' ') buf[m++] = *c;
    buf[m] = 0;
    const int ex = strpbrk(buf, "0123456789") != NULL; /* an example with numbers in it: "[]" and "[,]" have none */
    SETERRQ(comm, PETSC_ERR_USER_INPUT,
            "-%s %s: a bracket: give the numbers alone, joined by commas%s%s%s%s%s; brackets make a YAML list only in a "
            "scene file, unquoted",
            name, ShowText(text, &sh), ex ? " (-" : "", ex ? name : "", ex ? " " : "", ex ? ShowText(buf, &sh2) : "",
            ex ? ")" : "");
  }
  PetscCall(PetscStrncpy(buf, text, sizeof buf));
  *n = 0;
  while (next) { /* every field between commas: an empty one is refused, not skipped */
    char *tok = next, *comma = strchr(next, ',');
    if (comma) *comma = 0;
    next = comma ? comma + 1 : NULL;
    while (*tok == ' ') tok++;
    PetscCheck(*tok, comm, PETSC_ERR_USER_INPUT,
               "-%s %s: empty field %" PetscInt_FMT " (a comma at the start or the end, or two in a row): give a "
               "number between the commas",
               name, ShowText(text, &sh), *n + 1);
    if (*n < o->nmax) {
      if (o->type == OPT_INTS)
        PetscCall(ParseInt(comm, name, tok, (PetscInt *) v + *n));
      else
        PetscCall(ParseReal(comm, name, tok, (PetscReal *) v + *n));
    }
    (*n)++;
  }
  PetscCheck(*n > 0 && *n % o->per == 0 && *n <= o->nmax, comm, PETSC_ERR_USER_INPUT,
             "-%s needs %s, got %" PetscInt_FMT "%s", name, o->needs, *n, o->nmax > o->per ? " numbers" : "");
  PetscFunctionReturn(0);
}

/* The physical range of the options that set a stiffness, a mass or a size: far beyond any woven
   fabric, yet low enough that no product of them can overflow (a yarn's EA/L0 stays below
   1e9 N / 1e-5 m = 1e14 N/m; a grid of at least 3 crossings within 100 m keeps a point's mass
   below 100 kg). A value above it is a typo or a unit slip, not a material. The lower ends are the table's own
   (POSITIVE, NONNEG); products that underflow are refused where they are formed (fabric.c). docs/inputs.md lists them.
 */
typedef struct {
  const char *name; /* as in Options[] */
  PetscReal   hi;
  const char *hi_text, *unit, *why;
} PhysicalRange;

#define SIZE_MAX_MM 1e5
#define SIZE_WHY    "100 m, larger than any specimen or test rig"
#define PHYSICAL(name, hi, unit, why) \
  {                                   \
    name, hi, TEXT(hi), unit, why     \
  }
static const PhysicalRange Physical[] = {
    PHYSICAL("ends_per_cm", 1000, "threads/cm", "the densest woven fabrics have a few hundred"),
    PHYSICAL("picks_per_cm", 1000, "threads/cm", "the densest woven fabrics have a few hundred"),
    PHYSICAL("%s_tex", 1e5, "tex", "the heaviest woven tows are about 1e4 tex"),
    PHYSICAL("%s_modulus_cN_tex", 1e6, "cN/tex", "the stiffest fibres, high-modulus carbon, reach about 3e4 cN/tex"),
    PHYSICAL("%s_decrimp_ratio", 1, "", "straightening the crimp is never stiffer than stretching the yarn"),
    PHYSICAL("%s_compression_ratio", 1, "", "a yarn is never stiffer in compression than in tension"),
    PHYSICAL("%s_bending_Nm2", 1, "N m^2", "a 3 mm steel wire has 0.8 N m^2, yarns 1e-9 to 1e-5 N m^2"),
    PHYSICAL("shear_G_N_m", 1e6, "N/m", "woven fabrics have 0.1 to 100 N/m"),
    PHYSICAL("jam_factor", 1e6, "", "jammed crossings stiffen 1e2 to 1e4 times"),
    PHYSICAL("contact_stiffness_N_m", 1e12, "N/m", "a stiffer penalty only shrinks the time step"),
    PHYSICAL("damping_ratio", 1e6, "", "1 is critical damping, more only slows the relaxation"),
    PHYSICAL("tear_damping_ratio", 1e6, "", "1 is critical damping, yarns have about 0.05"),
    PHYSICAL("nu", 1e6, "N s/m", "6e-3 N s/m is about critical for a yarn of the stability sweep, docs/stability.md"),
    PHYSICAL("balance_floor", 1, "", "a fraction of the largest yarn tension: above it the test per crossing tests nothing"),
    PHYSICAL("gauge_mm", SIZE_MAX_MM, "mm", SIZE_WHY),
    PHYSICAL("width_mm", SIZE_MAX_MM, "mm", SIZE_WHY),
    PHYSICAL("disc_diameter_mm", SIZE_MAX_MM, "mm", SIZE_WHY),
    PHYSICAL("jaw_depth_mm", SIZE_MAX_MM, "mm", SIZE_WHY),
    PHYSICAL("sphere_diameter_mm", SIZE_MAX_MM, "mm", SIZE_WHY),
    PHYSICAL("thickness_mm", SIZE_MAX_MM, "mm", SIZE_WHY),
    PHYSICAL("sphere_travel_mm", SIZE_MAX_MM, "mm", SIZE_WHY),
    PHYSICAL("pedestal_diameter_mm", SIZE_MAX_MM, "mm", SIZE_WHY),
    PHYSICAL("pedestal_height_mm", SIZE_MAX_MM, "mm", SIZE_WHY),
    PHYSICAL("break_gauge_mm", SIZE_MAX_MM, "mm", SIZE_WHY),
};

static PetscErrorCode CheckReal(MPI_Comm comm, const OptionDesc *o, const char *name, PetscReal v)
{
  PetscBool ok = PETSC_TRUE;

  PetscFunctionBeginUser;
  if (o->check == POSITIVE) ok = v > 0 ? PETSC_TRUE : PETSC_FALSE;
  if (o->check == NONNEG) ok = v >= 0 ? PETSC_TRUE : PETSC_FALSE;
  if (o->check == RANGE)
    ok = ((o->lo_open ? v > o->lo : v >= o->lo) && (o->hi_open ? v < o->hi : v <= o->hi)) ? PETSC_TRUE : PETSC_FALSE;
  PetscCheck(ok, comm, PETSC_ERR_USER_INPUT, "-%s must be %s, got %.15g", name, o->must, (double) v);
  for (size_t k = 0; k < sizeof Physical / sizeof Physical[0]; k++)
    PetscCheck(strcmp(o->name, Physical[k].name) || v <= Physical[k].hi, comm, PETSC_ERR_USER_INPUT,
               "-%s %.15g is beyond the physical range (at most %s%s%s: %s)", name, (double) v, Physical[k].hi_text,
               Physical[k].unit[0] ? " " : "", Physical[k].unit, Physical[k].why);
  PetscFunctionReturn(0);
}

/* an array option's places and lines in mm (its name ends in _mm), within the sizes' range either way: a ball started
   at 1e300 mm never touched the fabric and the run was reported converged; a plane at 1e308 mm "started inf mm into
   the fabric". A line's angle (x,y,angle_deg,half_width_mm) is not a length. */
static PetscErrorCode CheckMillimetres(MPI_Comm comm, const char *name, const PetscReal *v, PetscInt n)
{
  const size_t    len   = strlen(name);
  const PetscBool lines = strstr(name, "_line_mm") ? PETSC_TRUE : PETSC_FALSE;

  PetscFunctionBeginUser;
  if (len < 3 || strcmp(name + len - 3, "_mm")) PetscFunctionReturn(0);
  for (PetscInt k = 0; k < n; k++)
    PetscCheck((lines && k % 4 == 2) || PetscAbsReal(v[k]) <= SIZE_MAX_MM, comm, PETSC_ERR_USER_INPUT,
               "-%s: its number %" PetscInt_FMT ", %.15g mm, is beyond the physical range (at most %s mm either way: %s)",
               name, k + 1, (double) v[k], TEXT(SIZE_MAX_MM), SIZE_WHY);
  PetscFunctionReturn(0);
}

/* the default as -help shows it */
static void DefaultText(const OptionDesc *o, const void *field, PetscReal def, char *out, size_t len)
{
  switch (o->type) {
  case OPT_REAL: snprintf(out, len, "%g", (double) def); break;
  case OPT_INT: snprintf(out, len, "%d", (int) def); break;
  case OPT_BOOL: snprintf(out, len, "%s", def != 0 ? "true" : "false"); break;
  case OPT_ENUM: snprintf(out, len, "%s", o->choices[(int) def]); break;
  case OPT_STRING: snprintf(out, len, "%s", (const char *) field); break;
  default: {
    const PetscInt nd = o->by_test ? (PetscInt) def : o->ndef;
    out[0]            = 0;
    if (!nd) snprintf(out, len, "unset");
    for (PetscInt k = 0; k < nd; k++) {
      const size_t at = strlen(out);
      snprintf(out + at, len - at, "%s%g", k ? "," : "", (double) o->def[k]);
    }
  }
  }
}

/* Read one option (for yarn options, of one yarn) into base (SceneInput or YarnInput): its
   default first, then the value given, parsed and checked. With -help, print it. */
static PetscErrorCode ReadOption(MPI_Comm comm, const OptionDesc *o, int yarn, const SceneInput *in, void *base,
                                 PetscBool help)
{
  char      name[64], opt[66], text[4096], deftext[256];
  PetscBool set;
  void     *f   = Field(base, o);
  PetscReal def = DefaultOf(o, in, yarn);

  PetscFunctionBeginUser;
  OptName(o, yarn, name);
  if (o->type == OPT_REAL) *(PetscReal *) f = def;
  if (o->type == OPT_INT || o->type == OPT_ENUM) *(PetscInt *) f = (PetscInt) def;
  if (o->type == OPT_BOOL) *(PetscBool *) f = def != 0 ? PETSC_TRUE : PETSC_FALSE;
  if (o->at_n) { /* an array: its default values (by_test: how many of them) */
    const PetscInt nd = o->by_test ? (PetscInt) def : o->ndef;
    if (o->type == OPT_REALS)
      for (PetscInt k = 0; k < nd; k++) ((PetscReal *) f)[k] = o->def[k];
    *(PetscInt *) Field(base, &(OptionDesc){.at = o->at_n}) = nd;
  }
  DefaultText(o, f, def, deftext, sizeof deftext);
  if (help) PetscCall(PetscPrintf(comm, "  -%s <%s>: %s\n", name, deftext, o->help));
  snprintf(opt, sizeof opt, "-%s", name);
  { /* PETSc's reader cuts a value at the buffer's size without a word: a path of 4099 characters named another file */
    const char *given = NULL;
    PetscCall(PetscOptionsFindPair(NULL, NULL, opt, &given, &set));
    if (set && given && strlen(given) >= (o->type == OPT_STRING ? (size_t) PETSC_MAX_PATH_LEN : sizeof text)) {
      Shown sh;
      SETERRQ(comm, PETSC_ERR_USER_INPUT, "-%s %s: too long (%zu characters; at most %d)", name, ShowText(given, &sh),
              strlen(given), (o->type == OPT_STRING ? PETSC_MAX_PATH_LEN : (int) sizeof text) - 1);
    }
  }
  PetscCall(PetscOptionsGetString(NULL, NULL, opt, text, sizeof text, &set));
  if (!set) PetscFunctionReturn(0);
  PetscCheck(text[0] || o->type == OPT_BOOL || !strcmp(o->name, "%s_law_csv"), comm, PETSC_ERR_USER_INPUT,
             "-%s: empty value (give a value or leave the option out)", name);
  switch (o->type) {
  case OPT_REAL:
    PetscCall(ParseReal(comm, name, text, (PetscReal *) f));
    PetscCall(CheckReal(comm, o, name, *(PetscReal *) f));
    break;
  case OPT_INT:
    PetscCall(ParseInt(comm, name, text, (PetscInt *) f));
    PetscCheck(*(PetscInt *) f >= (PetscInt) o->lo && *(PetscInt *) f <= (PetscInt) o->hi, comm, PETSC_ERR_USER_INPUT,
               "-%s must be %s, got %" PetscInt_FMT, name, o->must, *(PetscInt *) f);
    break;
  case OPT_BOOL: PetscCall(ParseBool(comm, name, text, (PetscBool *) f)); break;
  case OPT_ENUM: PetscCall(ParseEnum(comm, name, text, o->choices, (PetscInt *) f)); break;
  case OPT_STRING: PetscCall(PetscStrncpy((char *) f, text, PETSC_MAX_PATH_LEN)); break;
  default: {
    PetscInt *n = (PetscInt *) Field(base, &(OptionDesc){.at = o->at_n});
    PetscCall(ParseArray(comm, o, name, text, f, n));
    if (o->type == OPT_REALS) PetscCall(CheckMillimetres(comm, name, (const PetscReal *) f, *n));
  }
  }
  PetscFunctionReturn(0);
}

/* every option of the table into in, group by group */
static PetscErrorCode ReadOptions(MPI_Comm comm, SceneInput *in)
{
  PetscBool help;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  for (PetscInt k = 0; k < NOPTIONS; k++) {
    const OptionDesc *o = &Options[k];
    if (help && o->group[0]) PetscCall(PetscPrintf(comm, "%s:\n", o->group));
    if (strncmp(o->name, "%s", 2)) {
      PetscCall(ReadOption(comm, o, 0, in, in, help));
      continue;
    }
    if (help && !strcmp(o->name, "%s_tex")) /* the yarns' group: the first yarn option */
      PetscCall(PetscPrintf(comm, "Yarns (each -warp_... option has its -weft_... twin):\n"));
    for (int y = 0; y < 2; y++) PetscCall(ReadOption(comm, o, y, in, &in->yarn[y], help && y == 0));
  }
  PetscFunctionReturn(0);
}

int SceneOptionValues(const Scene *s, PetscInt k, char name[64], PetscReal v[], PetscInt *n)
{
  PetscInt q = 0;
  for (PetscInt e = 0; e < NOPTIONS; e++) {
    const OptionDesc *o     = &Options[e];
    const int         yarns = strncmp(o->name, "%s", 2) ? 1 : 2;
    if (o->type == OPT_STRING) continue;
    for (int y = 0; y < yarns; y++, q++) {
      const void *base = yarns == 2 ? (const void *) &s->in.yarn[y] : (const void *) &s->in;
      const void *f    = (const char *) base + o->at;
      if (q != k) continue;
      OptName(o, y, name);
      *n = 1;
      if (o->type == OPT_REAL) v[0] = *(const PetscReal *) f;
      if (o->type == OPT_INT || o->type == OPT_ENUM) v[0] = (PetscReal) * (const PetscInt *) f;
      if (o->type == OPT_BOOL) v[0] = (PetscReal) * (const PetscBool *) f;
      if (o->type == OPT_REALS || o->type == OPT_INTS) {
        *n = *(const PetscInt *) ((const char *) base + o->at_n);
        for (PetscInt c = 0; c < *n; c++)
          v[c] = o->type == OPT_REALS ? ((const PetscReal *) f)[c] : (PetscReal) ((const PetscInt *) f)[c];
      }
      return 1;
    }
  }
  return 0;
}

/* ---------------- from the options to the SI scene ---------------- */

static void DirOf(const char *path, char *dir, size_t len);

/* scene: the scene file's path, where a relative yarn table not found from the working directory is looked for */
static PetscErrorCode DeriveYarn(MPI_Comm comm, const YarnInput *in, const char *name, const char *scene, YarnLaw *y)
{
  PetscFunctionBeginUser;
  y->name          = name;
  y->tex           = in->tex;
  y->crimp         = in->crimp_pct / 100.0;
  y->EA            = in->modulus_cN_tex * 1e-2 * y->tex;
  y->k_comp        = in->compression_ratio;
  y->e_contact     = -in->contact_pct / 100.0;
  y->smoothing     = in->law_smoothing_pct / 100.0;
  /* a blend's cubic divides by its width squared and cubed: below about 1e-150 % of strain that overflows, and a
     blend far below the roundoff of a strain (1e-12) is no blend */
  PetscCheck(in->law_smoothing_pct == 0 || in->law_smoothing_pct >= 1e-6, comm, PETSC_ERR_USER_INPUT,
             "-%s_law_smoothing_pct %g: a blend this narrow cannot be computed (its cubic overflows) and blends nothing; "
             "0 for sharp kinks, or at least 1e-6",
             name, (double) in->law_smoothing_pct);
  y->bending       = in->bending_Nm2;
  y->break_ey      = in->break_pct / 100.0;
  y->decrimp_ratio = in->decrimp_ratio;
  y->bundle        = in->bundle;
  PetscCall(PetscStrncpy(y->csv, in->law_csv, sizeof y->csv));
  if (y->csv[0] && y->csv[0] != '/' && access(y->csv, F_OK)) { /* a relative path not found from here: from */
    char dir[PETSC_MAX_PATH_LEN], there[PETSC_MAX_PATH_LEN]; /* the scene file's directory (a scene's table) */
    DirOf(scene, dir, sizeof dir);
    PetscCall(PetscSNPrintf(there, sizeof there, "%s/%s", dir, y->csv));
    if (!access(there, F_OK)) PetscCall(PetscStrncpy(y->csv, there, sizeof y->csv));
  }
  PetscCall(YarnLawSetUp(y, comm));
  PetscFunctionReturn(0);
}

/* -clamp_line_mm / -grip_line_mm x,y,angle_deg,half_width_mm[,...] in SI */
static PetscErrorCode DeriveLines(MPI_Comm comm, const char *opt, const PetscReal *v, PetscInt n, PetscInt *nlines,
                                  PetscReal line[][4])
{
  PetscFunctionBeginUser;
  *nlines = n / 4;
  for (PetscInt k = 0; k < n / 4; k++) {
    const PetscReal *l = v + 4 * k;
    PetscCheck(l[3] > 0, comm, PETSC_ERR_USER_INPUT,
               "-%s line %" PetscInt_FMT ": the half-width must be a positive number of mm, got %g", opt, k + 1,
               (double) l[3]);
    line[k][0] = 1e-3 * l[0];
    line[k][1] = 1e-3 * l[1];
    line[k][2] = fmod(l[2], 360.0) * PETSC_PI / 180.0; /* exact: 1e308 degrees overflowed to an infinite angle */
    line[k][3] = 1e-3 * l[3];
  }
  PetscFunctionReturn(0);
}

/* -grip_path_mm: the waypoints in SI and the length along the path to each */
static PetscErrorCode DerivePath(MPI_Comm comm, const SceneInput *in, PetscReal gauge, LoadProgram *lp)
{
  PetscReal at = 0;

  PetscFunctionBeginUser;
  lp->waypoints = in->n_grip_path_mm / 3;
  for (PetscInt k = 0; k < lp->waypoints; k++) {
    const PetscReal *v    = in->grip_path_mm + 3 * k;
    PetscReal        len2 = 0;
    for (int d = 0; d < 3; d++) {
      lp->waypoint[k][d] = 1e-3 * v[d];
      len2 += PetscSqr(lp->waypoint[k][d] - (k ? lp->waypoint[k - 1][d] : 0.0));
    }
    PetscCheck(len2 > 0, comm, PETSC_ERR_USER_INPUT,
               "-grip_path_mm waypoint %" PetscInt_FMT
               " (%g,%g,%g mm) repeats the point before it: a path segment of zero length",
               k + 1, (double) v[0], (double) v[1], (double) v[2]);
    /* as -elongation_pct at most 100: the grip no farther from rest than the gauge length (the specimen's, rounded
       to the grid: DeriveGrid) */
    PetscCheck(PetscSqr(v[0]) + PetscSqr(v[1]) + PetscSqr(v[2]) <= PetscSqr(1e3 * gauge) * (1 + 1e-12), comm,
               PETSC_ERR_USER_INPUT,
               "-grip_path_mm waypoint %" PetscInt_FMT
               " (%.15g,%.15g,%.15g mm) is farther from rest than the gauge length, %.15g mm (-gauge_mm %.15g on the "
               "grid; as -elongation_pct is at most 100 %%): a grip travel the yarn model is not meant for",
               k + 1, (double) v[0], (double) v[1], (double) v[2], 1e3 * (double) gauge, (double) in->gauge_mm);
    at += PetscSqrtReal(len2);
    lp->path_at[k] = at;
  }
  PetscFunctionReturn(0);
}

/* a direction option as a unit vector (scaled by its largest component first: 1e-200,0,0 and 1e200,0,0 are
   directions too, their squares are not numbers) */
static PetscErrorCode UnitVector(MPI_Comm comm, const char *opt, const PetscReal v[3], PetscReal u[3])
{
  const PetscReal big = PetscMax(PetscAbsReal(v[0]), PetscMax(PetscAbsReal(v[1]), PetscAbsReal(v[2])));
  PetscReal       norm;

  PetscFunctionBeginUser;
  PetscCheck(isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]) && big > 0, comm, PETSC_ERR_USER_INPUT,
             "-%s must be a finite non-zero vector, got %g,%g,%g", opt, (double) v[0], (double) v[1], (double) v[2]);
  norm = PetscSqrtReal(PetscSqr(v[0] / big) + PetscSqr(v[1] / big) + PetscSqr(v[2] / big));
  for (int d = 0; d < 3; d++) u[d] = v[d] / big / norm;
  PetscFunctionReturn(0);
}

/* the largest yarn spacing (m) at these thread densities (per m) */
static PetscReal LargestSpacing(PetscReal ends_per_m, PetscReal picks_per_m)
{
  return PetscMax(1.0 / ends_per_m, 1.0 / picks_per_m);
}

/* a ball (radius in m; 0: none) touches the fabric at its crossings only: one narrower than two yarn spacings
   passes between them (DeriveBodies refuses it; SceneCoarsen builds no coarser fabric for it) */
static PetscBool BallPassesBetween(PetscReal radius, PetscReal ends_per_m, PetscReal picks_per_m)
{
  return radius > 0 && radius < LargestSpacing(ends_per_m, picks_per_m) ? PETSC_TRUE : PETSC_FALSE;
}

static PetscErrorCode DeriveBodies(MPI_Comm comm, const SceneInput *in, Scene *s)
{
  Bodies *b = &s->bodies;

  PetscFunctionBeginUser;
  b->sphere_radius = 0.5e-3 * in->sphere_diameter_mm;
  b->thickness     = 1e-3 * in->thickness_mm;
  b->sphere_travel = 1e-3 * in->sphere_travel_mm;
  PetscCall(UnitVector(comm, "sphere_direction", in->sphere_direction, b->sphere_dir));
  /* the default start: the ball touches the fabric's plane from behind, its centre on the path's line through
     the grid's centre, (R + h/2)/|dz| back along the path (a tilted path starts farther back) */
  b->sphere_start_set = in->n_sphere_start_mm ? PETSC_TRUE : PETSC_FALSE;
  PetscCheck(b->sphere_start_set || b->sphere_radius == 0 || b->sphere_dir[2] != 0, comm, PETSC_ERR_USER_INPUT,
             "-sphere_direction %g,%g,%g lies in the fabric's plane: the ball has no default start (touching the "
             "fabric from behind along the path); give -sphere_start_mm, or a direction with a z component",
             (double) in->sphere_direction[0], (double) in->sphere_direction[1], (double) in->sphere_direction[2]);
  for (int d = 0; d < 3; d++)
    b->sphere_start[d] = b->sphere_start_set ? 1e-3 * in->sphere_start_mm[d]
                         : b->sphere_radius > 0
                             ? -(b->sphere_radius + 0.5 * b->thickness) / PetscAbsReal(b->sphere_dir[2]) * b->sphere_dir[d]
                             : 0.0;
  { /* a path nearly in the plane: the default start touches the plane beyond the specimen, and the ball never
       reaches it */
    const PetscReal off = PetscSqrtReal(PetscSqr(b->sphere_start[0]) + PetscSqr(b->sphere_start[1])),
                    half = 0.5 * PetscSqrtReal(PetscSqr(s->spec.gauge) + PetscSqr(s->spec.width));
    PetscCheck(b->sphere_start_set || b->sphere_radius == 0 || off <= half, comm, PETSC_ERR_USER_INPUT,
               "-sphere_direction %g,%g,%g: the default start (touching the fabric's plane from behind along the path) "
               "is %g mm from the grid's centre, beyond the specimen (%g mm to its corners); give -sphere_start_mm, or "
               "a direction closer to the fabric's normal",
               (double) in->sphere_direction[0], (double) in->sphere_direction[1], (double) in->sphere_direction[2],
               1e3 * (double) off, 1e3 * (double) half);
  }
  b->plane = in->plane;
  for (int d = 0; d < 3; d++) b->plane_point[d] = 1e-3 * in->plane_point_mm[d];
  PetscCall(UnitVector(comm, "plane_normal", in->plane_normal, b->plane_normal));
  b->pedestal_radius = 0.5e-3 * in->pedestal_diameter_mm;
  b->pedestal_height = 1e-3 * in->pedestal_height_mm;
  for (int d = 0; d < 3; d++)
    b->pedestal_top[d] = in->n_pedestal_top_mm ? 1e-3 * in->pedestal_top_mm[d] : (d == 2 ? -0.5 * b->thickness : 0.0);
  b->friction_mu = in->friction_mu;
  b->contact_k =
      in->contact_stiffness_N_m > 0 ? in->contact_stiffness_N_m : s->yarns.warp.EA * s->spec.picks_per_m; /* EA/L0 */
  PetscCheck(s->test != TEST_PUSHING || b->sphere_radius > 0, comm, PETSC_ERR_USER_INPUT,
             "-test pushing needs a sphere: -sphere_diameter_mm must be positive, got %g",
             (double) in->sphere_diameter_mm);
  PetscCheck(s->test == TEST_PUSHING || b->sphere_radius == 0, comm, PETSC_ERR_USER_INPUT,
             "-sphere_diameter_mm %g: the sphere is the pushing test's punch (-test pushing)",
             (double) in->sphere_diameter_mm);
  {
    const PetscReal spacing = LargestSpacing(s->spec.ends_per_m, s->spec.picks_per_m);
    PetscCheck(!BallPassesBetween(b->sphere_radius, s->spec.ends_per_m, s->spec.picks_per_m), comm, PETSC_ERR_USER_INPUT,
               "-sphere_diameter_mm %g is less than two yarn spacings (%g mm at %g ends x %g picks per cm): the ball "
               "touches the fabric at its crossings only and would pass between them; use a ball of at least %g mm or "
               "a denser grid",
               (double) in->sphere_diameter_mm, 2e3 * (double) spacing, 1e-2 * (double) s->spec.ends_per_m,
               1e-2 * (double) s->spec.picks_per_m, 2e3 * (double) spacing);
  }
  if (s->test == TEST_DRAPE) { /* the drape coefficient's support disc */
    /* off (0,0,0) leaves the disc flat, drape coefficient 100 % (the measure's own check, tests/drape.sh) */
    PetscCheck(in->gravity[2] < 0 || (in->gravity[0] == 0 && in->gravity[1] == 0 && in->gravity[2] == 0), comm,
               PETSC_ERR_USER_INPUT,
               "-gravity %g,%g,%g with -test drape: the skirt hangs under gravity, which needs a downward component "
               "across the fabric (gz < 0; the default 0,0,-9.81), or 0,0,0 for the flat disc",
               (double) in->gravity[0], (double) in->gravity[1], (double) in->gravity[2]);
    PetscCheck(s->spec.shape == SHAPE_DISC, comm, PETSC_ERR_USER_INPUT,
               "-shape %s with -test drape: the drape coefficient (BS 5058, ISO 9073-9) is that of a disc specimen; "
               "use -shape disc",
               ShapeNames[s->spec.shape]);
    /* the skirt hangs free: held at its rim or along a line through it, the fabric is no drape (held at its rim,
       the disc gave a drape coefficient of 100 %; drape.yaml held along a diameter, 56.94 %) */
    PetscCheck(s->clamps.clamp == CLAMP_RING || s->clamps.clamp == CLAMP_NONE, comm, PETSC_ERR_USER_INPUT,
               "-clamp %s with -test drape: the skirt must hang free; the drape holds its centre (-clamp ring, or a "
               "pedestal with -clamp none)",
               ClampNames[s->clamps.clamp]);
    PetscCheck(in->n_clamp_line_mm == 0 && in->n_grip_line_mm == 0, comm, PETSC_ERR_USER_INPUT,
               "%s with -test drape: the skirt must hang free; the drape holds its centre (-clamp ring, or a pedestal "
               "with -clamp none)",
               in->n_clamp_line_mm ? "-clamp_line_mm" : "-grip_line_mm");
    PetscCheck(DrapeSupportRadius(s) > 0, comm, PETSC_ERR_USER_INPUT,
               "-pedestal_diameter_mm %g with -clamp %s: the drape has no support (a pedestal, or a clamping ring with "
               "-clamp ring): the specimen would fall freely",
               2e3 * (double) b->pedestal_radius, ClampNames[s->clamps.clamp]);
    PetscCheck(DrapeSupportRadius(s) < s->spec.disc_radius, comm, PETSC_ERR_USER_INPUT,
               "%s %g mm is not smaller than the specimen's %g mm (-disc_diameter_mm): nothing hangs over the "
               "support, and the drape coefficient (A_shadow - A_disc)/(A_specimen - A_disc) has no meaning",
               DrapeSupportRadius(s) > b->pedestal_radius ? "-clamp_ring_mm: the support's outer diameter"
                                                          : "-pedestal_diameter_mm",
               2e3 * (double) DrapeSupportRadius(s), 2e3 * (double) s->spec.disc_radius);
    /* A_disc is the pedestal's disc: it must hold the specimen's centre flat, under its centre and touching its
       lower face (a pedestal off-centre or below the fabric gave drape coefficients below 0 or above the truth) */
    PetscCheck(b->pedestal_radius == 0 ||
                   (b->pedestal_top[0] == 0 && b->pedestal_top[1] == 0 && b->pedestal_top[2] >= -b->thickness &&
                    b->pedestal_top[2] <= -0.5 * b->thickness), /* above: within the fabric, or wholly over it */
               comm, PETSC_ERR_USER_INPUT,
               "-pedestal_top_mm %g,%g,%g with -test drape: the drape coefficient's support disc is the pedestal's top "
               "face under the specimen's centre, touching it (x = y = 0, -%g mm <= z <= -%g mm; z = -%g mm, half the "
               "-thickness_mm, when unset); leave -pedestal_top_mm out or use -pedestal_diameter_mm 0 with -clamp ring",
               1e3 * (double) b->pedestal_top[0], 1e3 * (double) b->pedestal_top[1], 1e3 * (double) b->pedestal_top[2],
               1e3 * (double) b->thickness, 0.5e3 * (double) b->thickness, 0.5e3 * (double) b->thickness);
  }
  if (b->sphere_radius > 0 && b->plane) { /* a ball moving towards the plane must stay a fabric's thickness off it: in
                                             between, the fabric was crushed between two rigid bodies, and their
                                             penalties' overlap was reported as the force (1563 N, balanced, for 3.2 N
                                             without the plane). A plane behind the ball holds no fabric against it. */
    const PetscReal gap = b->sphere_radius + b->thickness, along = -(b->sphere_dir[0] * b->plane_normal[0] + b->sphere_dir[1] * b->plane_normal[1] + b->sphere_dir[2] * b->plane_normal[2]);
    PetscReal       d0 = 0;
    for (int d = 0; d < 3; d++) d0 += (b->sphere_start[d] - b->plane_point[d]) * b->plane_normal[d];
    PetscCheck(!(along > 0) || d0 >= gap, comm, PETSC_ERR_USER_INPUT,
               "-plane with the pushing test's ball: at its start the ball's centre is %g mm from the plane, within its "
               "radius and the fabric's thickness (%g mm): the fabric between them would be crushed; move the plane "
               "(-plane_point_mm, -plane_normal) or the ball (-sphere_start_mm)",
               1e3 * (double) d0, 1e3 * (double) gap);
    PetscCheck(!(along > 0) || d0 - b->sphere_travel * along >= gap, comm, PETSC_ERR_USER_INPUT,
               "-sphere_travel_mm %g with -plane: the ball comes within its radius and the fabric's thickness (%g mm) of "
               "the plane after %g mm of travel: the fabric between them would be crushed between two rigid bodies, "
               "which the model has no stiffness for; give at most that travel, or move the plane",
               1e3 * (double) b->sphere_travel, 1e3 * (double) gap, 1e3 * (double) ((d0 - gap) / along));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode GivenByUser(MPI_Comm comm, const char *opt, PetscBool *user);

/* the options that must agree with the test, the shape and the clamps */
static PetscErrorCode CheckTestOptions(MPI_Comm comm, const SceneInput *in, const Scene *s)
{
  const Clamps *c = &s->clamps;

  PetscFunctionBeginUser;
  PetscCheck(!(s->rupture.locate > 0 && in->friction_mu > 0 && (s->yarns.warp.break_ey > 0 || s->yarns.weft.break_ey > 0)),
             comm, PETSC_ERR_USER_INPUT,
             "-break_locate_pct %g with -friction_mu %g and breaking yarns: a located break solves the load again from an "
             "earlier state, and friction depends on the path taken; leave -break_locate_pct out (with friction yarns break "
             "on each load step's state) or use -friction_mu 0",
             (double) in->break_locate_pct, (double) in->friction_mu);
  if (s->test == TEST_STRIP && in->yarns > 0) { /* -yarns sets the width: a -width_mm typed was dropped */
    PetscBool yarns_typed, width_typed;
    PetscCall(GivenByUser(comm, "-yarns", &yarns_typed));
    PetscCall(GivenByUser(comm, "-width_mm", &width_typed));
    const PetscReal across = s->spec.pull == PULL_WARP ? in->ends_per_cm : in->picks_per_cm;
    PetscCheck(!(yarns_typed && width_typed), comm, PETSC_ERR_USER_INPUT,
               "-yarns %" PetscInt_FMT " and -width_mm %g both set the strip's width (%" PetscInt_FMT
               " yarns at %g threads/cm are %g mm); give one of them",
               in->yarns, (double) in->width_mm, in->yarns, (double) across, 10.0 * (double) in->yarns / (double) across);
    PetscCheck(!width_typed, comm, PETSC_ERR_USER_INPUT,
               "-width_mm %g is not read: the scene sets the strip's width in yarns, -yarns %" PetscInt_FMT
               " (%g mm at %g threads/cm); add -yarns 0 to give it in mm",
               (double) in->width_mm, in->yarns, 10.0 * (double) in->yarns / (double) across, (double) across);
  }
  PetscCheck(c->clamp != CLAMP_RING || (c->ring[0] >= 0 && c->ring[1] > c->ring[0]), comm, PETSC_ERR_USER_INPUT,
             "-clamp ring needs -clamp_ring_mm inner,outer with 0 <= inner < outer, got %g,%g",
             (double) (2e3 * c->ring[0]), (double) (2e3 * c->ring[1]));
  PetscCheck(
      (c->clamp == CLAMP_JAW) == JawTest(s) || (c->clamp == CLAMP_NONE && c->grip_lines > 0), comm,
      PETSC_ERR_USER_INPUT,
      "-clamp %s with -test %s: the jaws are the strip and bias tests' clamps, and only theirs (without jaws, these "
      "tests need -grip_line_mm)",
      ClampNames[c->clamp], TestNames[s->test]);
  PetscCheck(c->grip_lines == 0 || JawTest(s), comm, PETSC_ERR_USER_INPUT,
             "-grip_line_mm with -test %s: only the strip and bias tests move grips", TestNames[s->test]);
  PetscCheck((s->spec.shape == SHAPE_BIAS) == (s->test == TEST_BIAS), comm, PETSC_ERR_USER_INPUT,
             "-shape %s with -test %s: the bias shape is the bias test's, and it needs it", ShapeNames[s->spec.shape],
             TestNames[s->test]);
  PetscCheck(
      s->test != TEST_STRIP || (s->spec.shape == SHAPE_RECTANGLE &&
                                (c->clamp == CLAMP_JAW || (c->clamp == CLAMP_NONE && c->grip_lines > 0))),
      comm, PETSC_ERR_USER_INPUT,
      "-test strip is a rectangle between jaws: -shape %s and -clamp %s are for the other tests (a strip without jaws: "
      "-clamp none and -grip_line_mm)",
      ShapeNames[s->spec.shape], ClampNames[c->clamp]);
  PetscCheck(c->clamp != CLAMP_NONE || c->clamp_lines > 0 || c->grip_lines > 0 || s->bodies.plane ||
                 s->bodies.pedestal_radius > 0 || s->test == TEST_DRAPE, /* the drape's support: its own check */
             comm, PETSC_ERR_USER_INPUT,
             "-clamp none with -test %s: nothing holds the fabric (no clamp, no -clamp_line_mm, no plane or pedestal "
             "to rest on): the %s moves it freely and no load step can balance; use -clamp %s or add -clamp_line_mm",
             TestNames[s->test], s->test == TEST_PUSHING ? "ball" : "point load",
             s->test == TEST_PUSHING ? "ring with -clamp_ring_mm" : "edge");
  PetscCheck(JawTest(s) || in->elongation_pct == 0, comm, PETSC_ERR_USER_INPUT,
             "-elongation_pct %g: -test %s has no jaws to pull", (double) in->elongation_pct, TestNames[s->test]);
  PetscCheck(s->load.waypoints == 0 || JawTest(s), comm, PETSC_ERR_USER_INPUT,
             "-grip_path_mm with -test %s: only the strip and bias tests move grips", TestNames[s->test]);
  { /* vectors beyond any test (a run met them as NaN velocities at its first te step) */
    const PetscReal g = PetscSqrtReal(PetscSqr(in->gravity[0]) + PetscSqr(in->gravity[1]) + PetscSqr(in->gravity[2]));
    const PetscReal P = PetscSqrtReal(PetscSqr(in->point_load_N[0]) + PetscSqr(in->point_load_N[1]) +
                                      PetscSqr(in->point_load_N[2]));
    PetscCheck(g <= 1e4, comm, PETSC_ERR_USER_INPUT,
               "-gravity %g,%g,%g is beyond the physical range (at most 1e4 m/s^2, a thousand g, in magnitude)",
               (double) in->gravity[0], (double) in->gravity[1], (double) in->gravity[2]);
    PetscCheck(P <= 1e6, comm, PETSC_ERR_USER_INPUT,
               "-point_load_N %g,%g,%g is beyond the physical range (at most 1e6 N in magnitude: woven fabrics tear "
               "below 1e4 N)",
               (double) in->point_load_N[0], (double) in->point_load_N[1], (double) in->point_load_N[2]);
  }
  PetscCheck(!s->num.kinetic_damping || s->num.integrator == INTEGRATOR_DAMPED, comm, PETSC_ERR_USER_INPUT,
             "-kinetic_damping needs -integrator damped (the paper's integrator keeps two velocity chains), got "
             "-integrator %s",
             IntegratorNames[s->num.integrator]);
  PetscCheck(s->num.sleep_tol <= s->num.balance_tol, comm, PETSC_ERR_USER_INPUT,
             "-sleep_tol %g is above -balance_tol %g: points would sleep before they balance",
             (double) s->num.sleep_tol, (double) s->num.balance_tol);
  PetscCheck((s->bodies.sphere_radius == 0 && !s->bodies.plane && s->bodies.pedestal_radius == 0) ||
                 (!s->num.front && s->num.sleep_tol == 0),
             comm, PETSC_ERR_USER_INPUT,
             "-front and -sleep_tol follow the jaws and the point load only: switch them off with a sphere, a plane or "
             "a pedestal");
  PetscFunctionReturn(0);
}

/* the option (-name) was given by the user, not only set by the scene file: on the command line, in PETSC_OPTIONS or
   PETSC_OPTIONS_YAML, or in a file the user names there with -options_file or -options_file_yaml (as rank 0 has
   them). Every rank reads them (the file readers may be collective); rank 0's answer counts */
static PetscErrorCode GivenByUser(MPI_Comm comm, const char *opt, PetscBool *user)
{
  int          argc;
  char       **args;
  const char  *env = getenv("PETSC_OPTIONS");
  PetscOptions typed;
  PetscBool    has;
  PetscInt     found;

  PetscFunctionBeginUser;
  PetscCall(PetscGetArgs(&argc, &args));
  PetscCall(PetscOptionsCreate(&typed));
  PetscCall(PetscOptionsInsertArgs(typed, argc - 1, args + 1));
  if (env) PetscCall(PetscOptionsInsertString(typed, env));
  if ((env = getenv("PETSC_OPTIONS_YAML"))) PetscCall(PetscOptionsInsertStringYAML(typed, env));
  PetscCall(PetscOptionsHasName(typed, NULL, opt, &has));
  PetscCall(PetscOptionsDestroy(&typed));
  found = has;
  PetscCall(BroadcastFromRoot(comm, &found, 1, MPIU_INT));
  *user = found ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* An option that this test, shape or clamping does not read: typed by the user, it is refused (a run that
   ignored it would answer another question than the one asked); from the scene file only (a shipped scene run
   as another test: its keys cannot be unset on the command line), a warning says it is not used */
static PetscErrorCode CheckOptionsApply(MPI_Comm comm, const Scene *s)
{
  const PetscBool bodies =
      s->bodies.sphere_radius > 0 || s->bodies.plane || s->bodies.pedestal_radius > 0 ? PETSC_TRUE : PETSC_FALSE;
  const PetscBool moves = JawTest(s) || s->test == TEST_PUSHING ? PETSC_TRUE : PETSC_FALSE;
  const PetscBool tears = s->yarns.warp.break_ey > 0 || s->yarns.weft.break_ey > 0 ? PETSC_TRUE : PETSC_FALSE;
  const char     *nobreak = "-warp_break_pct 0 and -weft_break_pct 0", *notear = "no yarn breaks: there is no tear or rupture";
  const PetscBool fire = s->num.integrator == INTEGRATOR_FIRE ? PETSC_TRUE : PETSC_FALSE;
  const char     *nofire = "FIRE has no damping to set (a tear's is -tear_damping_ratio)";
  const char     *relaxer = s->num.solver == SOLVER_STATIC ? "-solver static and no yarn breaking"
                                                           : "-integrator fire and no yarn breaking";
  char test[64], shape[64], clamp[64], law[2][PETSC_MAX_PATH_LEN + 16], te[64];
  struct {
    const char *name;
    PetscBool   applies;
    const char *with, *why;
  } opts[] = {
      {"yarns", s->test == TEST_STRIP, test, "only the strip's width is given in yarns, the others take -width_mm"},
      {"jaw_depth_mm", s->test == TEST_BIAS, test, "only the bias test's jaws have a depth"},
      {"elongation_pct", !s->load.waypoints, "-grip_path_mm", "the path's waypoints set the grip's travel"},
      {"sphere_direction", s->test == TEST_PUSHING, test, "only the pushing test moves a ball"},
      {"sphere_start_mm", s->test == TEST_PUSHING, test, "only the pushing test moves a ball"},
      {"sphere_travel_mm", s->test == TEST_PUSHING, test, "only the pushing test moves a ball"},
      {"disc_diameter_mm", s->spec.shape == SHAPE_DISC, shape, "only a disc specimen (-shape disc) has a diameter"},
      {"clamp_ring_mm", s->clamps.clamp == CLAMP_RING, clamp, "only a ring clamp (-clamp ring) has diameters"},
      {"grip_ramp_steps", moves, test, "it moves no grips and no ball"},
      {"rupture_drop_pct", ReactionTest(s), test, "it measures no force for a break detection to watch"},
      {"friction_mu", bodies, test, "there is no sphere, plane or pedestal for the fabric to rub on"},
      {"contact_stiffness_N_m", bodies, test, "there is no sphere, plane or pedestal to touch"},
      {"warp_modulus_cN_tex", !s->yarns.warp.csv[0], law[0], "the table sets the yarn's stiffness"},
      {"weft_modulus_cN_tex", !s->yarns.weft.csv[0], law[1], "the table sets the yarn's stiffness"},
      {"break_gauge_mm", tears, nobreak, notear},
      {"break_seed", tears, nobreak, notear},
      {"rupture_drop_pct", tears || !ReactionTest(s), nobreak, notear}, /* else the entry above */
      {"tear_wave_crossings", tears, nobreak, notear},
      {"break_locate_pct", tears || s->rupture.locate == 0, nobreak, notear},
      {"tear_max_ms", tears, nobreak, notear},
      {"tear_damping_ratio", tears, nobreak, notear},
      {"tear_te_safety", tears, nobreak, notear},
      {"output_tear_every", tears || s->out.output_tear_every == 0, nobreak, notear}, /* 0: off, as without a tear */
      /* 0, off, passes: a command line that switches them off runs with FIRE too */
      {"damping_ratio", !fire || s->num.damping_ratio == 0, "-integrator fire", nofire},
      {"energy_watch", !fire || s->num.energy_watch == 0, "-integrator fire",
       "FIRE stops all motion at an uphill step: its energy cannot grow"},
      {"nu", !fire || tears || s->num.nu == 0, relaxer, "no viscosity there; only a tear's damped scheme reads it"},
      {"point_load_at", s->load.point_load[0] != 0 || s->load.point_load[1] != 0 || s->load.point_load[2] != 0,
       "-point_load_N 0,0,0", "there is no point load to place"},
      {"plane_normal", s->bodies.plane, "-plane false", "there is no plane"},
      {"plane_point_mm", s->bodies.plane, "-plane false", "there is no plane"},
      {"pedestal_height_mm", s->bodies.pedestal_radius > 0, "-pedestal_diameter_mm 0", "there is no pedestal"},
      {"pedestal_top_mm", s->bodies.pedestal_radius > 0, "-pedestal_diameter_mm 0", "there is no pedestal"},
      {"thickness_mm", bodies, test, "the thickness only sets where a crossing touches a sphere, plane or pedestal"},
      {"shear_G_N_m", s->terms.shear, "-shear false", "the shear term is off"},
      {"shear_lock_deg", s->terms.shear, "-shear false", "the shear term is off"},
      {"jam_factor", s->terms.shear, "-shear false", "the shear term is off"},
      {"warp_bending_Nm2", s->terms.bending, "-bending false", "the bending term is off"},
      {"weft_bending_Nm2", s->terms.bending, "-bending false", "the bending term is off"},
      /* -te sets te itself: no safety is applied to the bound, and -te_check has nothing else to check */
      {"te_safety", !(s->num.te_user > 0), te, "te is given, not taken from the stable bound"},
      {"tear_te_safety", !(s->num.te_user > 0), te, "te is given, also a tear's, not taken from the stable bound"},
      {"te_check", s->num.te_user > 0 || s->num.te_check, "-te unset",
       "te comes from the stable bound, below it by its safety: there is no -te to check"},
  };

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(test, sizeof test, "-test %s", TestNames[s->test]));
  PetscCall(PetscSNPrintf(te, sizeof te, "-te %g", (double) s->num.te_user));
  PetscCall(PetscSNPrintf(shape, sizeof shape, "-shape %s", ShapeNames[s->spec.shape]));
  PetscCall(PetscSNPrintf(clamp, sizeof clamp, "-clamp %s", ClampNames[s->clamps.clamp]));
  PetscCall(PetscSNPrintf(law[0], sizeof law[0], "-warp_law_csv %s", s->yarns.warp.csv));
  PetscCall(PetscSNPrintf(law[1], sizeof law[1], "-weft_law_csv %s", s->yarns.weft.csv));
  for (size_t k = 0; k < sizeof opts / sizeof opts[0]; k++) {
    char      opt[64], value[256] = "";
    PetscBool set, user;
    if (opts[k].applies) continue;
    PetscCall(PetscSNPrintf(opt, sizeof opt, "-%s", opts[k].name));
    PetscCall(PetscOptionsGetString(NULL, NULL, opt, value, sizeof value, &set));
    if (!set) continue;
    PetscCall(GivenByUser(comm, opt, &user));
    PetscCheck(!user, comm, PETSC_ERR_USER_INPUT, "%s %s is not used with %s: %s; leave it out", opt, value,
               opts[k].with, opts[k].why);
    PetscCall(PetscPrintf(comm, "fabric: warning: %s %s (from the scene) is not used with %s: %s\n", opt, value,
                          opts[k].with, opts[k].why));
  }
  PetscFunctionReturn(0);
}

/* what the quasi-static solver cannot do is refused, naming the option */
static PetscErrorCode CheckSolverOptions(MPI_Comm comm, const SceneInput *in, PetscBool coarse)
{
  PetscFunctionBeginUser;
  if (in->solver != SOLVER_STATIC) PetscFunctionReturn(0);
  PetscCheck(in->friction_mu == 0, comm, PETSC_ERR_USER_INPUT,
             "-friction_mu %g with -solver static: friction depends on the path, the quasi-static solver has none; use "
             "-solver explicit or -friction_mu 0",
             (double) in->friction_mu);
  PetscCheck(in->output_te_every == 0, comm, PETSC_ERR_USER_INPUT,
             "-output_te_every %" PetscInt_FMT " with -solver static: it takes no te steps; use -output_every",
             in->output_te_every);
  PetscCheck(in->checkpoint_every_te == 0, comm, PETSC_ERR_USER_INPUT,
             "-checkpoint_every_te %" PetscInt_FMT " with -solver static: it takes no te steps; use -checkpoint_every or "
             "-checkpoint_every_s",
             in->checkpoint_every_te);
  { /* the explicit relaxation's knobs: Newton reads none of them (a tear runs the damped scheme with the tear_*
       options, -te, -te_check, -te_strain_window and -max_inner_steps). Typed by the user, refused; from a scene
       file (large.yaml's -front, every scene's -max_inner_steps), left to the explicit path */
    static const char *const relaxation[] = {"integrator",    "front",        "sleep_tol",     "kinetic_damping",
                                             "damping_ratio", "balance_hold", "balance_floor", "speed_tol",
                                             "energy_watch",  "early_exit",   "te_safety",     "grip_ramp_steps",
                                             /* read by a tear only: refused where no yarn can break */
                                             "te",            "te_check",     "te_strain_window", "max_inner_steps"};
    /* a coarse scene's yarns never break (SceneCoarsen): the fabric's, checked first, decide */
    const PetscBool tears = coarse || in->yarn[0].break_pct > 0 || in->yarn[1].break_pct > 0 ? PETSC_TRUE : PETSC_FALSE;
    const size_t    n     = sizeof relaxation / sizeof relaxation[0] - (tears ? 4 : 0);
    for (size_t k = 0; k < n; k++) {
      char      opt[64], value[256] = "";
      PetscBool set, user;
      PetscCall(PetscSNPrintf(opt, sizeof opt, "-%s", relaxation[k]));
      PetscCall(PetscOptionsGetString(NULL, NULL, opt, value, sizeof value, &set));
      if (!set) continue;
      PetscCall(GivenByUser(comm, opt, &user));
      PetscCheck(!user, comm, PETSC_ERR_USER_INPUT,
                 "%s%s%s with -solver static: an option of the explicit relaxation, which the quasi-static solver "
                 "does not read%s; leave it out, or use -solver explicit",
                 opt, value[0] ? " " : "", value,
                 k >= 12 ? " (a tear reads it, and no yarn can break: -warp_break_pct and -weft_break_pct are 0)" : "");
    }
  }
  PetscFunctionReturn(0);
}

/* te safety and window for an integrator: the user's, or (0) the integrator's own. FIRE stops
   all motion at an uphill step: it runs close to the limit over a narrow window. The damped and
   paper schemes gain energy where a yarn crosses a kink of its law within a te step, so they keep
   a step that resolves the law's stiffest branch (docs/stability.md) */
static void StepPolicy(const SceneInput *in, IntegratorType integrator, PetscReal *safety, PetscReal *window)
{
  const PetscBool fire = integrator == INTEGRATOR_FIRE ? PETSC_TRUE : PETSC_FALSE;

  *safety = in->te_safety > 0 ? in->te_safety : fire ? 0.8 : 0.65;
  *window = in->te_strain_window > 0 ? in->te_strain_window : fire ? 0.005 : 1.0;
}

static void DeriveNumerics(const SceneInput *in, Scene *s)
{
  Numerics *n = &s->num;

  n->solver          = (SolverType) in->solver;
  n->integrator      = (IntegratorType) in->integrator;
  n->te_user         = in->te;
  StepPolicy(in, n->integrator, &n->te_safety, &n->te_window);
  /* a tear runs the damped scheme over the whole law, at its own safety: a few thousand te steps of
     dynamics with no balance to reach (docs/rupture.md) */
  StepPolicy(in, INTEGRATOR_DAMPED, &n->te_safety_tear, &n->te_window_tear);
  n->te_safety_tear = in->tear_te_safety;
  n->te_check        = in->te_check;
  n->te_measure      = in->te_measure;
  n->early_exit      = in->early_exit;
  n->balance_tol     = in->balance_tol;
  n->speed_tol       = in->speed_tol;
  n->balance_hold    = in->balance_hold;
  n->balance_floor   = in->balance_floor;
  n->energy_watch    = in->energy_watch;
  n->predict         = (PredictType) in->predict;
  n->front           = in->front;
  n->grip_ramp       = in->grip_ramp_steps;
  n->sleep_tol       = in->sleep_tol;
  n->kinetic_damping = in->kinetic_damping;
  n->nu              = in->nu;
  n->damping_ratio   = in->damping_ratio;
}

static void DeriveRupture(const SceneInput *in, Scene *s)
{
  s->rupture.seed      = in->break_seed;
  s->rupture.drop      = in->rupture_drop_pct / 100.0;
  s->rupture.crossings = in->tear_wave_crossings;
  s->rupture.locate    = in->break_locate_pct / 100.0;
  s->rupture.max_time  = in->tear_max_ms * 1e-3;
  s->rupture.damping   = in->tear_damping_ratio;
}

static void DeriveTermsAndLoad(const SceneInput *in, Scene *s)
{
  s->terms.traction   = in->traction;
  s->terms.bending    = in->bending;
  s->terms.shear      = in->shear;
  s->terms.shear_G    = in->shear_G_N_m;
  s->terms.lock_deg   = in->shear_lock_deg;
  s->terms.jam_factor = in->jam_factor;
  for (int d = 0; d < 3; d++) s->terms.gravity[d] = in->gravity[d];
  s->load.elongation      = in->elongation_pct / 100.0;
  s->load.speed           = in->speed_mm_min * 1e-3 / 60.0;
  s->load.load_steps      = in->load_steps;
  s->load.max_inner_steps = in->max_inner_steps;
  for (int d = 0; d < 3; d++) s->load.point_load[d] = in->n_point_load_N ? in->point_load_N[d] : 0.0;
  s->load.load_at[0] = in->n_point_load_at ? in->point_load_at[0] : -1;
  s->load.load_at[1] = in->n_point_load_at ? in->point_load_at[1] : -1;
  if (s->num.speed_tol == 0) s->num.speed_tol = s->load.speed;
}

static PetscErrorCode DeriveOutput(MPI_Comm comm, const SceneInput *in, Scene *s)
{
  SceneOutput *o = &s->out;
  const char  *base;

  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(o->file, in->scene, sizeof o->file));
  base = strrchr(o->file, '/');
  base = base ? base + 1 : o->file;
  PetscCall(PetscStrncpy(o->name, base[0] ? base : "default", sizeof o->name));
  {
    char *dot = strrchr(o->name, '.');
    if (dot && dot != o->name) *dot = 0;
  }
  if (in->output_dir[0])
    PetscCall(PetscStrncpy(o->output_dir, in->output_dir, sizeof o->output_dir));
  else
    PetscCall(PetscSNPrintf(o->output_dir, sizeof o->output_dir, "results/%s", o->name));
  if (!strcmp(o->output_dir, "none")) o->output_dir[0] = 0;
  PetscCall(PetscStrncpy(o->positions_out, in->positions_out, sizeof o->positions_out));
  PetscCall(PetscStrncpy(o->restart, in->restart, sizeof o->restart));
  o->quiet               = in->quiet;
  o->output_every        = in->output_every;
  o->output_te_every     = in->output_te_every;
  o->output_tear_every   = in->output_tear_every;
  o->checkpoint_every    = in->checkpoint_every;
  o->checkpoint_every_te = in->checkpoint_every_te;
  o->checkpoint_every_s  = in->checkpoint_every_s;
  PetscCheck(!o->checkpoint_every || o->output_dir[0], comm, PETSC_ERR_USER_INPUT,
             "-checkpoint_every %" PetscInt_FMT " needs an output directory: -output_dir is none", o->checkpoint_every);
  PetscCheck(!o->checkpoint_every_te || o->output_dir[0], comm, PETSC_ERR_USER_INPUT,
             "-checkpoint_every_te %" PetscInt_FMT " needs an output directory: -output_dir is none",
             o->checkpoint_every_te);
  PetscCheck(o->checkpoint_every_s == 0 || o->output_dir[0], comm, PETSC_ERR_USER_INPUT,
             "-checkpoint_every_s %g needs an output directory: -output_dir is none", (double) o->checkpoint_every_s);
  if (!o->output_dir[0]) { /* frames typed with no directory to write them to (a scene's frames: left unwritten) */
    static const char *const frames[] = {"-output_every", "-output_te_every", "-output_tear_every"};
    const PetscInt           every[]  = {in->output_every, in->output_te_every, in->output_tear_every};
    for (size_t k = 0; k < sizeof frames / sizeof frames[0]; k++) {
      char      value[64] = "";
      PetscBool set, user;
      PetscCall(PetscOptionsGetString(NULL, NULL, frames[k], value, sizeof value, &set));
      if (!set || every[k] == 0) continue; /* 0: no frames, as none are written */
      PetscCall(GivenByUser(comm, frames[k], &user));
      PetscCheck(!user, comm, PETSC_ERR_USER_INPUT, "%s %s writes frames of fabric.h5, but -output_dir is none; leave it out",
                 frames[k], value);
    }
  }
  if (o->restart[0]) PetscCall(SceneCheckReadable(comm, "-restart", o->restart));
  PetscFunctionReturn(0);
}

/* the options that set the grid's width, and their values: -yarns (the strip's, when given) or -width_mm; the bias test's
   -jaw_depth_mm too (its grid holds the jaws) */
PetscErrorCode SceneWidthText(const SceneInput *in, const char *real_fmt, char *text, size_t len)
{
  char fmt[32];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(fmt, sizeof fmt, "-width_mm %s", real_fmt));
  if (in->test == TEST_STRIP && in->yarns > 0) PetscCall(PetscSNPrintf(text, len, "-yarns %" PetscInt_FMT, in->yarns));
  else PetscCall(PetscSNPrintf(text, len, fmt, (double) in->width_mm));
  if (in->test == TEST_BIAS) { /* the bias grid holds the jaws too */
    size_t at = strlen(text);
    PetscCall(PetscSNPrintf(fmt, sizeof fmt, " -jaw_depth_mm %s", real_fmt));
    PetscCall(PetscSNPrintf(text + at, len - at, fmt, (double) in->jaw_depth_mm));
  }
  PetscFunctionReturn(0);
}

/* The grid's size: PETSc's DMDA holds 3 unknowns (x, y, z) per crossing and indexes them with 32-bit
   integers, so 3 nx ny must stay below 2^31 - 1 (about 7.16e8 crossings) */
#define GRID_MAX_CROSSINGS 7e8
static PetscErrorCode CheckGridSize(MPI_Comm comm, const SceneInput *in, PetscReal nx, PetscReal ny)
{
  char width[64];

  PetscFunctionBeginUser;
  PetscCall(SceneWidthText(in, "%.6g", width, sizeof width));
  PetscCheck(nx * ny <= GRID_MAX_CROSSINGS, comm, PETSC_ERR_USER_INPUT,
             "grid too large: -gauge_mm %.6g, %s at -ends_per_cm %.6g, -picks_per_cm %.6g give %.6g x "
             "%.6g = %.6g crossings, at most %.6g (3 unknowns each, within PETSc's 32-bit indices)",
             (double) in->gauge_mm, width, (double) in->ends_per_cm, (double) in->picks_per_cm,
             (double) nx, (double) ny, (double) (nx * ny), GRID_MAX_CROSSINGS);
  PetscFunctionReturn(0);
}

/* the grid of crossings that the test, shape and size give (nx x ny), with the gauge length,
   width and jaw depth rounded to it */
static PetscErrorCode DeriveGrid(MPI_Comm comm, const SceneInput *in, Scene *s)
{
  const PetscReal ends_cm = in->ends_per_cm, picks_cm = in->picks_per_cm, gauge_mm = in->gauge_mm,
                  width_mm = in->width_mm;
  const PetscReal jaw_mm = in->jaw_depth_mm, disc_mm = in->disc_diameter_mm;
  const PetscBool ring_set   = in->n_clamp_ring_mm > 0 ? PETSC_TRUE : PETSC_FALSE;
  /* no ring unless set: the drape's 0,180 (Cusick's 18 cm disc) is the option's default by test, RingByTest */
  const PetscReal ring_mm[2] = {ring_set ? in->clamp_ring_mm[0] : 0.0, ring_set ? in->clamp_ring_mm[1] : 0.0};

  PetscFunctionBeginUser;
  s->spec.ends_per_m  = ends_cm * 100.0;
  s->spec.picks_per_m = picks_cm * 100.0;
  s->spec.yarns       = in->yarns;
  s->spec.pull        = (PullAxis) in->pull;
  s->spec.shape       = (ShapeType) in->shape;
  s->clamps.clamp     = (ClampType) in->clamp;
  s->clamps.ring[0]   = 0.5e-3 * ring_mm[0];
  s->clamps.ring[1]   = 0.5e-3 * ring_mm[1];
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
    const PetscReal J = round(0.5e-3 * gauge_mm / h), E = round(0.5e-3 * width_mm / h),
                    Jd = PetscMax(1.0, round(1e-3 * jaw_mm / h));
    const PetscReal n  = J + E + Jd + fmod(Jd, 2.0) + 1;
    PetscCheck(E >= 1 && J > E, comm, PETSC_ERR_USER_INPUT,
               "bias specimen too small or too wide: -gauge_mm %g, -width_mm %g at %g threads/cm (the gauge length "
               "must exceed the width by at least one yarn spacing)",
               (double) gauge_mm, (double) width_mm, (double) picks_cm);
    PetscCall(CheckGridSize(comm, in, n, n));
    s->spec.nx        = (PetscInt) n;
    s->spec.ny        = (PetscInt) n;
    s->spec.gauge     = 2 * J * h; /* free length between the jaws, along the specimen */
    s->spec.width     = 2 * E * h;
    s->spec.jaw_depth = Jd * h;
  } else if (s->test == TEST_BIAS) { /* unequal densities: the diagonals are not at 45 degrees */
    const PetscReal side = (gauge_mm + 2 * jaw_mm + width_mm) * 1e-3 / PetscSqrtReal(2.0);
    const PetscReal nx = round(side * s->spec.picks_per_m) + 1, ny = round(side * s->spec.ends_per_m) + 1;
    PetscCheck(width_mm < gauge_mm, comm, PETSC_ERR_USER_INPUT,
               "bias specimen too wide: -gauge_mm %g, -width_mm %g (the gauge length must exceed the width)",
               (double) gauge_mm, (double) width_mm);
    PetscCheck(nx >= 5 && ny >= 5, comm, PETSC_ERR_USER_INPUT,
               "bias specimen too small: -gauge_mm %g, -width_mm %g at -ends_per_cm %g, -picks_per_cm %g give %g x %g "
               "crossings (at least 5 a side)",
               (double) gauge_mm, (double) width_mm, (double) ends_cm, (double) picks_cm, nx, ny);
    PetscCheck(1e-3 * width_mm >= LargestSpacing(s->spec.ends_per_m, s->spec.picks_per_m), comm, PETSC_ERR_USER_INPUT,
               "bias specimen too narrow: -width_mm %g at -ends_per_cm %g, -picks_per_cm %g is less than a yarn spacing "
               "(%g mm)",
               (double) width_mm, (double) ends_cm, (double) picks_cm,
               1e3 * (double) LargestSpacing(s->spec.ends_per_m, s->spec.picks_per_m));
    PetscCall(CheckGridSize(comm, in, nx, ny));
    s->spec.nx        = (PetscInt) nx;
    s->spec.ny        = (PetscInt) ny;
    s->spec.gauge     = gauge_mm * 1e-3; /* free length between the jaws, along the specimen */
    s->spec.width     = width_mm * 1e-3;
    s->spec.jaw_depth = jaw_mm * 1e-3;
  } else if (s->test != TEST_STRIP) { /* a gauge x width net with crossings on all four edges */
    const PetscReal nx = round(gauge_mm * 1e-3 * s->spec.picks_per_m) + 1,
                    ny = round(width_mm * 1e-3 * s->spec.ends_per_m) + 1;
    PetscCheck(nx >= 3 && ny >= 3, comm, PETSC_ERR_USER_INPUT,
               "grid too small: -gauge_mm %g x -width_mm %g gives %g x %g crossings, at least 3 x 3 are needed",
               (double) gauge_mm, (double) width_mm, nx, ny);
    PetscCall(CheckGridSize(comm, in, nx, ny));
    s->spec.nx          = (PetscInt) nx;
    s->spec.ny          = (PetscInt) ny;
    s->spec.gauge       = (nx - 1) / s->spec.picks_per_m;
    s->spec.width       = (ny - 1) / s->spec.ends_per_m;
    s->spec.disc_radius = disc_mm > 0 ? 0.5e-3 * disc_mm : 0.5 * PetscMin(s->spec.gauge, s->spec.width);
    /* a disc wider than the grid (by more than the rounding of the grid to its crossings) would be cut square */
    PetscCheck(s->spec.shape != SHAPE_DISC ||
                   2 * s->spec.disc_radius <= PetscMin(s->spec.gauge, s->spec.width) +
                                                  1 / PetscMin(s->spec.picks_per_m, s->spec.ends_per_m),
               comm, PETSC_ERR_USER_INPUT,
               "-disc_diameter_mm %g is wider than the grid, %g x %g mm (-gauge_mm %g, -width_mm %g): the disc would "
               "be cut square; make the grid at least as large as the disc",
               (double) disc_mm, 1e3 * (double) s->spec.gauge, 1e3 * (double) s->spec.width, (double) gauge_mm,
               (double) width_mm);
  } else {
    const PetscReal along_density  = s->spec.pull == PULL_WARP ? s->spec.picks_per_m : s->spec.ends_per_m;
    const PetscReal across_density = s->spec.pull == PULL_WARP ? s->spec.ends_per_m : s->spec.picks_per_m;
    const PetscReal n_along        = round(gauge_mm * 1e-3 * along_density) + 1;
    const PetscReal n_across = s->spec.yarns ? (PetscReal) s->spec.yarns : round(width_mm * 1e-3 * across_density);
    PetscCheck(n_along >= 3, comm, PETSC_ERR_USER_INPUT,
               "grid too small: -gauge_mm %g at %g threads/cm gives %g crossings along the pull, at least 3 are needed",
               (double) gauge_mm, (double) (along_density / 100), (double) n_along);
    PetscCheck(n_across >= 1, comm, PETSC_ERR_USER_INPUT,
               "grid too small: -width_mm %g at %g threads/cm gives no yarn across the strip", (double) width_mm,
               (double) (across_density / 100));
    PetscCall(CheckGridSize(comm, in, n_along, n_across));
    s->spec.nx    = (PetscInt) (s->spec.pull == PULL_WARP ? n_along : n_across);
    s->spec.ny    = (PetscInt) (s->spec.pull == PULL_WARP ? n_across : n_along);
    s->spec.gauge = (n_along - 1) / along_density;
    s->spec.width = n_across / across_density;
  }
  if (!in->n_point_load_at) {
    s->load.load_at[0] = s->spec.nx / 2;
    s->load.load_at[1] = s->spec.ny / 2;
  }
  PetscCheck(s->load.load_at[0] >= 0 && s->load.load_at[0] < s->spec.nx && s->load.load_at[1] >= 0 &&
                 s->load.load_at[1] < s->spec.ny,
             comm, PETSC_ERR_USER_INPUT,
             "-point_load_at %" PetscInt_FMT ",%" PetscInt_FMT " is outside the %" PetscInt_FMT " x %" PetscInt_FMT
             " grid",
             s->load.load_at[0], s->load.load_at[1], s->spec.nx, s->spec.ny);
  PetscFunctionReturn(0);
}

/* ---------------- the output places ---------------- */

/* Can the directory path be made and written into? What is missing is made (mkdir -p), a probe
   file is written and removed, then what was made is removed again: nothing is left behind,
   and a path under a file, on a read-only or a pseudo file system (/proc, where even root
   cannot write) is refused before any computation. msg: "" or why not. */
/* what ProbeDirectory made: the directories (their lengths in path) and the probe file, for ProbeUndo */
typedef struct {
  char   path[PETSC_MAX_PATH_LEN], probe[PETSC_MAX_PATH_LEN + 32];
  size_t made[64];
  int    nmade;
} ProbeMade;

/* Makes the directory path (mkdir -p) and writes a probe file in it, both left for the other ranks to see
   (ProbeUndo removes them); msg: "" or why not */
static void ProbeDirectory(const char *opt, const char *path, ProbeMade *pm, char *msg, size_t len)
{
  char        *buf = pm->path;
  size_t       n   = strlen(path);
  int          fd;
  struct stat  st;

  msg[0] = 0;
  pm->nmade = 0, pm->probe[0] = 0;
  if (n >= sizeof pm->path) {
    snprintf(msg, len, "-%s %s: path too long", opt, path);
    return;
  }
  memcpy(buf, path, n + 1);
  for (size_t at = 1; at <= n && !msg[0]; at++) { /* each leading part of the path, then the whole */
    if (at < n && buf[at] != '/') continue;
    buf[at] = 0;
    if (!stat(buf, &st)) {
      if (!S_ISDIR(st.st_mode)) snprintf(msg, len, "-%s %s: %s is not a directory", opt, path, buf);
    } else if (errno != ENOENT || mkdir(buf, 0755))
      snprintf(msg, len, "-%s %s: cannot create the directory %s (%s)", opt, path, buf, strerror(errno));
    else if (pm->nmade < 64)
      pm->made[pm->nmade++] = at;
    buf[at] = at < n ? '/' : 0;
  }
  if (!msg[0]) {
    snprintf(pm->probe, sizeof pm->probe, "%s/.fabric_probe_%d", path, (int) getpid());
    fd = open(pm->probe, O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd < 0 || write(fd, "\n", 1) != 1)
      snprintf(msg, len, "-%s %s: cannot write in the directory (%s)", opt, path, strerror(errno));
    if (fd >= 0) close(fd);
    if (fd < 0) pm->probe[0] = 0;
  }
}

/* removes what ProbeDirectory made: the probe file, then the directories, deepest first */
static void ProbeUndo(ProbeMade *pm)
{
  if (pm->probe[0]) unlink(pm->probe);
  for (int k = pm->nmade - 1; k >= 0; k--) {
    pm->path[pm->made[k]] = 0;
    (void) rmdir(pm->path);
  }
  pm->nmade = 0, pm->probe[0] = 0;
}

/* Every rank sees rank 0's probe file in -output_dir and can write beside it: parallel HDF5 writes one
   file from every rank (a directory on a node's own disk, or a relative path from another working
   directory, left the ranks waiting in MPI_File_open for ever). Rank 0 keeps its probe until all have
   looked; a look is tried for a second (a network file system may show a new file late). */
static PetscErrorCode ProbeShared(MPI_Comm comm, const char *dir, const ProbeMade *pm, char *msg, size_t len)
{
  char        probe[sizeof pm->probe];
  PetscMPIInt rank;
  int         mine = INT_MAX, first; /* (rank * 2 + what) * 4096 + errno; what: 0 not seen, 1 not writable */

  PetscFunctionBeginUser;
  PetscCall(CommRank(comm, &rank));
  if (!rank) memcpy(probe, pm->probe, sizeof probe);
  PetscCall(BroadcastFromRoot(comm, probe, (PetscInt) sizeof probe, MPI_CHAR));
  if (rank) {
    struct stat st;
    int         seen = 0;
    for (int t = 0; t < 20 && !(seen = !stat(probe, &st)); t++) usleep(50000);
    if (!seen) mine = (rank * 2 + 0) * 4096 + (errno & 4095);
    else {
      char own[sizeof probe + 32];
      int  fd;
      snprintf(own, sizeof own, "%s/.fabric_probe_%d_%d", dir, (int) getpid(), (int) rank);
      fd = open(own, O_WRONLY | O_CREAT | O_EXCL, 0644);
      if (fd < 0) mine = (rank * 2 + 1) * 4096 + (errno & 4095);
      else close(fd), unlink(own);
    }
  }
  PetscCallMPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm));
  if (first != INT_MAX)
    snprintf(msg, len,
             "-output_dir %s: rank %d %s (%s): parallel HDF5 writes fabric.h5 from every rank, so the directory must be "
             "one all ranks share (a relative path is taken from each rank's working directory)",
             dir, first / 8192, (first / 4096) % 2 ? "cannot write in it" : "does not see the files rank 0 writes there",
             strerror(first % 4096));
  PetscFunctionReturn(0);
}

static void PlaceOf(const char *path, char *out, size_t len);

/* the directory a file's path names ("." for none) */
static void DirOf(const char *path, char *dir, size_t len)
{
  const char *slash = strrchr(path, '/');
  snprintf(dir, len, "%.*s", slash ? (int) (slash == path ? 1 : slash - path) : 1, slash ? path : ".");
}

/* Is the file's directory the output directory (compared as places)? */
static int InOutputDir(const char *path, const char *output_dir)
{
  char dir[PETSC_MAX_PATH_LEN], a[2 * PETSC_MAX_PATH_LEN], b[2 * PETSC_MAX_PATH_LEN];
  if (!output_dir[0]) return 0;
  DirOf(path, dir, sizeof dir);
  PlaceOf(dir, a, sizeof a);
  PlaceOf(output_dir, b, sizeof b);
  return !strcmp(a, b);
}

/* Can the file be written? Its directory must exist (or be the output directory, made at the
   start of the run); an existing file is opened without being truncated, a new one is made and
   removed. msg: "" or why not. */
void ProbeFile(const char *opt, const char *path, const char *output_dir, char *msg, size_t len)
{
  char        dir[PETSC_MAX_PATH_LEN];
  struct stat st;
  int         fd;

  msg[0] = 0;
  DirOf(path, dir, sizeof dir);
  if (!stat(path, &st) && S_ISDIR(st.st_mode)) {
    snprintf(msg, len, "-%s %s: is a directory, not a file", opt, path);
    return;
  }
  if (stat(dir, &st)) {
    const int why = errno; /* before InOutputDir's realpath */
    if (InOutputDir(path, output_dir)) return; /* made by the run: probed with -output_dir */
    snprintf(msg, len, "-%s %s: cannot reach the directory %s (%s)", opt, path, dir, strerror(why));
    return;
  }
  if (!S_ISDIR(st.st_mode)) {
    snprintf(msg, len, "-%s %s: %s is not a directory", opt, path, dir);
    return;
  }
  fd = open(path, O_WRONLY | O_CREAT | O_EXCL, 0644);
  if (fd >= 0) {
    close(fd);
    unlink(path);
    return;
  }
  if (errno == EEXIST) fd = open(path, O_WRONLY | O_NONBLOCK); /* an older result: written over at the end (a pipe
                                                                   with no reader: ENXIO, not a wait for ever) */
  if (fd < 0 && errno == ENXIO) {
    snprintf(msg, len, "-%s %s: a pipe with no reader (the run would wait for one for ever)", opt, path);
    return;
  }
  if (fd >= 0)
    close(fd);
  else
    snprintf(msg, len, "-%s %s: cannot write the file (%s)", opt, path, strerror(errno));
}

/* path made absolute, its longest existing head resolved (realpath), repeated and trailing slashes
   dropped: two names of one place compare equal, whether or not it exists yet */
static void PlaceOf(const char *path, char *out, size_t len)
{
  char   abs[2 * PETSC_MAX_PATH_LEN], real[PATH_MAX];
  size_t n = 0, cut;

  abs[0] = 0;
  if (path[0] != '/' && realpath(".", real)) snprintf(abs, sizeof abs, "%s/", real);
  n = strlen(abs);
  for (const char *c = path; *c && n + 1 < sizeof abs; c++) /* repeated slashes as one */
    if (!(*c == '/' && n > 0 && abs[n - 1] == '/')) abs[n++] = *c;
  abs[n] = 0;
  for (; n > 1 && abs[n - 1] == '/'; n--) abs[n - 1] = 0;
  for (cut = n; cut > 0; cut--) { /* the longest existing head: abs[0, cut) */
    if (cut < n && abs[cut] != '/') continue;
    char head[2 * PETSC_MAX_PATH_LEN];
    snprintf(head, sizeof head, "%.*s", (int) cut, abs);
    if (realpath(head, real)) {
      snprintf(out, len, "%s%s", real, abs + cut);
      return;
    }
  }
  snprintf(out, len, "%s", abs);
}

/* the files a run writes in -output_dir, and its lock (OutputDirLock) */
static const char *const OwnFiles[] = {"curve.csv",     "summary.json",       "fabric.h5",         "fabric.xmf",
                                       "checkpoint.h5", ".checkpoint.h5.tmp", ".summary.json.tmp", ".fabric.xmf.tmp",
                                       ".fabric.lock"};

/* path and other are one file: the same device and inode when both exist (any spelling, a link),
   else the same place (PlaceOf) */
static int SameFile(const char *path, const char *other)
{
  struct stat a, b;
  char        p[2 * PETSC_MAX_PATH_LEN], q[2 * PETSC_MAX_PATH_LEN];

  if (!path[0] || !other[0]) return 0;
  if (!stat(path, &a) && !stat(other, &b)) return a.st_dev == b.st_dev && a.st_ino == b.st_ino;
  PlaceOf(path, p, sizeof p);
  PlaceOf(other, q, sizeof q);
  return !strcmp(p, q);
}

/* the run's input files, each with its option ("" when not given); -restart last */
typedef struct {
  const char *opt, *file;
} InputFile;
#define INPUT_FILES 4
static void InputFiles(const Scene *s, InputFile input[INPUT_FILES])
{
  input[0] = (InputFile){"scene", s->out.file};
  input[1] = (InputFile){"warp_law_csv", s->yarns.warp.csv};
  input[2] = (InputFile){"weft_law_csv", s->yarns.weft.csv};
  input[3] = (InputFile){"restart", s->out.restart};
}

/* no input file may be one the run writes in -output_dir: it would be removed at the start (summary.json,
   fabric.h5, ...) or written over (curve.csv); not -restart, whose DIR/checkpoint.h5 the run goes on from
   (RestartsFrom) */
static void InputOutputClash(const Scene *s, char *msg, size_t len)
{
  const SceneOutput *o = &s->out;
  InputFile          input[INPUT_FILES];
  char               f[3 * PETSC_MAX_PATH_LEN];

  if (!o->output_dir[0]) return;
  InputFiles(s, input);
  for (size_t k = 0; k < INPUT_FILES - 1; k++)
    for (size_t q = 0; input[k].file[0] && q < sizeof OwnFiles / sizeof OwnFiles[0]; q++) {
      snprintf(f, sizeof f, "%s/%s", o->output_dir, OwnFiles[q]);
      if (SameFile(input[k].file, f)) {
        snprintf(msg, len,
                 "-%s %.1024s: the run writes its %s there (-output_dir %.1024s): the input file would be removed "
                 "or written over; give another -output_dir, or rename the file",
                 input[k].opt, input[k].file, OwnFiles[q], o->output_dir);
        return;
      }
    }
}

/* a directory in -output_dir under the name of a file the run writes there: the write would fail at that file's
   first frame, checkpoint or end, with the run's other results written */
static void OwnFileIsDirectory(const SceneOutput *o, char *msg, size_t len)
{
  char        f[3 * PETSC_MAX_PATH_LEN];
  struct stat st;

  if (!o->output_dir[0]) return;
  for (size_t q = 0; q < sizeof OwnFiles / sizeof OwnFiles[0]; q++) {
    snprintf(f, sizeof f, "%s/%s", o->output_dir, OwnFiles[q]);
    if (!stat(f, &st) && S_ISDIR(st.st_mode)) {
      snprintf(msg, len, "-output_dir %.1024s: %.1024s is a directory, where the run writes its %s; remove it or give "
               "another -output_dir", o->output_dir, f, OwnFiles[q]);
      return;
    }
  }
}

/* a file the run or PETSc writes (-positions_out, a viewer's -log_view :FILE, -snes_monitor :FILE, ...), given as
   -opt value, must not be one of the run's input files (written over), the output directory, a file the run writes in
   it, or the run's -positions_out: written over, curve.csv was PETSc's profile and fabric.h5 no HDF5, with the run's
   end line saying all was well */
static void WrittenFileClash(const Scene *s, const char *opt, const char *value, const char *file, char *msg, size_t len)
{
  const SceneOutput *o = &s->out;
  InputFile          input[INPUT_FILES];
  char               f[3 * PETSC_MAX_PATH_LEN];

  InputFiles(s, input);
  for (size_t k = 0; k < INPUT_FILES; k++)
    if (SameFile(file, input[k].file)) {
      snprintf(msg, len, "-%s %s: is the run's input file -%s %s: it would be written over; give another file", opt,
               value, input[k].opt, input[k].file);
      return;
    }
  if (o->output_dir[0]) {
    if (SameFile(file, o->output_dir)) {
      snprintf(msg, len, "-%s %s: is the output directory (-output_dir %s); give a file", opt, value, o->output_dir);
      return;
    }
    for (size_t k = 0; k < sizeof OwnFiles / sizeof OwnFiles[0]; k++) {
      snprintf(f, sizeof f, "%s/%s", o->output_dir, OwnFiles[k]);
      if (SameFile(file, f)) {
        snprintf(msg, len, "-%s %s: the run writes its %s there (-output_dir %s); give another file", opt, value,
                 OwnFiles[k], o->output_dir);
        return;
      }
    }
  }
  if (strcmp(opt, "positions_out") && SameFile(file, o->positions_out))
    snprintf(msg, len, "-%s %s: the run writes its final positions there (-positions_out); give another file", opt,
             value);
}

/* an option's name, not a value (PETSc's rule: "-5" and "-.5" are values) */
static int IsOptionName(const char *tok)
{
  return tok[0] == '-' && isalpha((unsigned char) tok[1]);
}

int OptionsGivenGet(OptionsGiven *g)
{
  PetscInt cap = 1;

  memset(g, 0, sizeof *g);
  if (PetscOptionsGetAll(NULL, &g->text) || !g->text) return 1;
  for (const char *c = g->text; *c; c++) cap += *c == ' ';
  g->name  = malloc(cap * sizeof *g->name);
  g->value = malloc(cap * sizeof *g->value);
  if (!g->name || !g->value) {
    OptionsGivenFree(g);
    return 1;
  }
  for (char *tok = strtok(g->text, " "); tok;) {
    const char *name = tok;
    tok              = strtok(NULL, " ");
    if (!IsOptionName(name)) continue;
    g->name[g->n]  = name;
    g->value[g->n] = "";
    if (tok && !IsOptionName(tok)) {
      g->value[g->n] = tok;
      tok            = strtok(NULL, " ");
    }
    g->n++;
  }
  return 0;
}

void OptionsGivenFree(OptionsGiven *g)
{
  free(g->name);
  free(g->value);
  PetscFree(g->text);
  memset(g, 0, sizeof *g);
}

void SolverOptionsGiven(char *buf, size_t len)
{
  OptionsGiven g;
  size_t       at = 0;

  buf[0] = 0;
  if (len < 64 || OptionsGivenGet(&g)) return;
  for (PetscInt q = 0; q < g.n && at < len - 32; q++) {
    const char *nm = g.name[q];
    if (!(strstr(nm, "ksp_") || strstr(nm, "pc_") || strstr(nm, "snes_") || strstr(nm, "tao_"))) continue;
    at += (size_t) snprintf(buf + at, len - at, "%s%s%s%s", at ? " " : "", nm, g.value[q][0] ? " " : "", g.value[q]);
  }
  OptionsGivenFree(&g);
  if (at >= len - 32) snprintf(buf + len - 32, 32, " ...");
}

PetscBool OptionIs(const char *name, const char *suffix)
{
  const size_t n = strlen(name), ls = strlen(suffix);
  return n > ls && !strcmp(name + n - ls, suffix) && (name[n - ls - 1] == '-' || name[n - ls - 1] == '_')
             ? PETSC_TRUE
             : PETSC_FALSE;
}

/* an option PETSc reads as a viewer ([type][:file[:format[:mode]]]): -log_view and the solvers' viewers and
   monitors, under any prefix (-mg_levels_ksp_monitor); PETSc has switches that end alike (-snes_qn_monitor,
   -ksp_gmres_krylov_monitor: true or false), so only these */
static int ViewerOption(const char *name)
{
  static const char *const viewer[] = {"snes_view",   "ksp_view",   "pc_view",    "tao_view",   "dm_view",
                                       "mat_view",    "vec_view",   "snes_monitor", "ksp_monitor", "tao_monitor",
                                       "snes_monitor_short", "ksp_monitor_short", "ksp_monitor_true_residual",
                                       "snes_converged_reason", "ksp_converged_reason", "snes_linesearch_monitor",
                                       "snes_monitor_solution", "snes_monitor_solution_update", "snes_monitor_residual",
                                       "ksp_monitor_solution"};
  if (!strcmp(name, "log_view")) return 1;
  for (size_t k = 0; k < sizeof viewer / sizeof viewer[0]; k++)
    if (!strcmp(name, viewer[k]) || OptionIs(name, viewer[k])) return 1;
  return 0;
}

/* What PETSc's viewer parser (PetscOptionsGetViewer) would refuse in the value of option -name, said in msg; 0: nothing,
   or not a viewer option. Plain C: main.c asks it before PetscInitialize parses -log_view's (a traceback and an abort
   there, and a value it cannot take stopped the run where it was read: -log_view's at the very end). */
int ViewerValueProblem(const char *name, const char *value, char *msg, size_t len)
{
  static const char *const viewers[] = {"ascii", "binary", "draw", "socket", "matlab", "saws", "vtk", "hdf5",
                                        "glvis", "exodusii"};
  const char  *colon = strchr(value, ':'), *fmt = colon ? strchr(colon + 1, ':') : NULL, *mode;
  const size_t tl    = colon ? (size_t) (colon - value) : strlen(value);
  const int    draw  = tl >= 4 && !strncmp(value + tl - 4, "draw", 4);
  const int    drawn = draw && colon && (!strncmp(colon + 1, "tikz", 4) || !strncmp(colon + 1, "image", 5)); /* to a file */
  char         f[256];
  int          found = tl ? 0 : 1;

  if (!value[0] || !ViewerOption(name)) return 0;
  for (size_t k = 0; k < sizeof viewers / sizeof viewers[0] && !found; k++) /* PETSc: the type ends with one */
    found = tl >= strlen(viewers[k]) && !strncmp(value + tl - strlen(viewers[k]), viewers[k], strlen(viewers[k]));
  if (!found) {
    snprintf(msg, len, "-%s %s: '%.*s' is not a PETSc viewer (the value is [type][:file[:format]], type ascii, binary, "
             "draw, vtk or hdf5; -%s alone prints to the screen)", name, value, (int) tl, value, name);
    return 1;
  }
  if (draw && !drawn) {
    const char *display = getenv("DISPLAY"); /* PETSc's X11 window: "Unable to open display", a traceback */
    if (!(display && display[0])) {
      snprintf(msg, len, "-%s %s: a draw viewer opens an X window, and DISPLAY is not set; give a display, or "
               "draw:tikz:FILE or draw:image:FILE", name, value);
      return 1;
    }
  }
  snprintf(f, sizeof f, "%.*s", fmt ? (int) strcspn(fmt + 1, ":") : 0, fmt ? fmt + 1 : "");
  if (drawn) return 0; /* draw:tikz:FILE, draw:image:FILE: the third field is a file */
  found = !f[0];
  for (int k = 0; PetscViewerFormats[k] && k < 64 && !found; k++) /* the names, then the enum's name and prefix */
    found = !strcasecmp(PetscViewerFormats[k], f);
  if (!found) {
    snprintf(msg, len, "-%s %s: '%s' is not a PETSc viewer format (as default, ascii_info, ascii_info_detail, "
             "ascii_matlab)", name, value, f);
    return 1;
  }
  mode = fmt ? strchr(fmt + 1, ':') : NULL; /* the fourth field, the file's mode: PETSc's "Unknown file mode" named
                                               no option, and read mode cannot write */
  if (!mode || !mode[1] || !strcasecmp(mode + 1, "write") || !strcasecmp(mode + 1, "append") ||
      !strcasecmp(mode + 1, "update") || !strcasecmp(mode + 1, "append_update"))
    return 0;
  snprintf(msg, len, "-%s %s: '%s' is not a file mode a viewer can write with (write, the default, or append)", name,
           value, mode + 1);
  return 1;
}

/* A PETSc viewer option that names a file ([type]:file[:format], -log_view :log.txt, -snes_monitor
   :snes.txt, -ksp_view_mat binary:A.bin): PETSc opens it only when it first writes, -log_view's at
   the very end of a run, and a rank that cannot open it stops alone, so look now. PETSc opens the
   others as the grid and the solvers are made, before the run makes its output directory: only
   -log_view's file may be in it. msg: "" or why a file cannot be written. */
static void ProbeViewerFiles(const Scene *s, char *msg, size_t len)
{
  const char *output_dir = s->out.output_dir;
  static const char *const types[] = {"", "ascii", "binary", "hdf5", "vtk"};
  OptionsGiven             g;

  msg[0] = 0;
  if (OptionsGivenGet(&g)) return;
  for (PetscInt q = 0; q < g.n && !msg[0]; q++) {
    const char *name = g.name[q] + 1, *value = g.value[q], *colon = strchr(value, ':');
    const int   log = !strcmp(name, "log_view");
    char        file[PETSC_MAX_PATH_LEN];
    int         known = 0;
    if (ViewerValueProblem(name, value, msg, len)) break;
    if (!colon || (!strstr(name, "_view") && !strstr(name, "monitor") && !OptionIs(g.name[q], "converged_reason")))
      continue;
    for (size_t k = 0; k < sizeof types / sizeof types[0]; k++)
      known |= (size_t) (colon - value) == strlen(types[k]) && !strncmp(value, types[k], strlen(types[k]));
    if (log && colon != value && strncmp(value, "ascii:", 6)) { /* PETSc's profile is text: it failed at the end */
      snprintf(msg, len, "-log_view %s: the profile is written as text only (ascii, the default: -log_view :FILE)",
               value);
      break;
    }
    snprintf(file, sizeof file, "%.*s", (int) strcspn(colon + 1, ":"), colon + 1);
    if (!known || !file[0] || !strcmp(file, "stdout") || !strcmp(file, "stderr")) continue; /* ascii's streams */
    WrittenFileClash(s, name, value, file, msg, len);
    if (msg[0]) break;
    ProbeFile(name, file, log ? output_dir : "", msg, len);
    if (msg[0] && !log && InOutputDir(file, output_dir))
      snprintf(msg + strlen(msg), len - strlen(msg),
               ": PETSc opens it before the run makes -output_dir (only -log_view's file may be in it)");
  }
  OptionsGivenFree(&g);
}

/* PETSc's file viewers (fabric.h5, checkpoint.h5, -restart, -positions_out) expand '${NAME}' in a file name from
   the environment, where the run's own files (curve.csv, summary.json) take it as it is: refused (given_dir: -output_dir
   as given, "" for the default results/NAME, named after the scene file) */
static void ViewerNameClash(const SceneOutput *o, const char *given_dir, char *msg, size_t len)
{
  const struct {
    const char *opt, *path;
  } place[] = {
    {"output_dir",    o->output_dir   },
    {"positions_out", o->positions_out},
    {"restart",       o->restart      },
  };

  if (!given_dir[0] && strstr(o->output_dir, "${")) { /* the scene's name, not an -output_dir given */
    snprintf(msg, len,
             "-scene %.1024s: its output directory, %.1024s (named after the scene file: no -output_dir given), holds "
             "'${': PETSc's file viewers, which write fabric.h5 and checkpoint.h5, take '${...}' in a file name for an "
             "environment variable; give -output_dir",
             o->file, o->output_dir);
    return;
  }
  for (size_t k = 0; k < sizeof place / sizeof place[0]; k++)
    if (strstr(place[k].path, "${")) {
      snprintf(msg, len,
               "-%s %.1024s: PETSc's file viewers, which write fabric.h5, checkpoint.h5 and -positions_out and read "
               "-restart, take '${...}' in a file name for an environment variable; give the path without it",
               place[k].opt, place[k].path);
      return;
    }
}

/* One run per output directory: two runs writing into one would mix their files, and the first
   would still report success. Rank 0 holds a write lock on DIR/.fabric.lock while the run lasts
   (report.c takes it as the run opens its outputs; the set-up looks, so a refused run reads and
   removes nothing there). The system drops it when the run ends, however it ends: no stale lock
   after a crash. A lock file that cannot be made or opened, or a file system without locks, is let be. */
int OutputDirLock(const char *dir, FILE **take)
{
  char         file[PETSC_MAX_PATH_LEN];
  struct flock fl;
  int          fd, held;

  if (snprintf(file, sizeof file, "%s/.fabric.lock", dir) >= (int) sizeof file) return 0;
  memset(&fl, 0, sizeof fl);
  fl.l_type   = F_WRLCK;
  fl.l_whence = SEEK_SET; /* the whole file: l_start 0, l_len 0 */
  if (take) { /* e, O_CLOEXEC: not inherited by a child process */
    if (!(*take = fopen(file, "ae"))) return 0;
    return fcntl(fileno(*take), F_SETLK, &fl) && (errno == EACCES || errno == EAGAIN);
  }
  if ((fd = open(file, O_RDONLY | O_CLOEXEC)) < 0) return 0; /* none: no run has written there, or none is */
  held = !fcntl(fd, F_GETLK, &fl) && fl.l_type != F_UNLCK;
  close(fd);
  return held;
}

/* PETSc keeps an error message's first 1023 characters: a longer one (a path of a few kB, once or twice) lost its
   reason. Each word longer than 2 x 100 bytes, longest first (a path), keeps its first and last 100 with "..."
   between, until the message fits (cut at UTF-8 characters' starts); the middle of what is still too long goes */
static void CutBytes(char *msg, size_t from, size_t to, const char *mark)
{
  const size_t n = strlen(msg), m = strlen(mark);
  while (from > 0 && ((unsigned char) msg[from] & 0xC0) == 0x80) from--; /* not inside a character */
  while (to < n && ((unsigned char) msg[to] & 0xC0) == 0x80) to++;
  memmove(msg + from + m, msg + to, n - to + 1);
  memcpy(msg + from, mark, m);
}

static void FitErrorMessage(char *msg)
{
  const size_t most = 960, keep = 100;
  while (strlen(msg) > most) {
    size_t at = 0, len = 0;
    for (size_t i = 0, w; msg[i]; i += w ? w : 1) { /* the longest word */
      w = strcspn(msg + i, " ");
      if (w > len) at = i, len = w;
    }
    if (len <= 2 * keep + 3) break;
    CutBytes(msg, at + keep, at + len - keep, "...");
  }
  if (strlen(msg) > most) CutBytes(msg, most / 2, strlen(msg) - most / 2, " ... ");
}

/* -output_dir, -positions_out and the viewers' files can be written: rank 0 looks, every rank refuses alike */
static PetscErrorCode CheckOutputPlaces(MPI_Comm comm, const SceneInput *in, const Scene *s)
{
  const SceneOutput *o = &s->out;
  ProbeMade   pm = {.nmade = 0};
  char        msg[2 * PETSC_MAX_PATH_LEN + 128] = "";
  PetscMPIInt rank;
  PetscBool   help;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  if (help) PetscFunctionReturn(0); /* -help writes nothing */
  PetscCall(CommRank(comm, &rank));
  if (!rank) ViewerNameClash(o, in->output_dir, msg, sizeof msg);
  if (!rank && !msg[0] && o->positions_out[0])
    WrittenFileClash(s, "positions_out", o->positions_out, o->positions_out, msg, sizeof msg);
  if (!rank && !msg[0]) InputOutputClash(s, msg, sizeof msg);
  if (!rank && !msg[0]) OwnFileIsDirectory(o, msg, sizeof msg);
  if (!rank && !msg[0] && o->output_dir[0] && OutputDirLock(o->output_dir, NULL))
    snprintf(msg, sizeof msg, OUTPUT_DIR_BUSY, o->output_dir, o->output_dir);
  if (!rank && !msg[0] && o->output_dir[0]) ProbeDirectory("output_dir", o->output_dir, &pm, msg, sizeof msg);
  PetscCall(BroadcastFromRoot(comm, msg, (PetscInt) sizeof msg, MPI_CHAR));
  if (!msg[0] && o->output_dir[0]) PetscCall(ProbeShared(comm, o->output_dir, &pm, msg, sizeof msg));
  if (!rank) ProbeUndo(&pm);
  if (!rank && !msg[0] && o->positions_out[0]) {
    struct stat st;
    if (!stat(o->positions_out, &st) && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode)) /* /dev/full failed after the run */
      snprintf(msg, sizeof msg, "-positions_out %s: not a regular file (a device, a pipe or a socket); give a file",
               o->positions_out);
    else ProbeFile("positions_out", o->positions_out, o->output_dir, msg, sizeof msg);
  }
  if (!rank && !msg[0]) ProbeViewerFiles(s, msg, sizeof msg);
  PetscCall(BroadcastFromRoot(comm, msg, (PetscInt) sizeof msg, MPI_CHAR));
  FitErrorMessage(msg);
  PetscCheck(!msg[0], comm, PETSC_ERR_FILE_OPEN, "%s", msg);
  PetscFunctionReturn(0);
}

/* the scatter of each family's breaking strain, for its segments' rest chord */
static PetscErrorCode DeriveBreaks(MPI_Comm comm, const SceneInput *in, Scene *s)
{
  PetscFunctionBeginUser;
  for (int f = 0; f < 2; f++) {
    YarnLaw *y = f == 0 ? &s->yarns.warp : &s->yarns.weft;
    PetscCheck(in->yarn[f].break_cv_pct == 0 || in->yarn[f].break_pct > 0, comm, PETSC_ERR_USER_INPUT,
               "-%s_break_cv_pct %.6g needs a breaking strain: -%s_break_pct is 0 (never breaks)", y->name,
               (double) in->yarn[f].break_cv_pct, y->name);
    y->break_cv    = in->yarn[f].break_cv_pct / 100.0;
    y->break_gauge = in->break_gauge_mm * 1e-3;
    PetscCall(YarnBreakSetUp(y, f == 0 ? 1.0 / s->spec.picks_per_m : 1.0 / s->spec.ends_per_m, comm));
  }
  PetscFunctionReturn(0);
}

/* -sf_type, PETSc's type of the star forests every exchange runs on: basic (its default), neighbor, and window (which
   this MPI may not run: main.c names the option then) serve any graph. The others are for all-to-all patterns: on the
   grid's halo exchanges allgather and gather corrupted the heap, gatherv and allgatherv crashed and alltoall hung.
   The static path's line smoother asks its star forests for their leaf ranks, which window does not offer. */
static PetscErrorCode CheckStarForest(MPI_Comm comm, const SceneInput *in)
{
  char      type[64];
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-sf_type", type, sizeof type, &set));
  if (!set) PetscFunctionReturn(0);
  PetscCheck(!strcmp(type, PETSCSFBASIC) || !strcmp(type, PETSCSFNEIGHBOR) || !strcmp(type, PETSCSFWINDOW), comm,
             PETSC_ERR_USER_INPUT, "-sf_type %s: the grid's exchanges run on PetscSF's basic (its default), neighbor or window type%s",
             type,
             strncmp(type, "all", 3) && strncmp(type, "gather", 6) ? "" : " (this one is for all-to-all patterns, not the grid's)");
  PetscCheck(in->solver != SOLVER_STATIC || strcmp(type, PETSCSFWINDOW), comm, PETSC_ERR_USER_INPUT,
             "-sf_type window with -solver static: the multigrid's line smoother asks its exchanges for their ranks, "
             "which PetscSF's window type does not tell; use basic (the default) or neighbor");
  PetscFunctionReturn(0);
}

/* everything the scene's options (s->in) give; a coarse scene (SceneCoarsen) is not checked for options that do
   not apply: its options are the fine scene's, checked there (its yarns do not break, its rupture options stand) */
static PetscErrorCode SceneDerive(MPI_Comm comm, Scene *s, PetscBool coarse)
{
  SceneInput *in = &s->in;

  PetscFunctionBeginUser;
  s->test = (TestType) in->test;
  PetscCall(DeriveOutput(comm, in, s));
  PetscCall(DeriveYarn(comm, &in->yarn[0], "warp", in->scene, &s->yarns.warp));
  PetscCall(DeriveYarn(comm, &in->yarn[1], "weft", in->scene, &s->yarns.weft));
  DeriveNumerics(in, s);
  DeriveTermsAndLoad(in, s);
  PetscCall(DeriveGrid(comm, in, s));
  DeriveRupture(in, s);
  PetscCall(DeriveBreaks(comm, in, s));
  for (int f = 0; f < 2 && !coarse; f++) /* a fraction typed for a percentage (0.065 for 6.5 %) runs, and breaks early */
    if (in->yarn[f].break_pct > 0 && in->yarn[f].break_pct < 0.3)
      PetscCall(PetscPrintf(comm,
                            "fabric: warning: -%s_break_pct %g is a breaking strain of %g %%, below any textile yarn's "
                            "(high-modulus carbon, the lowest, breaks at 0.3 to 0.5 %%, glass at 2 to 5 %%, cotton at 5 to "
                            "10 %%); the option is in %% (6.5 for 6.5 %%)\n",
                            f ? "weft" : "warp", (double) in->yarn[f].break_pct, (double) in->yarn[f].break_pct));
  PetscCall(DeriveBodies(comm, in, s));
  PetscCall(DeriveLines(comm, "clamp_line_mm", in->clamp_line_mm, in->n_clamp_line_mm, &s->clamps.clamp_lines,
                        s->clamps.clamp_line));
  PetscCall(DeriveLines(comm, "grip_line_mm", in->grip_line_mm, in->n_grip_line_mm, &s->clamps.grip_lines,
                        s->clamps.grip_line));
  PetscCall(DerivePath(comm, in, s->spec.gauge, &s->load));
  if (s->rupture.locate > 0 && in->friction_mu > 0) { /* friction follows the path: breaks are located only when asked
                                                         (and then refused, CheckTestOptions) */
    PetscBool typed, set;
    PetscCall(GivenByUser(comm, "-break_locate_pct", &typed));
    PetscCall(PetscOptionsHasName(NULL, NULL, "-break_locate_pct", &set));
    if (!typed) s->rupture.locate = 0;
    if (!typed && set && (s->yarns.warp.break_ey > 0 || s->yarns.weft.break_ey > 0))
      PetscCall(PetscPrintf(comm, "fabric: warning: -break_locate_pct %g (from the scene) is not used with -friction_mu %g: "
                                  "friction depends on the path, and a located break solves the load again from an earlier "
                                  "state; yarns break on each load step's state\n",
                            (double) in->break_locate_pct, (double) in->friction_mu));
  }
  PetscCall(CheckSolverOptions(comm, in, coarse)); /* first: the explicit knobs' own checks would name the wrong cure */
  PetscCall(CheckTestOptions(comm, in, s));
  if (!coarse) PetscCall(CheckOptionsApply(comm, s));
  if (!coarse) PetscCall(CheckStarForest(comm, in));
  PetscCall(CheckOutputPlaces(comm, in, s));
  PetscFunctionReturn(0);
}

PetscErrorCode SceneLoad(MPI_Comm comm, Scene *s)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(s, sizeof *s));
  PetscCall(ReadOptions(comm, &s->in));
  PetscCall(SceneDerive(comm, s, PETSC_FALSE));
  PetscFunctionReturn(0);
}

PetscErrorCode SceneCoarsen(MPI_Comm comm, const Scene *fine, Scene *coarse, PetscBool *fits)
{
  SceneInput     *in     = &coarse->in;
  const PetscReal *f      = fine->load.point_load;
  const PetscBool  loaded = (f[0] != 0 || f[1] != 0 || f[2] != 0) ? PETSC_TRUE : PETSC_FALSE;

  PetscFunctionBeginUser;
  *fits = PETSC_FALSE;
  if (fine->test == TEST_STRIP || fine->test == TEST_BIAS || fine->spec.nx % 2 == 0 || fine->spec.ny % 2 == 0 ||
      (loaded && (fine->load.load_at[0] % 2 || fine->load.load_at[1] % 2)))
    PetscFunctionReturn(0); /* its crossings would not lie on every other one of the fine grid's */
  PetscCall(PetscMemzero(coarse, sizeof *coarse));
  *in = fine->in;
  in->ends_per_cm /= 2;
  in->picks_per_cm /= 2;
  for (int y = 0; y < 2; y++) { /* each coarse yarn is two of the fabric's (a tabulated law's forces too) */
    in->yarn[y].bundle = 2 * PetscMax(in->yarn[y].bundle, 1.0);
    in->yarn[y].tex *= 2;
    in->yarn[y].bending_Nm2 *= 2;
    in->yarn[y].break_pct    = 0; /* a first guess: nothing breaks */
    in->yarn[y].break_cv_pct = 0;
  }
  if (BallPassesBetween(0.5e-3 * in->sphere_diameter_mm, 100.0 * in->ends_per_cm, 100.0 * in->picks_per_cm)) {
    PetscCall(PetscMemzero(coarse, sizeof *coarse));
    PetscFunctionReturn(0); /* the ball would pass between the coarse crossings: no coarser fabric */
  }
  if (in->n_point_load_at) { /* on a coarse crossing when loaded (checked above) */
    in->point_load_at[0] /= 2;
    in->point_load_at[1] /= 2;
  }
  PetscCall(PetscStrncpy(in->output_dir, "none", sizeof in->output_dir));
  in->positions_out[0] = in->restart[0] = 0;
  in->quiet                             = PETSC_TRUE;
  in->output_every = in->output_te_every = in->output_tear_every = 0;
  in->checkpoint_every = in->checkpoint_every_te = 0;
  in->checkpoint_every_s                         = 0;
  PetscCall(SceneDerive(comm, coarse, PETSC_TRUE));
  *fits = (2 * coarse->spec.nx - 1 == fine->spec.nx && 2 * coarse->spec.ny - 1 == fine->spec.ny &&
           (!loaded || (2 * coarse->load.load_at[0] == fine->load.load_at[0] &&
                        2 * coarse->load.load_at[1] == fine->load.load_at[1])))
              ? PETSC_TRUE
              : PETSC_FALSE;
  if (!*fits) PetscCall(SceneDestroy(coarse));
  PetscFunctionReturn(0);
}

PetscErrorCode SceneDestroy(Scene *s)
{
  PetscFunctionBeginUser;
  PetscCall(YarnLawDestroy(&s->yarns.warp));
  PetscCall(YarnLawDestroy(&s->yarns.weft));
  PetscFunctionReturn(0);
}

/* the length of the well-formed UTF-8 sequence at s (lead byte >= 0x80), 0 if it is not one */
static int Utf8Length(const unsigned char *s)
{
  const int n = s[0] >= 0xc2 && s[0] <= 0xdf ? 2 : s[0] >= 0xe0 && s[0] <= 0xef ? 3 : s[0] >= 0xf0 && s[0] <= 0xf4 ? 4 : 0;
  for (int k = 1; k < n; k++)
    if ((s[k] & 0xc0) != 0x80) return 0;
  if ((n == 3 && s[0] == 0xe0 && s[1] < 0xa0) || (n == 3 && s[0] == 0xed && s[1] >= 0xa0) ||
      (n == 4 && s[0] == 0xf0 && s[1] < 0x90) || (n == 4 && s[0] == 0xf4 && s[1] >= 0x90))
    return 0; /* overlong, a surrogate, or beyond U+10FFFF */
  return n;
}

/* a JSON string: quote and backslash escaped, every control character as \u00XX, a byte that is not
   well-formed UTF-8 (a Latin-1 file name) as U+FFFD */
void JsonString(FILE *fp, const char *str)
{
  const unsigned char *s = (const unsigned char *) str;
  fputc('"', fp);
  while (*s) {
    const unsigned char c = *s;
    if (c < 0x20) fprintf(fp, "\\u%04x", (unsigned) c), s++;
    else if (c < 0x80) {
      if (c == '"' || c == '\\') fputc('\\', fp);
      fputc(c, fp), s++;
    } else {
      const int n = Utf8Length(s);
      if (n) fwrite(s, 1, (size_t) n, fp), s += n;
      else fputs("\\ufffd", fp), s++;
    }
  }
  fputc('"', fp);
}

/* every option of the table as JSON members "name": value, one per line after indent (summary.json) */
void SceneOptionsJson(const Scene *s, FILE *fp, const char *indent)
{
  int first = 1;
  for (PetscInt e = 0; e < NOPTIONS; e++) {
    const OptionDesc *o     = &Options[e];
    const int         yarns = strncmp(o->name, "%s", 2) ? 1 : 2;
    for (int y = 0; y < yarns; y++) {
      const void *base = yarns == 2 ? (const void *) &s->in.yarn[y] : (const void *) &s->in;
      const void *f    = (const char *) base + o->at;
      char        name[64];
      OptName(o, y, name);
      fprintf(fp, "%s%s\"%s\": ", first ? "" : ",\n", indent, name);
      first = 0;
      switch (o->type) {
      case OPT_REAL: fprintf(fp, "%.17g", (double) *(const PetscReal *) f); break;
      case OPT_INT: fprintf(fp, "%" PetscInt_FMT, *(const PetscInt *) f); break;
      case OPT_BOOL: fprintf(fp, "%s", *(const PetscBool *) f ? "true" : "false"); break;
      case OPT_ENUM: fprintf(fp, "\"%s\"", o->choices[*(const PetscInt *) f]); break;
      case OPT_STRING: JsonString(fp, (const char *) f); break;
      default: {
        const PetscInt n = *(const PetscInt *) ((const char *) base + o->at_n);
        fputc('[', fp);
        for (PetscInt c = 0; c < n; c++) {
          if (o->type == OPT_REALS)
            fprintf(fp, "%s%.17g", c ? ", " : "", (double) ((const PetscReal *) f)[c]);
          else
            fprintf(fp, "%s%" PetscInt_FMT, c ? ", " : "", ((const PetscInt *) f)[c]);
        }
        fputc(']', fp);
      }
      }
    }
  }
  fprintf(fp, "\n");
}

/* the options of PETSc's solvers, read when the quasi-static solver sets itself up and solves (its own, -static_*,
   have been read before: one left is misspelt) */
PetscBool SceneSolverOption(const char *name)
{
  static const char *const prefix[] = {"snes_",       "ksp_",      "pc_",       "mg_", "mat_", "matptap_", "tao_",
                                       "fieldsplit_", "redundant_", "telescope_", "sub_"}; /* and the inner solvers' */
  for (size_t q = 0; q < sizeof prefix / sizeof prefix[0]; q++)
    if (!strncmp(name, prefix[q], strlen(prefix[q]))) return PETSC_TRUE;
  return PETSC_FALSE;
}

void SolverOptionsJson(FILE *fp, const char *indent)
{
  OptionsGiven g;
  int          first = 1;

  if (OptionsGivenGet(&g)) return;
  for (PetscInt q = 0; q < g.n; q++) {
    const char *name = g.name[q] + 1;
    if (!SceneSolverOption(name) && strncmp(name, "static_", 7)) continue;
    fprintf(fp, "%s%s", first ? "" : ",\n", indent);
    JsonString(fp, name);
    fprintf(fp, ": ");
    JsonString(fp, g.value[q]);
    first = 0;
  }
  if (!first) fprintf(fp, "\n");
  OptionsGivenFree(&g);
}

PetscInt SceneOptionCapacity(PetscInt k)
{
  PetscInt q = 0;
  for (PetscInt e = 0; e < NOPTIONS; e++) {
    const OptionDesc *o     = &Options[e];
    const int         yarns = strncmp(o->name, "%s", 2) ? 1 : 2;
    if (o->type == OPT_STRING) continue;
    if (k < q + yarns) return (o->type == OPT_REALS || o->type == OPT_INTS) ? o->nmax : 0;
    q += yarns;
  }
  return -1;
}
