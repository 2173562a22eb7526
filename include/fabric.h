/* fabric.h - the woven-fabric solver: scene, state and the phases of a run.
 *
 * A fabric is a grid of yarn crossing points (DMDA, warp along x, weft along y)
 * linked by yarn segments; each load step is relaxed to balance by explicit
 * integration (MODEL.md). The driver order is:
 *   FabricCreate  -> scene options, grid, masses, clamps and grips, prediction weights
 *   FabricRun     -> for each load step: move grips, predict, stable step, relax
 *   FabricDestroy
 */
#ifndef FABRIC_H
#define FABRIC_H

#include <petscdmda.h>

#include "kernels.h"
#include "bodies.h"
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

typedef struct { /* one row of curve.csv */
  PetscInt  load_step, inner_steps;
  PetscReal time, elongation, force, residual;
  PetscReal travel; /* m: the load point's displacement along the load (square), the sphere's travel (pushing) */
  PetscReal center_shear; /* degrees: mean shear angle of the central zone (bias) */
  PetscReal plane_force[3], pedestal_force[3]; /* N: force of the fabric on each body (its reaction) */
  PetscReal clamp_force[3];  /* N: force on the clamps: the pull of the fabric plus the clamped crossings' weight */
  PetscReal weight[3];       /* N: the specimen's weight at this load step's gravity */
  PetscBool balanced;
} CurveRow;

typedef struct { /* what the balance test and the stability watch see after a te step */
  PetscReal residual; /* max |F| on a free point / force scale */
  PetscReal speed;    /* max |v| on a free point, m/s */
  PetscReal tension_max;
  PetscBool balanced;
} StepStats;

typedef struct { /* the grid of crossings: layout, rest state, masses and point kinds */
  DM             da;          /* dof 3: positions, velocities, forces (box stencil, width 2) */
  DM             da_seg;      /* dof 2, same layout: per point, its segments to i+1 and to j+1
                                 (broken flags in checkpoints) or two graph distances (prediction) */
  Vec            X0;          /* rest positions */
  Patch          patch;       /* the rank's ghosted patch for the force kernels */
  PetscInt       nloc;        /* owned points xm*ym */
  PetscReal     *mass, *inv_m; /* owned; inv_m = 0 for clamped, grip and absent points */
  unsigned char *kind;        /* owned PointKind */
  PetscReal     *predict_w;   /* owned: linear-prediction weight d0/(d0+d1) */
  PetscInt       points;      /* existing points, global */
  PetscInt       load_index;  /* owned index of the point load, -1 if not here */
  PetscReal      pull_dir[3];
  PetscReal      extent;      /* fabric size, m: runaway threshold */
  PetscReal      centre[3];   /* m: the grid centre at rest */
} FabricGrid;

typedef struct { /* the dynamic state */
  Vec X, V, F, Xl;       /* positions, velocities, forces, ghosted positions */
  Vec Xold, Vold;        /* paper scheme: x(n-1), V(n-1) */
  Vec Xconv, Xconv_prev; /* converged positions of the last two load steps (extrapolation) */
  Vec anchor[3];         /* friction anchors of the sphere, plane, pedestal (bodies.h), NULL = none */
} FabricState;

typedef struct { /* where the load program is */
  PetscInt  load_step;
  PetscReal load_factor;      /* load_step / load_steps */
  PetscReal travel;           /* m: this load step's target travel of the grips or the sphere */
  PetscReal travel_step_prev; /* m: the last load step's travel increment */
  PetscReal travel_now;       /* m: where the grips or the sphere are (ramping towards travel) */
  PetscReal travel_from;      /* m: where the ramp started */
  PetscInt  ramp_steps, ramp_done; /* the ramp of this load step, te steps */
  PetscReal gravity_now[3];   /* m/s^2: gravity of the current load step */
} LoadState;

typedef struct { /* the time step, damping and the balance test's scales */
  PetscReal te, te_bound, omega_max, damp_c;
  PetscReal omega1;        /* slowest mode along the pull (estimate), rad/s */
  PetscBool bound_fresh;   /* the stable step was just taken at the current state */
  StepStats last;
  PetscReal force_floor;   /* smallest force scale of the balance test, N */
  PetscReal ke_prev;       /* kinetic damping: total kinetic energy after the last te step, J */
  PetscReal *ke_terms;     /* kinetic damping: owned points' kinetic energies (work) */
  PetscInt64 ke_resets;    /* kinetic damping: velocity resets so far */
} StepControl;

typedef struct { /* rank propagation and sleeping (front.c) */
  PetscInt  front_dmax;    /* largest graph distance to a disturbed point */
  PetscInt *front_box;     /* [4 (dmax+1)]: global bounding box of {d <= R} */
  PetscInt  front_step;    /* te steps since the last load change */
  PetscBool front_covered; /* the front has reached every point */
  PetscInt  awake_box[4];  /* global bounding box of the awake points */
  PetscInt  grip_box[4];   /* global bounding box of the grip points */
} FrontState;

typedef struct { /* run statistics and the curve */
  PetscInt64     te_steps, point_updates;
  PetscBool      converged;
  PetscBool      broken_any; /* a yarn segment broke */
  PetscLogDouble wall_start, wall;
  CurveRow      *curve;
  FILE          *curve_fp;   /* rank 0 */
} RunStats;

typedef struct { /* measurements of the last force evaluation and of the drape */
  PetscReal sphere_sum[3], plane_sum[3], pedestal_sum[3]; /* this rank's sum of each body's contact forces */
  PetscReal drape_pct;       /* drape coefficient (%), drape test */
  PetscReal drape_flat_area; /* m^2: the flat specimen's shadow, measured once (0: not yet) */
  PetscInt  folds;           /* folds of the draped outline, drape test */
} Measures;

typedef struct _p_Fabric *Fabric;
struct _p_FabricIO; /* io.h */
struct _p_Fabric {
  MPI_Comm    comm;
  PetscMPIInt rank, size;
  Scene       s;
  FabricGrid  grid;
  FabricState state;
  LoadState   load;
  StepControl step;
  FrontState  front;
  RunStats    stats;
  Measures    meas;
  struct _p_FabricIO *io; /* frames of fabric.h5/.xmf, checkpoint and restart; NULL: none (io.h) */
};

/* log events (registered in FabricCreate) */
extern PetscLogEvent EV_Force, EV_Integrate, EV_Halo, EV_Reduce, EV_Output, EV_Bound, EV_Predict;

/* scene.c */
PetscErrorCode SceneInsertFile(MPI_Comm comm, int argc, char **argv);
PetscErrorCode SceneCheckUnused(MPI_Comm comm);
PetscErrorCode SceneLoad(MPI_Comm comm, Scene *s);
PetscErrorCode SceneDestroy(Scene *s);
/* fabric.c */
PetscErrorCode FabricCreate(MPI_Comm comm, Fabric *fab);
void           BiasCoords(const Scene *s, PetscInt i, PetscInt j, PetscReal *along, PetscReal *across);
PetscErrorCode FabricDestroy(Fabric *fab);
/* comm.c: halo exchange and reductions, the only place that communicates */
PetscErrorCode HaloExchange(Fabric fab);
PetscErrorCode HaloExchangeVec(Fabric fab, Vec X, Vec Xl);
PetscErrorCode GlobalMax(MPI_Comm comm, PetscReal *v, PetscInt n);
PetscErrorCode GlobalSum(MPI_Comm comm, PetscReal *v, PetscInt n);
PetscErrorCode GlobalSumExact(MPI_Comm comm, const PetscReal *terms, PetscInt n, PetscReal *sum);
/* integrate.c */
PetscErrorCode ComputeForces(Fabric fab, const PetscInt box[4], PetscReal *tension_max);
PetscErrorCode StableStep(Fabric fab);
PetscErrorCode TimeStep(Fabric fab, StepStats *st);
/* predict.c */
#define DIST_INF 1e30
PetscErrorCode GraphDistance(Fabric fab, const char *source, PetscReal *dist);
PetscErrorCode PredictSetUp(Fabric fab);
/* front.c */
PetscErrorCode FrontSetUp(Fabric fab);
void           FrontLoadChange(Fabric fab);
void           FrontWakeAll(Fabric fab);
PetscInt64     FrontStepBox(Fabric fab, PetscInt global[4], PetscInt local[4]);
PetscErrorCode PredictLoadStep(Fabric fab, PetscReal grip_step, const PetscReal grip_move[3]);
/* relax.c */
PetscErrorCode FabricRun(Fabric fab);
PetscErrorCode ApplyLoadStep(Fabric fab, PetscInt k);
PetscErrorCode RelaxLoadStep(Fabric fab, CurveRow *row);
/* drape test: drape_pct and folds of the current positions, the largest drop into row->travel */
PetscErrorCode DrapeOutline(Fabric fab, CurveRow *row);
PetscErrorCode GripReaction(Fabric fab, PetscReal *force);
PetscReal      LoadTravel(const Scene *s);
PetscReal      TestTime(Fabric fab);
PetscErrorCode MoveGrips(Fabric fab, PetscReal disp, PetscBool shift_history);
void           GripMove(Fabric fab, PetscReal from, PetscReal to, PetscReal move[3]);
PetscReal      GripElongation(Fabric fab, PetscReal disp);
/* output.c */
PetscErrorCode OutputOpen(Fabric fab);
PetscErrorCode OutputCurveRow(Fabric fab, const CurveRow *row);
PetscErrorCode OutputProgress(Fabric fab, const CurveRow *row);
PetscErrorCode OutputSummary(Fabric fab, const char *error);
PetscErrorCode OutputPositions(Fabric fab, const char *file);
/* io.c, checkpoint.c: results for ParaView, checkpoint and restart (hooks; the rest is in io.h) */
PetscErrorCode IOSetUp(Fabric fab);
PetscErrorCode IODestroy(Fabric fab);
PetscErrorCode FramesOpen(Fabric fab);
PetscErrorCode FramesLoadStep(Fabric fab, const CurveRow *row);
PetscErrorCode FramesTeStep(Fabric fab);
PetscErrorCode CheckpointLoadStep(Fabric fab);
PetscErrorCode RestartLoad(Fabric fab);
PetscErrorCode IODescribe(Fabric fab, char *buf, size_t len);

#endif
