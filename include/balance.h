/* balance.h - the checks that end or stop the relaxation of a load step (MODEL.md 8, 15): the
 * balance test per crossing and the energy watch (balance.c). */
#ifndef FABRIC_BALANCE_H
#define FABRIC_BALANCE_H

#include "fabric.h"

/* The balance test per crossing, on every crossing (sleeping ones and those the front has not
   reached included), at the current positions: each free crossing's residual force against the sum
   of the magnitudes of its own force terms (every yarn segment, bending centre and shear crossing
   acting on it, its weight, the point load, the bodies' contact), never below -balance_floor of the
   largest yarn tension nor below the force floor. The same on any number of ranks (max-reductions). */
typedef struct {
  PetscReal worst;   /* the largest ratio */
  PetscInt  i, j;    /* where (the lowest global index on a tie) */
  PetscReal largest; /* the test of every te step, on every crossing: the largest free force over the largest tension */
  PetscInt  box[4];  /* global bounding box of the crossings that fail either test (empty: none) */
} BalanceCheck;
PetscErrorCode BalanceCrossings(Fabric fab, BalanceCheck *c);

/* -info, at te steps 1024, 2048, 4096, ... of a relaxation round that has not ended: the te steps' test (residual,
   largest speed, on the crossings that te step moved), the fastest free crossing, how many free crossings move faster
   than the speed test's tolerance (-speed_tol), and the shares of sum |v|^2 along x (warp), y (weft) and z (exact
   sums: the same on any number of ranks): what holds the round. Sleeping crossings count with the velocity they
   fell asleep with (at most -speed_tol). */
PetscErrorCode RelaxInfo(Fabric fab, PetscInt round, PetscInt n, const StepStats *st);

/* The pushing test, before a load step's row is written: a free crossing within the ball's silhouette (closer
   to the axis of its path than its radius) and behind its centre along the path, ahead of the ball's start at rest,
   has been passed through (a ball that starts beyond the fabric and moves away from it passes nothing).
   Contact acts on the crossings alone: yarns strained far past any real yarn's strength (no breaking strain)
   let the ball slip between them. Stops the run naming the crossing; not once a yarn has broken (the ball may
   go through the hole). */
PetscErrorCode BallPassedCheck(Fabric fab);

/* After a tear that left the specimen whole, and before a load step's row is written, once yarns have broken: the
   crossing the point load (-point_load_N) acts on still has a yarn segment, and (the square net, whose rows report
   its travel) has not moved farther than the fabric's size from its place at rest (a piece torn out with it). Else nothing holds it against the load: it flew
   off (the square net's rows said 240 m of travel, every load step after unbalanced) or Newton diverged with a
   message that blamed the solver. Stops the run naming the crossing and the options. */
PetscErrorCode PointLoadHeldCheck(Fabric fab);

/* The energy watch (damped and paper integrators): every ENERGY_WATCH_EVERY te steps of a
   relaxation with nothing doing work on the fabric, the mechanical energy H (below) is taken
   across one te step. EnergyWatchBefore, before te step n of the relaxation round, says whether
   this one is watched and keeps what H needs; EnergyWatchAfter, after it, stops the run with an
   error naming the crossing that moves most if H has grown above its lowest by more than
   -energy_watch times the energy the round released plus its largest kinetic energy. */
PetscErrorCode EnergyWatchBefore(Fabric fab, PetscInt n, PetscBool *due);
PetscErrorCode EnergyWatchAfter(Fabric fab, PetscInt n);
/* a new relaxation round (a load step, or the relaxation after a tear): the watch starts again */
void EnergyWatchReset(Fabric fab);

#endif
