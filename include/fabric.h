/* fabric.h - the fabric: its grid of crossings, its state and where the run is.
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

#include "bodies.h"
#include "kernels.h"
#include "scene.h"

typedef struct { /* one row of curve.csv */
  PetscInt  load_step, inner_steps;
  PetscReal time, elongation, force, residual;
  PetscReal travel;       /* m: the load point's displacement along the load (square), the sphere's travel (pushing),
                             the largest drop of a crossing (drape: curve.csv's drop_mm) */
  PetscReal center_shear; /* degrees: mean shear angle of the central zone (bias) */
  PetscReal plane_force[3], pedestal_force[3]; /* N: force of the fabric on each body (its reaction) */
  PetscReal clamp_force[3]; /* N: force on the clamps: the pull of the fabric plus the clamped crossings' weight */
  PetscReal weight[3];      /* N: the specimen's weight at this load step's gravity */
  PetscBool balanced;
} CurveRow;

/* where a row is on the load program: its elongation (jaw tests) or its travel (m) */
static inline PetscReal RowAt(const Scene *s, const CurveRow *r)
{
  return JawTest(s) ? r->elongation : r->travel;
}

typedef struct {      /* what the balance test and the stability watch see after a te step */
  PetscReal residual; /* max |F| on a free point / force scale */
  PetscReal speed;    /* max |v| on a free point, m/s */
  PetscReal tension_max;
  PetscBool balanced;
} StepStats;

typedef struct {               /* the grid of crossings: layout, rest state, masses and point kinds */
  DM da;                       /* dof 3: positions, velocities, forces (box stencil, width 2) */
  DM da_seg;                   /* dof 2, same layout: per point, its segments to i+1 and to j+1
                                  (broken flags in checkpoints) or two graph distances (prediction) */
  Vec            X0;           /* rest positions */
  Patch          patch;        /* the rank's ghosted patch for the force kernels */
  PetscInt       nloc;         /* owned points xm*ym */
  PetscReal     *mass, *inv_m; /* owned; inv_m = 0 for clamped, grip and absent points */
  unsigned char *kind;         /* owned PointKind */
  PetscReal     *predict_w;    /* owned: linear-prediction weight d0/(d0+d1) */
  PetscInt       points;       /* existing points, global */
  PetscInt       load_index;   /* owned index of the point load, -1 if not here */
  PetscReal      pull_dir[3];
  PetscReal      extent;    /* fabric size, m: runaway threshold */
  PetscReal      centre[3]; /* m: the grid centre at rest */
} FabricGrid;

typedef struct { /* -solver static: what a load step's solve starts from (static.c), checkpointed */
  Vec       Xh[3]; /* the last balanced states, the latest first */
  PetscReal lh[3]; /* their load factors */
  PetscInt  nhist;
  PetscReal shift; /* the pretension shift k_s / k_ref where the last solve ended */
  PetscReal rnorm0; /* a checkpoint within a solve: its attempt's first residual norm (SNES's divergence test) */
  PetscInt64 segments; /* yarn segments broken when the latest was kept */
} StaticHistory;

typedef struct {         /* the dynamic state */
  Vec X, V, F, Xl;       /* positions, velocities, forces, ghosted positions */
  Vec Xold, Vold;        /* paper scheme: x(n-1), V(n-1) */
  Vec Xconv, Xconv_prev; /* converged positions of the last two load steps (extrapolation) */
  PetscInt64 conv_segments; /* yarn segments broken when Xconv was kept */
  Vec anchor[3];         /* friction anchors of the sphere, plane, pedestal (bodies.h), NULL = none */
  Vec watch_x, watch_v;  /* energy watch: x and v before a watched te step (balance.c), NULL until one */
  Vec Xbelow, Xabove;    /* -break_locate_pct: the last balanced state below every breaking strain, and a trial's
                            state above (relax.c LocateBreak), NULL until used */
  StaticHistory hist;    /* -solver static */
} FabricState;

typedef struct { /* where the load program is */
  PetscInt  load_step;
  PetscReal load_factor;           /* load_step / load_steps */
  PetscReal travel;                /* m: this load step's target travel of the grips or the sphere */
  PetscReal travel_step_prev;      /* m: the last load step's travel increment */
  PetscReal travel_now;            /* m: where the grips or the sphere are (ramping towards travel) */
  PetscReal travel_from;           /* m: where the ramp started */
  PetscInt  ramp_steps, ramp_done; /* the ramp of this load step, te steps */
  PetscReal gravity_now[3];        /* m/s^2: gravity of the current load step */
  PetscReal elapsed;               /* s: time since the load step began, the te of its te steps summed */
  PetscBool left;                  /* the load step has left its own load to locate a break: no checkpoint within it */
  PetscInt  frames_below;          /* frames written up to the load step's start, or up to the state below a located
                                      break kept within it: a location drops none before (relax.c) */
} LoadState;

/* where the grips or the sphere are for a curve row: the load step's travel, or, while a ramp towards it is
   unfinished (a load step that ran out of te steps), where the ramp has got to */
static inline PetscReal LoadTravelReached(const LoadState *ls)
{
  return ls->ramp_done < ls->ramp_steps ? ls->travel_now : ls->travel;
}

typedef struct {       /* te against the measured stable limit at one state (-te_measure, spectrum.c) */
  PetscInt  load_step; /* the load step the state belongs to */
  PetscBool end;       /* its balanced end (else its start, after the grips moved and the prediction) */
  PetscReal te;        /* s: the te in use from (start) or up to (end) that state */
  PetscReal te_bound;  /* s: the stable bound at that state */
  PetscReal limit;     /* s: 2/omega_max (damped) or 1/omega_max (paper), omega_max^2 measured */
} TeMeasure;

typedef struct { /* the time step, damping and the balance test's scales */
  PetscReal  te, te_bound, omega_max, damp_c;
  PetscReal  omega1;      /* slowest mode along the pull (estimate), rad/s */
  PetscBool  bound_fresh; /* the stable step was just taken at the current state */
  PetscBool  tear;        /* a tear is followed (relax.c FollowTear): no kinetic damping */
  PetscBool  torn;        /* the relaxation after a tear, to the load step's end: the paper scheme gives way to the damped one */
  StepStats  last;
  PetscReal  force_floor; /* smallest force scale of the balance test, N */
  PetscReal  ke_prev;     /* kinetic damping: total kinetic energy after the last te step, J */
  PetscReal *ke_terms;    /* kinetic damping: owned points' kinetic energies (work) */
  PetscInt64 ke_resets;   /* kinetic damping: velocity resets so far */
  PetscReal  fire_dt;     /* FIRE: the current step, s (<= te) */
  PetscReal  fire_alpha;  /* FIRE: the velocity mixing */
  PetscInt   fire_npos;   /* FIRE: te steps since the power F.v was last <= 0 */
  PetscInt64 fire_stops;  /* FIRE: velocity resets (power F.v <= 0) so far */
  PetscReal  fire_scale[3]; /* FIRE: the scales of the next te step's sums of F.v, |F|^2, |v|^2 (0: none yet) */
  PetscReal *tally_rows;  /* a row's |F|^2 and |v|^2 for the sweep's statistics (work, 2 xm) */
  PetscInt   balance_held; /* te steps in a row the balance test has passed */
  PetscInt   balance_need; /* te steps in a row it must pass before the test per crossing (relax.c) */
  PetscInt   watch_checks; /* energy watch: watched te steps of this relaxation round */
  PetscInt   watch_held;   /* energy watch: watched te steps in a row with H above its lowest */
  PetscInt   window_grow;  /* te's window: its margin doubled this many times (StableStepRebound) */
  PetscInt64 window_bound_at; /* te's window: the te step count when it was last set */
  PetscReal  watch_h0, watch_hmin, watch_kmax; /* energy watch: the round's first and lowest mechanical energy
                                                 and its largest kinetic energy, J */
  /* -te_measure: the first and last states measured, the one with the smallest limit, the one with
     the largest te / limit, how many were measured, and the load step of the last stable step taken */
  TeMeasure te_first, te_last, te_tightest, te_worst;
  PetscInt  te_measured, te_prev_step;
} StepControl;

typedef struct {           /* rank propagation and sleeping (front.c) */
  PetscInt  front_dmax;    /* largest graph distance to a disturbed point */
  PetscInt *front_box;     /* [4 (dmax+1)]: global bounding box of {d <= R} */
  PetscInt  front_step;    /* te steps since the last load change */
  PetscBool front_covered; /* the front has reached every point */
  PetscInt  awake_box[4];  /* global bounding box of the awake points */
  PetscInt  keep_box[4];   /* kept awake for the rest of the round: the crossings a balance check found unbalanced */
  PetscInt  grip_box[4];   /* global bounding box of the grip points */
} FrontState;

typedef struct {               /* yarn breaking and rupture (relax.c) */
  PetscInt64 segments;         /* yarn segments broken so far */
  BreakSite  first;            /* where the first segment broke (kernels.h); first.ratio 0: none yet */
  BreakSite  last_break;       /* the most overstrained segment that broke at the last break check of a balanced
                                  state (read at once by PeakAtBreak: not checkpointed) */
  PetscInt   first_step;       /* its load step */
  PetscReal  first_time;       /* s: its test time */
  PetscReal  peak_force;       /* N: the largest force so far (a row's, or interpolated at a first break) */
  PetscReal  at_peak;          /* its elongation (jaw tests) or travel (m) */
  PetscBool  peak_balanced;    /* the largest force comes from balanced states (not a load step that did not balance) */
  PetscReal  load_now;         /* the last break check's largest strain / breaking strain of a segment */
  PetscReal  last_load, last_force, last_at; /* the same, the force and where, of the last balanced state
                                                  with no segment past its breaking strain */
  PetscBool  have_below;       /* state.Xbelow holds such a state with the segments broken now (-break_locate_pct) */
  PetscReal  below_lambda;     /* its load factor */
  PetscInt64 located;          /* breaks located (-break_locate_pct) */
  PetscReal  located_ratio;    /* the largest ratio at the last one located */
  PetscInt   rupture_step;     /* the load step in which the specimen ruptured (0: it has not) */
  PetscReal  rupture_time;     /* s: test time at the end of that load step's tear */
  PetscInt64 tear_te_steps;    /* te steps of tears so far */
} RuptureState;

typedef struct { /* run statistics and the curve */
  PetscInt64     te_steps, point_updates;
  PetscInt64     te_rebounds; /* stable steps taken again within a load step (a state left te's window) */
  PetscInt64     nonlinear_iterations, linear_iterations; /* the quasi-static solver's Newton and Krylov steps */
  PetscInt64     coarse_nonlinear_iterations; /* its Newton steps on -static_sequence's coarser fabrics */
  PetscInt       rows_done; /* load steps done: their curve rows written (not one a failure stopped within) */
  PetscBool      converged;
  PetscBool      broken_any; /* a yarn segment broke */
  RuptureState   rupture;
  PetscLogDouble wall_start, wall;
  CurveRow      *curve;
  FILE          *curve_fp; /* rank 0 */
  PetscBool      summary_failed; /* summary.json could not be written: the error path does not try again */
  FILE          *lock_fp;  /* rank 0: DIR/.fabric.lock, write-locked while the run lasts */
} RunStats;

typedef struct {                     /* measurements of the drape */
  PetscReal drape_pct;               /* drape coefficient (%), drape test */
  PetscReal drape_flat_area;         /* m^2: the flat specimen's shadow, measured once (0: not yet) */
  PetscInt  folds;                   /* folds of the draped outline, drape test */
} Measures;

typedef struct { /* the scene's rigid bodies, in BodyKind order */
  PetscInt n;
  Body     body[BODY_KINDS];
} RigidBodies;

typedef struct _p_Fabric *Fabric;
struct _p_FabricIO; /* frames.h */
struct _p_Fabric {
  MPI_Comm            comm;
  PetscMPIInt         rank, size;
  Scene               s;
  FabricGrid          grid;
  FabricState         state;
  RigidBodies         bodies;
  LoadState           load;
  StepControl         step;
  FrontState          front;
  RunStats            stats;
  Measures            meas;
  struct _p_FabricIO *io; /* frames of fabric.h5/.xmf, checkpoint and restart; NULL: none (frames.h) */
};

PetscErrorCode FabricCreate(MPI_Comm comm, Fabric *fab);
/* the fabric at half the thread density, for -solver static's grid sequencing (SceneCoarsen);
   NULL where its crossings would not be every other one of fine's */
PetscErrorCode FabricCreateCoarse(Fabric fine, Fabric *coarse);
PetscErrorCode FabricDestroy(Fabric *fab);
/* the te step is the paper's (-integrator paper): not within a tear nor in the relaxation after one,
   where the broken pieces fly and its two chains' parasitic mode grows (the damped scheme runs) */
PetscBool PaperSteps(const Fabric fab);
/* a bias specimen's coordinates of crossing (i,j): along its length and across it, m, from its centre */
void BiasCoords(const Scene *s, PetscInt i, PetscInt j, PetscReal *along, PetscReal *across);
/* is crossing (i,j) in the bias specimen's central zone (curve.csv center_shear_deg) */
PetscBool BiasCentreZone(const Scene *s, PetscInt i, PetscInt j);

#endif
