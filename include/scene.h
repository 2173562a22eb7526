/* scene.h - the scene: every parameter of a run, from the options database (scene.c).
 *
 * A scene file is a YAML option file (-scene inputs/X.yaml); the command line overrides it.
 * Options are in textile units (tex, threads/cm, %, cN/tex, mm); the Scene holds SI.
 */
#ifndef FABRIC_SCENE_H
#define FABRIC_SCENE_H

#include <petscsys.h>

#include "material.h"

#define MAX_LINES     8  /* -clamp_line_mm, -grip_line_mm */
#define MAX_WAYPOINTS 32 /* -grip_path_mm */

typedef enum { PULL_WARP, PULL_WEFT } PullAxis;
typedef enum { INTEGRATOR_DAMPED, INTEGRATOR_PAPER } IntegratorType;
typedef enum { PREDICT_NONE, PREDICT_LINEAR, PREDICT_EXTRAPOLATE } PredictType;
typedef enum { POINT_FREE = 0, POINT_CLAMPED = 1, POINT_GRIP = 2 } PointKind;
typedef enum { TEST_STRIP, TEST_SQUARE, TEST_PUSHING, TEST_BIAS, TEST_DRAPE } TestType;           /* the scene's test (its load program and curve) */
typedef enum { SHAPE_RECTANGLE, SHAPE_DISC, SHAPE_BIAS } ShapeType;      /* which crossings of the grid exist */
typedef enum { CLAMP_JAW, CLAMP_EDGE, CLAMP_RING, CLAMP_NONE } ClampType; /* which existing crossings never move */

extern const char *const PullAxisNames[];
extern const char *const IntegratorNames[];
extern const char *const PredictNames[];
extern const char *const TestNames[];
extern const char *const ShapeNames[];
extern const char *const ClampNames[];

/* Everything a scene file or the command line sets, converted to SI, by concern. */
typedef struct { /* what is written where */
  char      name[PETSC_MAX_PATH_LEN];          /* scene name: the scene file's base name */
  char      file[PETSC_MAX_PATH_LEN];          /* scene file, "" if none */
  char      output_dir[PETSC_MAX_PATH_LEN];    /* "" = no output files */
  char      positions_out[PETSC_MAX_PATH_LEN]; /* final positions, PETSc binary ("" = none) */
  PetscBool quiet;                             /* no progress line per load step */
} SceneOutput;

typedef struct { /* the specimen: densities, size, shape and the grid they give */
  PetscReal ends_per_m, picks_per_m; /* warp and weft thread densities */
  PetscReal gauge, width;            /* m */
  PetscInt  yarns;                   /* yarns across the strip (0: from width) */
  PullAxis  pull;
  PetscInt  nx, ny;                  /* grid, derived */
  ShapeType shape;
  PetscReal disc_radius;             /* m, SHAPE_DISC: from the grid centre */
  PetscReal jaw_depth;               /* m, SHAPE_BIAS: the specimen reaches this far into each jaw */
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

typedef struct { /* the load program */
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

typedef struct { /* integration, balance test and speed-ups */
  IntegratorType integrator;
  PetscReal      te_user, te_safety, te_window;
  PetscBool      te_check;
  PetscBool      early_exit;
  PetscReal      balance_tol, speed_tol;
  PredictType    predict;
  PetscBool      front;           /* rank propagation */
  PetscInt       grip_ramp;       /* te steps over which the grips move to a load step's position (-1 auto) */
  PetscReal      sleep_tol;       /* 0 = no sleeping */
  PetscBool      kinetic_damping; /* zero the velocities at each peak of the kinetic energy */
  PetscReal      nu, damping_ratio;
} Numerics;

typedef struct {
  TestType    test; /* the scene's test: its load program and curve */
  SceneOutput out;
  Specimen    spec;
  Clamps      clamps;
  Yarns       yarns;
  Terms       terms;
  LoadProgram load;
  Bodies      bodies;
  Numerics    num;
} Scene;

/* the strip and bias tests pull jaws (their curve is force vs elongation); the others have none */
static inline PetscBool JawTest(const Scene *s) { return (s->test == TEST_STRIP || s->test == TEST_BIAS) ? PETSC_TRUE : PETSC_FALSE; }

PetscErrorCode SceneInsertFile(MPI_Comm comm, int argc, char **argv);
PetscErrorCode SceneCheckUnused(MPI_Comm comm);
PetscErrorCode SceneLoad(MPI_Comm comm, Scene *s);
PetscErrorCode SceneDestroy(Scene *s);

#endif
