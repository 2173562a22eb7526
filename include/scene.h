/* scene.h - the scene: every parameter of a run, from the options database (scene.c).
 *
 * A scene file is a YAML option file (-scene inputs/X.yaml); the command line overrides it.
 * Options are in textile units (tex, threads/cm, %, cN/tex, mm); the Scene holds SI.
 */
#ifndef FABRIC_SCENE_H
#define FABRIC_SCENE_H

#include <petscsys.h>

#include "material.h"

/* DIR/.fabric.lock: 1 when another run holds it; with take, rank 0 locks it for this run (*take stays
   open while the run lasts). The set-up looks (take NULL); report.c takes it as the outputs open. */
int OutputDirLock(const char *dir, FILE **take);

/* a run refused because another holds DIR/.fabric.lock: DIR, DIR */
#define OUTPUT_DIR_BUSY \
  "-output_dir %.2000s: another run is writing there (it holds %.2000s/.fabric.lock); give each run its own -output_dir, " \
  "or wait for that one to end"

#define MAX_LINES     8  /* -clamp_line_mm, -grip_line_mm */
#define MAX_WAYPOINTS 32 /* -grip_path_mm */
#define MAX_LOAD_STEPS 10000000 /* curve.csv's rows are kept in memory, one per load step */

typedef enum { PULL_WARP, PULL_WEFT } PullAxis;
typedef enum { SOLVER_EXPLICIT, SOLVER_STATIC } SolverType;
typedef enum { INTEGRATOR_DAMPED, INTEGRATOR_PAPER, INTEGRATOR_FIRE } IntegratorType;
typedef enum { PREDICT_NONE, PREDICT_LINEAR, PREDICT_EXTRAPOLATE } PredictType;
typedef enum { POINT_FREE = 0, POINT_CLAMPED = 1, POINT_GRIP = 2 } PointKind;
typedef enum {
  TEST_STRIP,
  TEST_SQUARE,
  TEST_PUSHING,
  TEST_BIAS,
  TEST_DRAPE,
  TEST_COUNT
} TestType;                                                         /* the scene's test (its load program and curve) */
typedef enum { SHAPE_RECTANGLE, SHAPE_DISC, SHAPE_BIAS } ShapeType; /* which crossings of the grid exist */
typedef enum { CLAMP_JAW, CLAMP_EDGE, CLAMP_RING, CLAMP_NONE } ClampType; /* which existing crossings never move */

extern const char *const PullAxisNames[];
extern const char *const SolverNames[];
extern const char *const IntegratorNames[];
extern const char *const PredictNames[];
extern const char *const TestNames[];
extern const char *const ShapeNames[];
extern const char *const ClampNames[];

/* Everything a scene file or the command line sets, converted to SI, by concern. */
/* The options as given, in their own units (tex, threads/cm, %, cN/tex, mm): what the option
   table of scene.c reads, and what checkpoints and summary.json record. */
typedef struct {
  PetscReal tex, crimp_pct, modulus_cN_tex, decrimp_ratio, compression_ratio, contact_pct, law_smoothing_pct;
  PetscReal bending_Nm2, break_pct, break_cv_pct;
  char      law_csv[PETSC_MAX_PATH_LEN];
  PetscReal bundle; /* not an option: the yarns a grid yarn stands for, on a coarse fabric (SceneCoarsen) */
} YarnInput;

typedef struct {
  char      scene[PETSC_MAX_PATH_LEN];
  PetscReal ends_per_cm, picks_per_cm, gauge_mm, width_mm;
  PetscInt  yarns, pull, test, shape, clamp;
  PetscReal disc_diameter_mm, jaw_depth_mm;
  PetscReal clamp_ring_mm[2], clamp_line_mm[4 * MAX_LINES], grip_line_mm[4 * MAX_LINES];
  PetscInt  n_clamp_ring_mm, n_clamp_line_mm, n_grip_line_mm;
  PetscReal sphere_diameter_mm, thickness_mm, sphere_direction[3], sphere_start_mm[3], sphere_travel_mm;
  PetscInt  n_sphere_direction, n_sphere_start_mm;
  PetscReal contact_stiffness_N_m, plane_point_mm[3], plane_normal[3];
  PetscInt  n_plane_point_mm, n_plane_normal;
  PetscBool plane;
  PetscReal pedestal_diameter_mm, pedestal_height_mm, pedestal_top_mm[3], friction_mu;
  PetscInt  n_pedestal_top_mm;
  YarnInput yarn[2]; /* warp, weft */
  PetscBool traction, bending, shear;
  PetscReal shear_G_N_m, shear_lock_deg, jam_factor, gravity[3], nu, damping_ratio;
  PetscInt  n_gravity;
  PetscReal elongation_pct, speed_mm_min, point_load_N[3], grip_path_mm[3 * MAX_WAYPOINTS];
  PetscInt  n_point_load_N, point_load_at[2], n_point_load_at, n_grip_path_mm, load_steps, max_inner_steps;
  PetscReal break_gauge_mm, rupture_drop_pct, break_locate_pct, tear_wave_crossings, tear_max_ms, tear_damping_ratio, tear_te_safety;
  PetscInt  break_seed, output_tear_every;
  PetscInt  solver, integrator, predict, grip_ramp_steps, te_measure, balance_hold;
  PetscReal te, te_safety, te_strain_window, balance_tol, speed_tol, sleep_tol, balance_floor, energy_watch;
  PetscBool te_check, early_exit, front, kinetic_damping;
  char      output_dir[PETSC_MAX_PATH_LEN], positions_out[PETSC_MAX_PATH_LEN], restart[PETSC_MAX_PATH_LEN];
  PetscBool quiet;
  PetscInt  output_every, output_te_every, checkpoint_every, checkpoint_every_te;
  PetscReal checkpoint_every_s;
} SceneInput;

typedef struct {                               /* what is written where */
  char      name[PETSC_MAX_PATH_LEN];          /* scene name: the scene file's base name */
  char      file[PETSC_MAX_PATH_LEN];          /* scene file, "" if none */
  char      output_dir[PETSC_MAX_PATH_LEN];    /* "" = no output files */
  char      positions_out[PETSC_MAX_PATH_LEN]; /* final positions, PETSc binary ("" = none) */
  PetscBool quiet;                             /* no progress line per load step */
  PetscInt  output_every;                      /* a frame every K load steps and at the last (0: none) */
  PetscInt  output_te_every;                   /* a frame every M te steps within a load step (0: none) */
  PetscInt  output_tear_every;                 /* a frame every M te steps of a tear (0: none) */
  PetscInt  checkpoint_every;                  /* checkpoint.h5 every K load steps (0: never) */
  PetscInt  checkpoint_every_te;               /* checkpoint.h5 within a load step every K te steps (0: never) */
  PetscReal checkpoint_every_s;                /* checkpoint.h5 within a load step every S s of wall clock (0: never) */
  char      restart[PETSC_MAX_PATH_LEN];       /* -restart FILE, "" for a fresh run */
} SceneOutput;

typedef struct {                     /* the specimen: densities, size, shape and the grid they give */
  PetscReal ends_per_m, picks_per_m; /* warp and weft thread densities */
  PetscReal gauge, width;            /* m */
  PetscInt  yarns;                   /* yarns across the strip (0: from width) */
  PullAxis  pull;
  PetscInt  nx, ny; /* grid, derived */
  ShapeType shape;
  PetscReal disc_radius; /* m, SHAPE_DISC: from the grid centre */
  PetscReal jaw_depth;   /* m, SHAPE_BIAS: the specimen reaches this far into each jaw */
} Specimen;

/* lines across the grid at any angle (on top of -clamp): the existing crossings within a band
   of half-width w around the line through (x, y) at angle a to the warp (x) axis,
   |-(X - x) sin a + (Y - y) cos a| <= w, are clamped (clamp lines) or move with the grip */
typedef struct {
  ClampType clamp;
  PetscReal ring[2]; /* m, CLAMP_RING: inner and outer radius from the grid centre */
  PetscInt  clamp_lines, grip_lines;
  PetscReal clamp_line[MAX_LINES][4]; /* x, y (m, from the grid centre), a (rad), w (m) */
  PetscReal grip_line[MAX_LINES][4];
} Clamps;

typedef struct { /* the yarns: warp along x, weft along y */
  YarnLaw warp, weft;
} Yarns;

typedef struct { /* the force terms and their constants */
  PetscBool traction, bending, shear;
  PetscReal shear_G, lock_deg, jam_factor;
  PetscReal gravity[3]; /* m/s^2 */
} Terms;

typedef struct {           /* the load program */
  PetscReal elongation;    /* final grip displacement / gauge */
  PetscReal speed;         /* test speed, m/s (gives time_s) */
  PetscReal point_load[3]; /* final point load, N */
  PetscInt  load_at[2];
  PetscInt  load_steps, max_inner_steps;
  /* the grip's path: piecewise linear from (0,0,0) through the waypoints, travelled at the
     test speed over the load steps (equal lengths along it); 0 waypoints: straight along the pull */
  PetscInt  waypoints;
  PetscReal waypoint[MAX_WAYPOINTS][3]; /* m: grip displacement at the path's corners */
  PetscReal path_at[MAX_WAYPOINTS];     /* m: length along the path to each waypoint */
} LoadProgram;

typedef struct { /* rigid bodies with penalty contact (MODEL.md 5.5) */
  /* sphere (punch): centre = start + d * dir, d = 0 .. travel over the load steps */
  PetscReal sphere_radius;   /* m, 0 = no sphere */
  PetscReal sphere_start[3]; /* m, from the grid centre at rest */
  PetscBool sphere_start_set; /* given (-sphere_start_mm), else the default: touching the fabric's plane */
  PetscReal sphere_dir[3];   /* unit */
  PetscReal sphere_travel;   /* m */
  PetscReal thickness;       /* m: fabric thickness, contact at R + h/2 */
  PetscReal contact_k;       /* N/m: penalty stiffness per crossing */
  /* plane (table): the fabric stays on the side the normal points to */
  PetscBool plane;
  PetscReal plane_point[3];  /* m, from the grid centre at rest */
  PetscReal plane_normal[3]; /* unit */
  /* pedestal (disc, the drape's support): a solid vertical cylinder whose flat top face,
     centred on pedestal_top, faces +z (bodies.h DiscContact) */
  PetscReal pedestal_radius; /* m, 0 = no pedestal */
  PetscReal pedestal_top[3]; /* m, from the grid centre at rest */
  PetscReal pedestal_height; /* m, below the top face */
  PetscReal friction_mu;     /* Coulomb friction of every body, 0 = frictionless */
} Bodies;

typedef struct {         /* integration, balance test and speed-ups */
  SolverType     solver; /* explicit relaxation or the quasi-static Newton-Krylov solve (static.h) */
  IntegratorType integrator;
  PetscReal      te_user, te_safety, te_window;
  PetscReal      te_safety_tear, te_window_tear; /* a tear's (the damped scheme's) */
  PetscBool      te_check;
  PetscInt       te_measure; /* measure omega_max^2 of the tangent every this many load steps (0: never) */
  PetscBool      early_exit;
  PetscReal      balance_tol, speed_tol;
  PetscInt       balance_hold;  /* te steps in a row the balance test must pass */
  PetscReal      balance_floor; /* per crossing: the force scale's floor, a fraction of the largest tension */
  PetscReal      energy_watch;  /* stop at energy growth above this fraction of the energy released (0: off) */
  PredictType    predict;
  PetscBool      front;           /* rank propagation */
  PetscInt       grip_ramp;       /* te steps over which the grips move to a load step's position (-1 auto) */
  PetscReal      sleep_tol;       /* 0 = no sleeping */
  PetscBool      kinetic_damping; /* zero the velocities at each peak of the kinetic energy */
  PetscReal      nu, damping_ratio;
} Numerics;

typedef struct {      /* rupture (relax.c): how a tear is followed and when the specimen has broken */
  PetscInt64 seed;     /* of the segments' breaking strains (material.h SegmentBreakStrain) */
  PetscReal  drop;     /* broken: after a yarn broke, the force fell below (1 - drop) of its maximum */
  PetscReal  crossings; /* a tear ends when no segment broke while a yarn wave crossed the specimen this often */
  PetscReal  max_time; /* s of test time: the longest tear */
  PetscReal  damping;  /* a tear's damping ratio at the slowest mode */
  PetscReal  locate;   /* a break is located: the load is found at which the largest strain ratio is within (1, 1 + locate]
                          (0: yarns break on the load step's balanced state) */
} Rupture;

typedef struct {
  SceneInput  in;   /* the options as given */
  TestType    test; /* the scene's test: its load program and curve */
  SceneOutput out;
  Specimen    spec;
  Clamps      clamps;
  Yarns       yarns;
  Terms       terms;
  LoadProgram load;
  Bodies      bodies;
  Numerics    num;
  Rupture     rupture;
} Scene;

/* the strip and bias tests pull jaws (their curve is force vs elongation); the others have none */
static inline PetscBool JawTest(const Scene *s)
{
  return (s->test == TEST_STRIP || s->test == TEST_BIAS) ? PETSC_TRUE : PETSC_FALSE;
}

/* the tests whose force is a reaction to an imposed travel (jaws or the ball): their maximum force is
   reported, and their specimen can be seen to rupture */
static inline PetscBool ReactionTest(const Scene *s)
{
  return (JawTest(s) || s->test == TEST_PUSHING) ? PETSC_TRUE : PETSC_FALSE;
}

/* m: the drape's support disc, A_disc of the drape coefficient: the fabric is held flat out to the larger of
   the pedestal and the clamping ring's outer radius */
static inline PetscReal DrapeSupportRadius(const Scene *s)
{
  return PetscMax(s->bodies.pedestal_radius, s->clamps.clamp == CLAMP_RING ? s->clamps.ring[1] : 0.0);
}

/* what PETSc would refuse in the value of a viewer option -name ([type][:file[:format]]), said in msg; 0: nothing */
int  ViewerValueProblem(const char *name, const char *value, char *msg, size_t len);
/* a text in a message: one longer than SHOWN_MAX keeps its first and last 100 bytes, "..." between (PETSc keeps a
   message's first 1023 characters) */
#define SHOWN_MAX 240
typedef struct {
  char text[SHOWN_MAX];
} Shown;
const char *ShowText(const char *text, Shown *sh);
/* an option of PETSc's solvers (name without its '-': snes_, ksp_, pc_, mg_, mat_, tao_ ...), read when the
   quasi-static solver sets itself up */
PetscBool SceneSolverOption(const char *name);
/* OPT's FILE is a readable regular file (not a directory, device or pipe), or an error naming both */
PetscErrorCode SceneCheckReadable(MPI_Comm comm, const char *opt, const char *file);
PetscErrorCode SceneLoad(MPI_Comm comm, Scene *s);
PetscErrorCode SceneWidthText(const SceneInput *in, const char *real_fmt, char *text, size_t len);
/* the same fabric at half the thread density (-solver static's grid sequencing): each coarse yarn
   stands for two (twice the tex and the bending stiffness: the same stiffness and weight per width
   and area), no yarn breaks, no output. fits: its crossings are every other one of the fine grid's
   (an odd number along each side, the point load on one of them; not a strip or bias test) */
PetscErrorCode SceneCoarsen(MPI_Comm comm, const Scene *fine, Scene *coarse, PetscBool *fits);
PetscErrorCode SceneDestroy(Scene *s);

/* The numeric options of the option table as (name, values): the checkpoint's scene keys and
   summary.json's options. k = 0, 1, ... until it returns 0; n values into v (at most 96). */
int SceneOptionValues(const Scene *s, PetscInt k, char name[64], PetscReal v[], PetscInt *n);
/* the most values option k of SceneOptionValues takes: 0 for a single value (-1: no option k) */
PetscInt SceneOptionCapacity(PetscInt k);
/* every option as JSON members "name": value, one a line after indent (summary.json's "options") */
void SceneOptionsJson(const Scene *s, FILE *fp, const char *indent);
void JsonString(FILE *fp, const char *str); /* a JSON string literal of str (escaped, valid UTF-8) */
/* the quasi-static path's and PETSc's solver options given (-static_minimizer, -snes_*, -tao_nls_*, ...), as JSON
   members "name": "value as given" one a line after indent, none if none (summary.json's "solver_options") */
void SolverOptionsJson(FILE *fp, const char *indent);

/* The options given, in PETSc's database: each name (with its '-') and value ("" if none), read
   from the database's text, which marks nothing used. OptionsGivenGet: 0, or non-zero if PETSc
   could not list them (then nothing to free). */
typedef struct {
  PetscInt     n;
  const char **name, **value;
  char        *text;
} OptionsGiven;
int  OptionsGivenGet(OptionsGiven *g);
void OptionsGivenFree(OptionsGiven *g);
/* the solvers' options given (the names with ksp_, pc_, snes_ or tao_ in them, and their values), "" if none:
   into buf, cut with " ..." if longer */
void SolverOptionsGiven(char *buf, size_t len);
/* name is -suffix, or suffix under a prefix (-mg_levels_ksp_type, -tao_nls_ksp_type ...) */
PetscBool OptionIs(const char *name, const char *suffix);

/* Can the file be written? Its directory must exist (or be output_dir, made at the start of a run);
   libc alone, so main may call it before PetscInitialize. msg: "" or why not. */
void ProbeFile(const char *opt, const char *path, const char *output_dir, char *msg, size_t len);

#endif
