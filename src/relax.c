/* relax.c - the load program: multi-sampling with early exit (MODEL.md 6, 8).
 *
 * External conditions are constant during a load step (Te = N te). At its start the
 * grips move and the prediction moves the free points; then te steps run until the
 * global balance test passes (modified multi-sampling, -early_exit 1) or N steps
 * have run. The measured response is the reaction on the grips.
 */
#include "relax.h"
#include "scenefile.h" /* SceneWarnUnused */
#include "balance.h"
#include "checkpoint.h"
#include "comm.h"
#include "frames.h"
#include "front.h"
#include "integrate.h"
#include "load.h"
#include "measure.h"
#include "predict.h"
#include "spectrum.h"
#include "report.h"
#include "static.h"

#include <math.h>

#define MAX_BREAK_ROUNDS 1000 /* re-relaxations of one load step after yarns broke */
#define BALANCE_NEED_MAX 512  /* te steps in a row, at most, between two checks per crossing */

/* Break the yarn segments strained past their breaking strain (all ranks agree); *broke: how many
   broke (known: the largest ratio of this state if just measured, else negative). Where (where, and at the first break, whose place is kept): the most overstrained segment
   that broke, the lowest index on a tie, in r->last_break (one more reduction). */
static PetscErrorCode CheckBreaks(Fabric fab, PetscBool where, PetscReal known, PetscInt *broke)
{
  RuptureState      *r = &fab->stats.rupture;
  const PetscScalar *xl;
  BreakSite          site;
  PetscReal          load;
  PetscInt           n;

  PetscFunctionBeginUser;
  *broke = 0;
  if (!isfinite(fab->s.yarns.warp.break_e) && !isfinite(fab->s.yarns.weft.break_e)) PetscFunctionReturn(0);
  if (known >= 0 && known <= 1.0) { /* LocateBreak has just found every segment below its breaking strain */
    r->load_now = known;
    PetscFunctionReturn(0);
  }
  PetscCall(HaloExchange(fab->grid.da, fab->state.X, fab->state.Xl));
  PetscCall(VecGetArrayRead(fab->state.Xl, &xl));
  n = BreakSegments(&fab->grid.patch, xl, 1, &site, &load);
  PetscCall(VecRestoreArrayRead(fab->state.Xl, &xl));
  { /* one reduction when nothing broke (a tear's every te step): the largest load and whether any broke */
    PetscReal red[2] = {load, (PetscReal) n};
    PetscCall(GlobalMax(fab->comm, red, 2));
    r->load_now = red[0];
    if (red[1] == 0) PetscFunctionReturn(0);
  }
  PetscCall(GlobalSumInt(fab->comm, &n, 1));
  *broke = n;
  fab->stats.broken_any = PETSC_TRUE;
  r->have_below         = PETSC_FALSE; /* the fabric is another: its states below are to be found again */
  r->segments += n;
  if (where || r->first.ratio == 0) { /* the most overstrained segment that broke (the lowest index on a tie) */
    const PetscInt nx = fab->s.spec.nx, ny = fab->s.spec.ny;
    PetscReal      best = site.ratio;
    PetscInt       code = site.ratio > 0 ? site.dir * nx * ny + site.j * nx + site.i : -1; /* -1: none broke here */
    PetscCall(GlobalArgMax(fab->comm, &best, &code));
    r->last_break.ratio = best;
    r->last_break.dir   = code / (nx * ny);
    r->last_break.j     = (code % (nx * ny)) / nx;
    r->last_break.i     = code % nx;
  }
  if (r->first.ratio == 0) { /* the first break */
    r->first       = r->last_break;
    r->first_step  = fab->load.load_step;
    r->first_time  = TestTime(&fab->s, &fab->load);
  }
  PetscFunctionReturn(0);
}

/* the largest strain / breaking strain of an unbroken segment now (all ranks alike); nothing breaks */
static PetscErrorCode BreakRatio(Fabric fab, PetscReal *ratio)
{
  const PetscScalar *xl;
  BreakSite          site;

  PetscFunctionBeginUser;
  PetscCall(HaloExchange(fab->grid.da, fab->state.X, fab->state.Xl));
  PetscCall(VecGetArrayRead(fab->state.Xl, &xl));
  (void) BreakSegments(&fab->grid.patch, xl, 0, &site, ratio);
  PetscCall(VecRestoreArrayRead(fab->state.Xl, &xl));
  PetscCall(GlobalMax(fab->comm, ratio, 1));
  PetscFunctionReturn(0);
}

/* what frames are taken of (frames.h): the grid, the state, where the files go */
static FrameSource FramesOf(Fabric fab)
{
  const FrameSource src = {fab->comm, &fab->grid, fab->state.X, fab->state.V, fab->state.Xl, &fab->s.out};
  return src;
}

/* the current state for its frames: the load step's test time and the time its te steps have taken, the load
   step's number (te step: the caller's) */
static FrameInfo NowFrame(Fabric fab)
{
  const FrameInfo f = {TestTime(&fab->s, &fab->load) + fab->load.elapsed, fab->load.load_step, 0};
  return f;
}

/* -output_te_every: a frame after this te step, if due */
static PetscErrorCode TeStepFrame(Fabric fab)
{
  const FrameSource src = FramesOf(fab);
  const FrameInfo   now = NowFrame(fab);

  PetscFunctionBeginUser;
  PetscCall(FramesTeStep(fab->io, &src, &now, fab->stats.te_steps));
  PetscFunctionReturn(0);
}

/* The load of load step k at load factor lambda (its own: k / K; a located break's: between two load
   factors): move the grips (at once, or start their ramp), predict, take the stable step. */
static PetscErrorCode ApplyLoad(Fabric fab, PetscInt k, PetscReal lambda, PetscBool start)
{
  const Scene    *s    = &fab->s;
  const PetscReal disp = lambda * LoadTravel(s), step = disp - fab->load.travel;
  PetscReal       damp_c, omega1, move[3];
  PetscBool       predicted;

  PetscFunctionBeginUser;
  fab->load.load_step   = k;
  fab->load.elapsed     = 0;
  fab->load.load_factor = lambda;
  if (s->test == TEST_DRAPE) /* the specimen is lowered onto its support: gravity grows with the load steps */
    for (int d = 0; d < 3; d++) fab->load.gravity_now[d] = lambda * s->terms.gravity[d];
  /* the damping is tuned to the balanced state before the grips jump: right after the jump
     the segment at the grip is strained far beyond the rest of the chain */
  if (!fab->step.bound_fresh) PetscCall(StableDamping(fab)); /* else FabricRun just took it, at this state */
  damp_c = fab->step.damp_c;
  omega1 = fab->step.omega1;
  /* Without prediction a jump of the jaw is an impact on the yarns (they fold and pile up):
     the jaw moves instead over a cosine ramp of half a period of the slowest mode, pi/omega_1,
     as a testing machine does, so the strain at the jaw never overshoots the step's mean
     strain (TimeStep drives it). With prediction (or -grip_ramp_steps 0) it jumps, before
     the prediction and the stable step see the new state; but a sphere always ramps: the
     prediction only guesses the fabric's shape, and a sphere that jumped into the crossings
     it missed would strike them with its penalty force. */
  fab->load.travel_from = fab->load.travel_now;
  fab->load.ramp_steps  = step == 0               ? 0
                          : s->num.grip_ramp >= 0 ? s->num.grip_ramp
                                                  : ((s->num.predict == PREDICT_NONE || s->bodies.sphere_radius > 0)
                                                         ? (PetscInt) PetscMin(PetscCeilReal(PETSC_PI / (omega1 * fab->step.te)),
                                                                               (PetscReal) PETSC_MAX_INT)
                                                         : 0);
  fab->load.ramp_done   = 0;
  GripPathMove(s, fab->grid.pull_dir, fab->load.travel, disp, move);
  if (s->bodies.sphere_radius > 0) /* the sphere's move: what its linear prediction follows */
    for (int d = 0; d < 3; d++) move[d] = step * s->bodies.sphere_dir[d];
  if (!fab->load.ramp_steps) PetscCall(PlaceGrips(fab, disp, PETSC_TRUE));
  PetscCall(PredictLoadStep(fab, step, move, &predicted));
  fab->load.travel           = disp;
  if (start) fab->load.travel_step_prev = step; /* a load step's whole step: what extrapolation scales by */
  FrontLoadChange(fab, predicted);
  PetscCall(StableStep(fab));
  fab->step.damp_c      = damp_c;
  fab->step.bound_fresh = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* Load step k of K */
PetscErrorCode ApplyLoadStep(Fabric fab, PetscInt k)
{
  PetscFunctionBeginUser;
  fab->load.left         = PETSC_FALSE;
  fab->load.frames_below = fab->io ? fab->io->frames : 0;
  PetscCall(ApplyLoad(fab, k, (PetscReal) k / (PetscReal) fab->s.load.load_steps, PETSC_TRUE));
  PetscFunctionReturn(0);
}

/* the balanced state x at load factor lambda, at rest, as the state now (a located break's trials start from
   one; the grips are where x has them) */
static PetscErrorCode RestoreAt(Fabric fab, Vec x, PetscReal lambda)
{
  const Scene    *s    = &fab->s;
  const PetscReal disp = lambda * LoadTravel(s);

  PetscFunctionBeginUser;
  PetscCall(VecCopy(x, fab->state.X));
  PetscCall(VecZeroEntries(fab->state.V));
  if (fab->state.Xold) {
    PetscCall(VecCopy(x, fab->state.Xold));
    PetscCall(VecZeroEntries(fab->state.Vold));
  }
  fab->load.load_factor = lambda;
  fab->load.travel = fab->load.travel_now = fab->load.travel_from = disp;
  fab->load.ramp_steps = fab->load.ramp_done = 0;
  if (s->test == TEST_DRAPE)
    for (int d = 0; d < 3; d++) fab->load.gravity_now[d] = lambda * s->terms.gravity[d];
  FrontWakeAll(fab);
  PetscFunctionReturn(0);
}

/* -break_locate_pct: keep this balanced state, below every breaking strain (largest ratio `ratio`), as the
   lower end of the next break's bracket, and its force and place as the reference of PeakAtBreak (row: this
   state measured) */
static PetscErrorCode KeepBelow(Fabric fab, PetscReal ratio, const CurveRow *row)
{
  RuptureState *r = &fab->stats.rupture;

  PetscFunctionBeginUser;
  r->last_load  = ratio;
  r->last_force = row->force;
  r->last_at    = RowAt(&fab->s, row);
  if (!(fab->s.rupture.locate > 0)) PetscFunctionReturn(0);
  if (fab->load.left && fab->io) fab->load.frames_below = fab->io->frames; /* a tear's frames before stay */
  if (!fab->state.Xbelow) PetscCall(VecDuplicate(fab->state.X, &fab->state.Xbelow));
  PetscCall(VecCopy(fab->state.X, fab->state.Xbelow));
  r->have_below   = PETSC_TRUE;
  r->below_lambda = fab->load.load_factor;
  PetscFunctionReturn(0);
}

/* the curve row of the current state: its balance, where the load program is, the measurements */
static PetscErrorCode MeasureRow(Fabric fab, PetscReal residual, PetscBool balanced, CurveRow *row)
{
  const Scene *s = &fab->s;

  PetscFunctionBeginUser;
  row->load_step  = fab->load.load_step;
  row->residual   = residual;
  row->balanced   = balanced;
  row->elongation = JawTest(s) ? GripElongation(s, fab->grid.pull_dir, LoadTravelReached(&fab->load)) : 0.0;
  row->time       = TestTimeAt(s, &fab->load, LoadTravelReached(&fab->load));
  PetscCall(MeasureLoadStep(fab, row));
  PetscFunctionReturn(0);
}

/* break detection is on for the tests with a reaction (-rupture_drop_pct 0: never) */
static PetscBool CanRupture(const Scene *s)
{
  return ReactionTest(s) && s->rupture.drop > 0 ? PETSC_TRUE : PETSC_FALSE;
}

/* the break detection on a measured row: a force below (1 - drop) of the maximum marks the rupture here (then,
   at the time the load step's te steps have reached) */
static PetscBool MarkRupture(Fabric fab, const CurveRow *row)
{
  RuptureState *r = &fab->stats.rupture;
  if (!(r->peak_force > 0 && row->force < (1.0 - fab->s.rupture.drop) * r->peak_force)) return PETSC_FALSE;
  r->rupture_step = fab->load.load_step;
  r->rupture_time = row->time + fab->load.elapsed;
  return PETSC_TRUE;
}

/* a force and where it was (elongation or travel) as a candidate for the maximum force; balanced:
   it comes from balanced states */
static void KeepPeak(RuptureState *r, PetscReal force, PetscReal at, PetscBool balanced)
{
  if (force > r->peak_force) r->peak_force = force, r->at_peak = at, r->peak_balanced = balanced;
}

/* the curve row of a load step that has ended (measured: row already holds this state), and the
   largest force so far. A balanced state with every segment below its breaking strain is the
   reference of the next first break's force. After a yarn broke, a force below the break detection's
   threshold ends the test here (as within a tear: CheckRupture), also where the tear ended before the
   unloading reached the grips. */
static PetscErrorCode FinishRow(Fabric fab, PetscReal residual, PetscBool balanced, PetscBool measured, CurveRow *row)
{
  RuptureState *r = &fab->stats.rupture;

  PetscFunctionBeginUser;
  if (!measured) PetscCall(MeasureRow(fab, residual, balanced, row)); /* else: this state, measured before CheckBreaks */
  KeepPeak(r, row->force, RowAt(&fab->s, row), balanced);
  if (CanRupture(&fab->s) && fab->stats.broken_any && !r->rupture_step) (void) MarkRupture(fab, row);
  if (balanced && r->load_now <= 1.0) PetscCall(KeepBelow(fab, r->load_now, row));
  if (!balanced) r->have_below = PETSC_FALSE; /* a located break never goes back past this row */
  PetscFunctionReturn(0);
}

/* Yarns broke on this balanced state (row: measured before they broke): the load step overshot the
   first break. Between the last balanced state below every breaking strain (largest strain ratio r0)
   and this one (r1 > 1), the break comes at the fraction w = (1 - r0)/(r1 - r0) of the strain: the
   elongation or travel there is interpolated at w; the force at the fraction of the tension that the
   segment that broke (breaking chord strain eb) gains by its yarn law from r0 eb to eb of what it gains
   up to r1 eb. (The force at w overstated it where the law's stiffness changes within the load step: past
   the crimp, 20 times the de-crimping stiffness.) The force is a candidate for the maximum. */
static void PeakAtBreak(Fabric fab, const CurveRow *row)
{
  RuptureState    *r  = &fab->stats.rupture;
  const BreakSite *b  = &r->last_break;
  const YarnLaw   *y  = b->dir == 0 ? fab->grid.patch.warp : fab->grid.patch.weft;
  const PetscReal  r0 = r->last_load, r1 = r->load_now;
  const PetscReal  w  = r1 > r0 ? PetscMin(1.0, PetscMax(0.0, (1.0 - r0) / (r1 - r0))) : 1.0;
  const PetscReal  eb = SegmentBreakStrain(y, fab->s.rupture.seed, (int) b->dir, b->i, b->j);
  const PetscReal  t0 = ChordTension(y, r0 * eb), gain = ChordTension(y, r1 * eb) - t0;
  const PetscReal  wt = gain > 0 && isfinite(gain) ? PetscMin(1.0, PetscMax(0.0, (ChordTension(y, eb) - t0) / gain)) : w;

  KeepPeak(r, r->last_force + wt * (row->force - r->last_force), r->last_at + w * (RowAt(&fab->s, row) - r->last_at),
           PETSC_TRUE);
}

/* te steps in which a yarn's stress wave crosses the specimen -tear_wave_crossings times: a chain in
   yarn extension carries it at c = sqrt(T' / (mu (1 + crimp))), T' = EA / (1 + crimp) */
static PetscInt TearQuietSteps(Fabric fab)
{
  const Scene    *s    = &fab->s;
  const Patch    *p    = &fab->grid.patch;
  const PetscReal span = PetscMax((s->spec.nx - 1) * p->ax, (s->spec.ny - 1) * p->ay);
  PetscReal       c    = 0;
  for (int f = 0; f < 2; f++) {
    const YarnLaw *y = f == 0 ? p->warp : p->weft;
    c                = PetscMax(c, PetscSqrtReal(y->EA / (y->mu * PetscSqr(1.0 + y->crimp))));
  }
  return (PetscInt) PetscMin(PetscCeilReal(s->rupture.crossings * span / (c * fab->step.te)), (PetscReal) PETSC_MAX_INT);
}

/* within a tear: the state now measured, and the break detection on it (MarkRupture) */
static PetscErrorCode CheckRupture(Fabric fab, const StepStats *st, CurveRow *row, PetscBool *ruptured)
{
  PetscFunctionBeginUser;
  PetscCall(MeasureRow(fab, st->residual, PETSC_FALSE, row));
  *ruptured = MarkRupture(fab, row);
  PetscFunctionReturn(0);
}

/* A tear: yarns broke on the balanced state of this load step. Follow the unloading with the true
   masses and the yarns' own damping, -tear_damping_ratio (no balance test, no kinetic damping),
   breaking segments after every te step, until none has broken while a stress wave crossed the
   specimen -tear_wave_crossings times, or -tear_max_ms of test time or -max_inner_steps te steps
   have passed, or the force has fallen below the break detection's threshold (checked 8 times a
   quiet window: then the specimen has ruptured). */
static PetscErrorCode FollowTear(Fabric fab, StepStats *st, CurveRow *row, PetscBool *ruptured)
{
  const Scene    *s      = &fab->s;
  const PetscInt  before = row->inner_steps, every = s->out.output_tear_every;
  const PetscReal damp_c = fab->step.damp_c; /* the relaxation's */
  PetscInt        last = 0, n = 0, quiet, most, check;

  PetscFunctionBeginUser;
  *ruptured = PETSC_FALSE;
  FrontWakeAll(fab);
  fab->front.front_covered = PETSC_TRUE;
  fab->step.tear           = PETSC_TRUE;
  fab->step.window_grow    = 0; /* the tear's window from its own margin */
  PetscCall(StableStepAgain(fab)); /* the damped scheme's te */
  PetscCall(StableStepMeasureTear(fab, "start"));
  fab->step.damp_c = 2.0 * s->rupture.damping * fab->step.omega1;
  quiet            = TearQuietSteps(fab);
  most  = (PetscInt) PetscMax(1.0, PetscMin(PetscFloorReal(s->rupture.max_time / fab->step.te), (PetscReal) PETSC_MAX_INT));
  most  = PetscMin(most, s->load.max_inner_steps); /* a load step's te steps: a tiny -tear_te_safety ends too */
  check = CanRupture(s) ? PetscMax(1, quiet / 8) : 0;
  while (n < most && n - last < quiet && !*ruptured) {
    PetscInt broke;
    PetscCall(TimeStep(fab, st));
    n++;
    PetscCall(CheckBreaks(fab, PETSC_FALSE, -1.0, &broke));
    if (broke) last = n;
    if (fab->io && every && n % every == 0) {
      const FrameSource src = FramesOf(fab);
      FrameInfo         now = NowFrame(fab);
      now.te_step           = before + n;
      PetscCall(FramesTearStep(fab->io, &src, &now));
    }
    if (check && n % check == 0) PetscCall(CheckRupture(fab, st, row, ruptured));
  }
  if (check && n % check) PetscCall(CheckRupture(fab, st, row, ruptured));
  PetscCall(StableStepMeasureTear(fab, "end"));
  fab->step.tear   = PETSC_FALSE;
  fab->step.torn   = PETSC_TRUE; /* PaperSteps: the damped scheme relaxes the broken pieces */
  fab->step.damp_c      = damp_c;
  fab->step.window_grow = 0;
  PetscCall(StableStepAgain(fab)); /* the relaxation's te again */
  row->inner_steps += n;
  fab->stats.rupture.tear_te_steps += n;
  PetscCall(PetscInfo(NULL, "load step %" PetscInt_FMT ": a tear of %" PetscInt_FMT " te steps, the last break at %" PetscInt_FMT "%s\n",
                      fab->load.load_step, n, last, *ruptured ? ": ruptured" : ""));
  PetscFunctionReturn(0);
}

/* A balanced state of the current load step (either path): measured before anything breaks (the
   row, or the force at a first break: *measured), then the segments past their breaking strain
   break (*broke) and the tear is followed; *ruptured: the test ends. at_rest: the balanced state
   came from Newton, the velocities of an earlier tear are not its own. */
static PetscErrorCode BreakAndTear(Fabric fab, StepStats *st, PetscBool at_rest, PetscReal known, CurveRow *row, PetscBool *measured,
                                   PetscInt *broke, PetscBool *ruptured)
{
  PetscFunctionBeginUser;
  *ruptured = PETSC_FALSE;
  *measured = ReactionTest(&fab->s);
  if (*measured) PetscCall(MeasureRow(fab, st->residual, st->balanced, row));
  PetscCall(CheckBreaks(fab, *measured, known, broke));
  if (!*broke) PetscFunctionReturn(0);
  if (*measured) PeakAtBreak(fab, row);
  *measured = PETSC_FALSE; /* the row is no longer this state */
  if (at_rest) PetscCall(VecZeroEntries(fab->state.V));
  PetscCall(FollowTear(fab, st, row, ruptured));
  if (!*ruptured) PetscCall(PointLoadHeldCheck(fab)); /* before the load step relaxes (or is solved) again */
  PetscFunctionReturn(0);
}

/* Has the load step balanced? The test of every te step (st) has passed the te steps in a row the
   step control asks for (-balance_hold, doubled after each failed check, so that a test per crossing
   that keeps failing costs little), then the test per crossing on every crossing (balance.c); a
   failure wakes every sleeping crossing and the te steps go on. final: the load step ends here
   whatever the count (the test per crossing still decides whether it balanced). */
static PetscErrorCode Balanced(Fabric fab, StepStats *st, PetscBool final, PetscBool *done)
{
  StepControl    *c     = &fab->step;
  const PetscBool sleep = fab->s.num.sleep_tol > 0 ? PETSC_TRUE : PETSC_FALSE;
  BalanceCheck    chk;

  PetscFunctionBeginUser;
  *done = PETSC_FALSE;
  if (!st->balanced) {
    c->balance_held = 0;
    PetscFunctionReturn(0);
  }
  if (++c->balance_held < c->balance_need && !final) PetscFunctionReturn(0);
  PetscCall(BalanceCrossings(fab, &chk));
  c->balance_held = 0;
  /* sleeping: the te steps' test saw the awake crossings only (all asleep, it read 0): the row gets
     the test on every crossing, which must pass too */
  if (sleep) st->residual = chk.largest;
  if (chk.worst <= fab->s.num.balance_tol && (!sleep || chk.largest <= fab->s.num.balance_tol)) {
    *done = PETSC_TRUE;
    PetscFunctionReturn(0);
  }
  PetscCall(PetscInfo(NULL, "load step %" PetscInt_FMT ": balanced by the te steps' test, not at crossing (%" PetscInt_FMT ", %" PetscInt_FMT "): residual %g of its own forces, %g of the largest tension on every crossing\n",
                      fab->load.load_step, chk.i, chk.j, (double) chk.worst, (double) chk.largest));
  st->balanced    = PETSC_FALSE;
  if (c->balance_need < BALANCE_NEED_MAX) c->balance_need = PetscMin(2 * c->balance_need, BALANCE_NEED_MAX); /* never fewer */
  FrontWakeAll(fab);
  FrontKeepAwake(fab, chk.box); /* sleeping: the crossings that failed keep their te steps */
  PetscFunctionReturn(0);
}

/* a new relaxation round (a load step, or the relaxation after a tear) */
static void RoundStart(Fabric fab)
{
  fab->step.balance_held = 0;
  fab->step.balance_need = fab->s.num.balance_hold;
  FrontKeepReset(fab);
  EnergyWatchReset(fab);
}

/* After a tear the damped scheme relaxed the load step (PaperSteps): the paper scheme's two chains
   start the next one at rest where it left the points */
static PetscErrorCode PaperAtRest(Fabric fab)
{
  PetscFunctionBeginUser;
  if (!fab->step.torn) PetscFunctionReturn(0);
  fab->step.torn = PETSC_FALSE;
  if (!fab->state.Xold) PetscFunctionReturn(0);
  PetscCall(VecCopy(fab->state.X, fab->state.Xold));
  PetscCall(VecZeroEntries(fab->state.V));
  PetscCall(VecZeroEntries(fab->state.Vold));
  PetscCall(StableStepAgain(fab)); /* the paper scheme's te: the next load step's ramp is counted in it */
  PetscFunctionReturn(0);
}

/* -static_sequence: load step k solved first on the coarser fabrics, the coarsest first (each
   solve's change is the next finer one's first guess: StaticSolve); their Newton steps add to newton */
static PetscErrorCode SolveCoarser(StaticSolver ss, PetscInt k, PetscInt64 *newton)
{
  Fabric       cf;
  StaticSolver cs;
  StaticResult r;

  PetscFunctionBeginUser;
  StaticCoarser(ss, &cf, &cs);
  if (!cs) PetscFunctionReturn(0);
  PetscCall(ApplyLoadStep(cf, k));
  if (cf->load.travel_now != cf->load.travel) PetscCall(PlaceGrips(cf, cf->load.travel, PETSC_TRUE));
  cf->load.ramp_done = cf->load.ramp_steps;
  PetscCall(SolveCoarser(cs, k, newton));
  PetscCall(StaticSolve(cs, NULL, &r));
  *newton += r.nonlinear_iterations;
  PetscCall(PetscInfo(NULL, "load step %" PetscInt_FMT ": the %" PetscInt_FMT " x %" PetscInt_FMT
                            " coarse fabric %s in %" PetscInt_FMT " Newton steps, residual %g\n",
                      k, cf->s.spec.nx, cf->s.spec.ny, r.balanced ? "balanced" : "not balanced",
                      r.nonlinear_iterations, (double) r.residual));
  PetscFunctionReturn(0);
}

/* One relaxation round at the load now: te steps until balance (early exit) or max_inner_steps, from te step
   at->te_step (a restart within the round) on. *stopped: a signal's checkpoint stopped the run. Within a load
   step that has left its own load (a located break) no checkpoint is taken and no te-step frame written. */
static PetscErrorCode RelaxRound(Fabric fab, PetscInt round, RelaxPoint *at, CurveRow *row, StepStats *st,
                                 PetscBool *stopped)
{
  const Scene *s    = &fab->s;
  PetscBool    done = PETSC_FALSE;
  PetscInt     n;

  PetscFunctionBeginUser;
  *stopped       = PETSC_FALSE;
  fab->step.torn = round > 0 ? PETSC_TRUE : PETSC_FALSE; /* after a tear (also on a restart within it) */
  if (!at->te_step) RoundStart(fab); /* else restarted within the round: its state is the checkpoint's */
  for (n = at->te_step + 1; n <= s->load.max_inner_steps; n++) {
    PetscBool watched;
    PetscCall(RampGrips(fab));
    PetscCall(EnergyWatchBefore(fab, n, &watched));
    PetscCall(TimeStep(fab, st));
    if (watched) PetscCall(EnergyWatchAfter(fab, n));
    if (fab->io && !fab->load.left) PetscCall(TeStepFrame(fab)); /* -output_te_every */
    if (s->num.early_exit) {
      PetscCall(Balanced(fab, st, PETSC_FALSE, &done));
      if (done) break;
    }
    if (n < s->load.max_inner_steps) { /* the round goes on: -info says what holds it; a checkpoint within the load
                                          step, if due or signalled */
      const RelaxPoint here = {round, n, row->inner_steps, 0};
      PetscCall(RelaxInfo(fab, round, n, st));
      if (!fab->load.left) PetscCall(CheckpointTeStep(fab, &here));
      if (CheckpointStopped()) {
        *stopped = PETSC_TRUE;
        PetscFunctionReturn(0);
      }
    }
  }
  n           = PetscMin(n, s->load.max_inner_steps); /* the round's te steps */
  at->te_step = 0;
  row->inner_steps += n;
  if (!done) PetscCall(Balanced(fab, st, PETSC_TRUE, &done)); /* the last te step: checked per crossing too */
  PetscCall(PetscInfo(NULL, "load step %" PetscInt_FMT ", round %" PetscInt_FMT " at load factor %.9g: %" PetscInt_FMT
                            " te steps, %s\n", fab->load.load_step, round, (double) fab->load.load_factor, n,
                      done ? "balanced" : "not balanced"));
  PetscFunctionReturn(0);
}

typedef struct { /* a static solve's place in its load step (NewtonLook) */
  Fabric   fab;
  PetscInt round, inner_steps; /* the break round, the Newton steps of the rounds before */
} NewtonWhere;

/* after a Newton step of a solve that goes on (not a located break's trial): signals and the clock's checkpoint.
   The checkpoint holds the solve's counts so far and the shift the next Newton step takes, so that a restart goes
   on with the Newton steps the run would have taken (StaticResume). */
static PetscErrorCode NewtonLook(void *ctx, const StaticProgress *p, PetscBool *stop)
{
  const NewtonWhere *w   = (const NewtonWhere *) ctx;
  Fabric             fab = w->fab;
  const RelaxPoint   at  = {w->round, 0, w->inner_steps + p->its - p->attempt_its, p->attempt_its};
  const PetscReal    shift = fab->state.hist.shift, rnorm0 = fab->state.hist.rnorm0;
  PetscErrorCode     ierr;

  PetscFunctionBeginUser;
  *stop = PETSC_FALSE;
  if (fab->load.left) PetscFunctionReturn(0);
  fab->stats.nonlinear_iterations += p->its, fab->stats.linear_iterations += p->lits;
  fab->state.hist.shift = p->next_shift, fab->state.hist.rnorm0 = p->rnorm0;
  ierr                  = CheckpointNewtonStep(fab, &at);
  fab->stats.nonlinear_iterations -= p->its, fab->stats.linear_iterations -= p->lits;
  fab->state.hist.shift = shift, fab->state.hist.rnorm0 = rnorm0;
  PetscCall(ierr);
  *stop = CheckpointStopped();
  PetscFunctionReturn(0);
}

/* The load now balanced by either path: the relaxation's round (explicit), or Newton (ss, -solver static: the
   grips go straight to their place) */
static PetscErrorCode Settle(Fabric fab, StaticSolver ss, PetscInt round, CurveRow *row, StepStats *st, PetscBool *stopped)
{
  StaticResult      r = {0};
  PetscErrorCode    ierr;
  NewtonWhere       where;
  const StaticWatch watch = {NewtonLook, &where};

  PetscFunctionBeginUser;
  *stopped = PETSC_FALSE;
  if (!ss) {
    RelaxPoint at = {round, 0, row->inner_steps, 0};
    PetscCall(RelaxRound(fab, round, &at, row, st, stopped));
    PetscFunctionReturn(0);
  }
  if (fab->load.travel_now != fab->load.travel) PetscCall(PlaceGrips(fab, fab->load.travel, PETSC_TRUE));
  fab->load.ramp_done = fab->load.ramp_steps;
  where               = (NewtonWhere){fab, round, row->inner_steps};
  ierr                = StaticSolve(ss, fab->io ? &watch : NULL, &r); /* counted also when it stops the run: summary.json's counts */
  row->inner_steps += r.nonlinear_iterations;
  fab->stats.nonlinear_iterations += r.nonlinear_iterations;
  fab->stats.linear_iterations += r.linear_iterations;
  PetscCall(ierr);
  if (CheckpointStopped()) { /* SIGTERM or SIGUSR1 within the solve: its checkpoint is written */
    *stopped = PETSC_TRUE;
    PetscFunctionReturn(0);
  }
  if (!r.balanced)
    PetscCall(PetscInfo(NULL, "load step %" PetscInt_FMT ": not balanced (%s), residual %g\n", fab->load.load_step,
                        r.reason, (double) r.residual));
  st->residual = r.residual;
  st->speed    = 0;
  st->balanced = r.balanced;
  PetscFunctionReturn(0);
}

#define LOCATE_TRIALS 40 /* solves of a located break, at most (each trial at least halves the bracket's
                            width in two, Illinois' regula falsi) */

/* -break_locate_pct: this balanced state (load factor lB) has a segment past its breaking strain by more than
   the tolerance, and a balanced state below every breaking strain, with the segments broken now, was kept at a
   lower load (lA, state.Xbelow). The break comes between them: regula falsi on the load factor (Illinois),
   aiming at the largest ratio 1 + tol/2, each trial solved from the state below, until a trial's largest ratio
   is in (1, 1 + tol]; the load step then goes on from there (RelaxLoadStep). If a trial does not balance, or
   none comes within the tolerance, the state goes back to this one. */
static PetscErrorCode LocateBreak(Fabric fab, StaticSolver ss, PetscInt round, CurveRow *row, StepStats *st, PetscReal *known)
{
  const PetscReal tol = fab->s.rupture.locate, target = 1.0 + 0.5 * tol;
  RuptureState   *r   = &fab->stats.rupture;
  PetscReal       lA = r->below_lambda, fA = r->last_load - target, lB = fab->load.load_factor, fB;
  StepStats       stB = *st; /* of the state above: the load step's, then the lowest trial above */
  PetscInt        side = 0, trial;

  PetscFunctionBeginUser;
  *known = -1.0;
  if (!(tol > 0) || !r->have_below || !(lA < lB)) PetscFunctionReturn(0);
  PetscCall(BreakRatio(fab, &fB));
  *known = fB;
  if (!(fB > 1.0 + tol) || !(fA < 0)) PetscFunctionReturn(0);
  *known = -1.0;
  fB -= target;
  fab->load.left = PETSC_TRUE;
  {
    const FrameSource src = FramesOf(fab);
    PetscCall(FramesDropLoadStep(fab->io, &src, fab->load.load_step, fab->load.frames_below));
  }
  if (!fab->state.Xabove) PetscCall(VecDuplicate(fab->state.X, &fab->state.Xabove));
  PetscCall(VecCopy(fab->state.X, fab->state.Xabove));
  for (trial = 1; trial <= LOCATE_TRIALS; trial++) {
    PetscReal lC = lA - fA * (lB - lA) / (fB - fA), ratio;
    PetscBool stopped;
    CurveRow  scratch = *row;
    if (!(lC > lA && lC < lB)) lC = 0.5 * (lA + lB);
    if (!(lC > lA && lC < lB)) break; /* the bracket is down to rounding */
    PetscCall(RestoreAt(fab, fab->state.Xbelow, lA));
    PetscCall(ApplyLoad(fab, fab->load.load_step, lC, PETSC_FALSE));
    PetscCall(Settle(fab, ss, round, row, st, &stopped));
    if (!st->balanced) break;
    PetscCall(BreakRatio(fab, &ratio));
    PetscCall(PetscInfo(NULL, "load step %" PetscInt_FMT ": locating a break, trial %" PetscInt_FMT " at load factor %.12g: largest strain ratio %.9g\n",
                        fab->load.load_step, trial, (double) lC, (double) ratio));
    if (ratio > 1.0 && ratio <= 1.0 + tol) { /* here */
      r->located++;
      r->located_ratio = ratio;
      PetscFunctionReturn(0);
    }
    if (ratio <= 1.0) { /* the new state below */
      PetscCall(MeasureRow(fab, st->residual, PETSC_TRUE, &scratch));
      PetscCall(KeepBelow(fab, ratio, &scratch));
      lA = lC, fA = ratio - target;
      if (side < 0) fB *= 0.5; /* the same end kept twice: Illinois */
      side = -1;
    } else {
      PetscCall(VecCopy(fab->state.X, fab->state.Xabove));
      stB = *st;
      lB = lC, fB = ratio - target;
      if (side > 0) fA *= 0.5;
      side = 1;
    }
  }
  PetscCall(PetscInfo(NULL, "load step %" PetscInt_FMT ": the break was not located (%s): yarns break at load factor %.12g, the lowest balanced above the tolerance\n",
                      fab->load.load_step, trial > LOCATE_TRIALS ? "no trial within the tolerance" : st->balanced ? "the bracket is down to rounding" : "a trial did not balance",
                      (double) lB));
  PetscCall(RestoreAt(fab, fab->state.Xabove, lB));
  *st = stB; /* that state's, balanced */
  PetscFunctionReturn(0);
}

/* Yarns broke in this load step: the last load step's converged increment is the intact fabric's, not one to
   extrapolate to the load step's own load (KeepConverged forgets it at the load step's end too) */
static PetscErrorCode ForgetIncrement(Fabric fab)
{
  PetscFunctionBeginUser;
  if (fab->stats.rupture.segments != fab->state.conv_segments) PetscCall(VecDestroy(&fab->state.Xconv_prev));
  PetscFunctionReturn(0);
}

/* Balance the current load step (either path: ss, -solver static), break the yarns past their breaking
   strain and follow each tear: the load step relaxes (or is solved) again while yarns break. A located break
   (-break_locate_pct) leaves the load step at a lower load; once nothing more breaks there, the load step's own
   load is applied from that state. */
static PetscErrorCode BalanceLoadStep(Fabric fab, StaticSolver ss, CurveRow *row)
{
  const PetscReal own      = fab->load.load_factor;
  StepStats       st       = {0};
  PetscBool       measured = PETSC_FALSE;
  RelaxPoint      at       = {0, 0, 0, 0};

  PetscFunctionBeginUser;
  CheckpointRelaxStart(&at); /* restarted within this load step: where its checkpoint was taken */
  row->inner_steps = at.inner_steps + at.newton;
  if (ss && at.newton) StaticResume(ss, at.newton); /* from the checkpoint's Newton iterate */
  else if (ss) PetscCall(SolveCoarser(ss, fab->load.load_step, &fab->stats.coarse_nonlinear_iterations)); /* the grips go to their place in Settle */
  for (PetscInt round = at.round;; round++) {
    PetscInt  broke;
    PetscBool ruptured, stopped;
    PetscReal known;
    if (ss || round > at.round || !at.te_step) PetscCall(Settle(fab, ss, round, row, &st, &stopped));
    else PetscCall(RelaxRound(fab, round, &at, row, &st, &stopped)); /* the round a restart is within */
    if (stopped) PetscFunctionReturn(0);
    if (!st.balanced && fab->load.load_factor != own) { /* not balanced after a located break's tear: the load
                                                            step's own load is still to come */
      PetscCall(ForgetIncrement(fab));
      PetscCall(ApplyLoad(fab, fab->load.load_step, own, PETSC_FALSE));
      continue;
    }
    if (!st.balanced) break;
    PetscCall(LocateBreak(fab, ss, round, row, &st, &known));
    /* yarns start to break on a balanced (quasi-static) state only: the strains of the relaxation
       transient are artefacts of the load stepping. If one broke, the tear that follows is
       dynamics; then the specimen has ruptured, or this step relaxes again. */
    PetscCall(BreakAndTear(fab, &st, ss ? PETSC_TRUE : PETSC_FALSE, known, row, &measured, &broke, &ruptured));
    if (ruptured) PetscFunctionReturn(0);
    if (round >= MAX_BREAK_ROUNDS) break;
    if (broke) continue;
    if (fab->load.load_factor == own) break;
    { /* a located break's load, held now: on to the load step's own */
      CurveRow here = *row;
      if (!measured) PetscCall(MeasureRow(fab, st.residual, PETSC_TRUE, &here));
      PetscCall(KeepBelow(fab, fab->stats.rupture.load_now, &here));
      measured = PETSC_FALSE;
    }
    PetscCall(ForgetIncrement(fab));
    PetscCall(ApplyLoad(fab, fab->load.load_step, own, PETSC_FALSE));
  }
  if (ss) fab->step.torn = PETSC_FALSE; /* Newton relaxed after the tears: no te steps to follow */
  else PetscCall(PaperAtRest(fab));
  PetscCall(FinishRow(fab, st.residual, st.balanced, measured, row));
  PetscFunctionReturn(0);
}

/* remember the converged state of the last two load steps (extrapolating prediction); if yarns broke since the
   last, it is forgotten: the fabric is another, and the tear's motion extrapolated would be predicted again (the
   next load step then takes the linear prediction) */
static PetscErrorCode KeepConverged(Fabric fab)
{
  Vec t;

  PetscFunctionBeginUser;
  if (fab->s.num.predict != PREDICT_EXTRAPOLATE) PetscFunctionReturn(0);
  if (!fab->state.Xconv) {
    PetscCall(VecDuplicate(fab->state.X, &fab->state.Xconv));
    PetscCall(VecCopy(fab->grid.X0, fab->state.Xconv));
  }
  if (!fab->state.Xconv_prev) PetscCall(VecDuplicate(fab->state.X, &fab->state.Xconv_prev));
  t                     = fab->state.Xconv_prev;
  fab->state.Xconv_prev = fab->state.Xconv;
  fab->state.Xconv      = t;
  PetscCall(VecCopy(fab->state.X, fab->state.Xconv));
  if (fab->stats.rupture.segments != fab->state.conv_segments) PetscCall(VecDestroy(&fab->state.Xconv_prev));
  fab->state.conv_segments = fab->stats.rupture.segments;
  PetscFunctionReturn(0);
}

PetscErrorCode FabricRun(Fabric fab)
{
  const Scene      *s   = &fab->s;
  const FrameSource src = FramesOf(fab); /* the state vectors are the fabric's for the whole run */
  FrameInfo         f;
  StaticSolver      ss       = NULL;
  PetscBool         ruptured = PETSC_FALSE, stepped = PETSC_FALSE;
  PetscBool         warned   = PETSC_FALSE; /* -solver static: the options its solves have not read, named */

  PetscFunctionBeginUser;
  PetscCall(PetscTime(&fab->stats.wall_start));
  PetscCall(StableStep(fab));         /* refuses a -te above the bound before any output exists */
  fab->step.bound_fresh = PETSC_TRUE; /* taken at the state the run starts from */
  /* the static solver's scales from the rest state's stable step, before a restart's state replaces
     it (a restart then solves as the run it continues) */
  if (s->num.solver == SOLVER_STATIC) PetscCall(StaticCreate(fab, &ss));
  PetscCall(RestartLoad(fab)); /* -restart: state, counters and curve rows of the checkpoint */
  PetscCall(OutputOpen(fab));
  f = NowFrame(fab); /* the state the run starts from */
  if (CheckpointResumesLoadStep()) { /* a restart within load step k: frame 0 (if frames were off) is a state of it */
    f.load_step = fab->load.load_step + 1;
    if (fab->io && fab->io->te_load_step == f.load_step) f.te_step = (PetscInt) (fab->stats.te_steps - fab->io->te_base);
    if (!s->out.output_te_every && !s->out.output_tear_every) /* load step frames at their time_s: before k's */
      f.time = fab->load.load_step > 0 ? fab->stats.curve[fab->load.load_step - 1].time : 0;
  } else if (fab->load.load_step > 0 && !s->out.output_te_every &&
             !s->out.output_tear_every) /* a restart at a load step's end: frame 0 (if frames were off) at its time_s */
    f.time = fab->stats.curve[fab->load.load_step - 1].time;
  PetscCall(FramesOpen(fab->io, &src, &f)); /* fabric.h5 and fabric.xmf */
  for (PetscInt k = fab->load.load_step + 1; k <= s->load.load_steps && !fab->stats.rupture.rupture_step; k++) {
    CurveRow *row = &fab->stats.curve[k - 1];
    stepped       = PETSC_TRUE;
    if (!CheckpointWithinLoadStep(fab, k)) PetscCall(ApplyLoadStep(fab, k)); /* else restarted within it */
    PetscCall(BalanceLoadStep(fab, ss, row));
    if (CheckpointStopped()) break; /* SIGTERM or SIGUSR1: its checkpoint is written */
    ruptured = fab->stats.rupture.rupture_step == k;
    if (!ruptured) PetscCall(BallPassedCheck(fab)); /* the pushing test: the fabric still before the ball */
    if (!ruptured) PetscCall(PointLoadHeldCheck(fab)); /* a point load: its crossing still held */
    if (!row->balanced && !ruptured) fab->stats.converged = PETSC_FALSE; /* a tear is not meant to balance */
    PetscCall(KeepConverged(fab));
    PetscCall(PetscTime(&fab->stats.wall));
    fab->stats.wall -= fab->stats.wall_start;
    PetscCall(OutputCurveRow(fab, row));
    fab->stats.rows_done = k;
    f = (FrameInfo){row->time, row->load_step, row->inner_steps};
    PetscCall(FramesLoadStep(fab->io, &src, &f, fab->load.elapsed, row->load_step == s->load.load_steps, ruptured));
    PetscCall(OutputProgress(fab, row));
    if (ss && !warned && fab->stats.linear_iterations > 0) { /* misspelt -snes_*, once a linear solve has set up the PC */
      char when[64];
      PetscCall(PetscSNPrintf(when, sizeof when, "by the solves up to load step %" PetscInt_FMT, k));
      PetscCall(SceneWarnUnused(fab->comm, when));
      warned = PETSC_TRUE;
    }
    PetscCall(CheckpointLoadStep(fab));
    if (ruptured) break; /* the test ends: the specimen has broken */
    if (k < s->load.load_steps) { /* a signal: the load step's checkpoint, then stop (the explicit path looks within
                                     load steps too) */
      PetscCall(CheckpointLoadStepLook(fab, ss ? PETSC_TRUE : PETSC_FALSE));
      if (CheckpointStopped()) break;
    }
  }
  if (!CheckpointStopped()) { /* also when no load step ran (a restart from the last one's checkpoint) */
    PetscCall(PetscTime(&fab->stats.wall));
    fab->stats.wall -= fab->stats.wall_start; /* the run before the restart and this one */
  }
  if (!stepped && s->test == TEST_DRAPE && fab->load.load_step > 0) { /* drape_pct, folds: the checkpoint's state */
    CurveRow scratch = fab->stats.curve[fab->load.load_step - 1];  /* its row stays the checkpoint's */
    PetscCall(DrapeOutline(fab, &scratch));
  }
  if (!CheckpointStopped()) PetscCall(StableStepMeasureLast(fab)); /* with the static path's tangent, as the others */
  PetscCall(StaticDestroy(&ss));
  if (CheckpointStopped()) PetscFunctionReturn(0);
  PetscCall(OutputSummary(fab, NULL, PETSC_TRUE));
  if (s->out.positions_out[0]) PetscCall(OutputPositions(fab, s->out.positions_out));
  PetscFunctionReturn(0);
}
