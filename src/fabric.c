/* fabric.c - building the fabric: grid, rest state, masses (MODEL.md 2, 4), clamps and grips (6).
 *
 * The warp x weft grid is a DMDA with dof 3 (x, y, z) and a box stencil of width 2:
 * bending reaches two points along a yarn and shear reaches the diagonal neighbours,
 * so each rank computes the forces on its own points from its ghosts.
 */
#include "fabric.h"
#include "comm.h"
#include "events.h"
#include "front.h"
#include "predict.h"
#include "frames.h"
#include "stencil.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <sys/resource.h>
#include <stdlib.h>
#include <strings.h> /* strcasecmp */
#include <unistd.h>

#define YARN_K_MIN 1e-100 /* N/m: the least yarn segment stiffness EA/L0 (CheckStiffnessAndMass) */

/* Position of crossing (i,j) relative to the grid centre at rest, m. (i - (nx-1)/2) is exact,
   so mirrored crossings get mirrored coordinates and the shapes keep the grid's symmetries. */
static void FromCentre(const Scene *s, PetscInt i, PetscInt j, PetscReal *x, PetscReal *y)
{
  *x = (i - 0.5 * (s->spec.nx - 1)) / s->spec.picks_per_m;
  *y = (j - 0.5 * (s->spec.ny - 1)) / s->spec.ends_per_m;
}

/* A bias specimen's coordinates of crossing (i,j) at rest, m: along the specimen (the grid
   diagonal) and across it, from its centre. */
void BiasCoords(const Scene *s, PetscInt i, PetscInt j, PetscReal *along, PetscReal *across)
{
  PetscReal x, y;
  FromCentre(s, i, j, &x, &y);
  *along  = (x + y) / PetscSqrtReal(2.0);
  *across = (y - x) / PetscSqrtReal(2.0);
}

/* Is crossing (i,j) in the bias specimen's central zone, where curve.csv's center_shear_deg is measured: within
   min(W, D)/4 of its centre along and across it, D = gauge - width (a square inside the pure-shear zone) */
PetscBool BiasCentreZone(const Scene *s, PetscInt i, PetscInt j)
{
  const PetscReal half = 0.25 * PetscMin(s->spec.width, s->spec.gauge - s->spec.width) +
                         1e-9 * s->spec.gauge; /* crossings on its edge count */
  PetscReal       along, across;
  BiasCoords(s, i, j, &along, &across);
  return PetscAbsReal(along) <= half && PetscAbsReal(across) <= half ? PETSC_TRUE : PETSC_FALSE;
}

PetscBool PaperSteps(const Fabric fab)
{
  return fab->s.num.integrator == INTEGRATOR_PAPER && !fab->step.tear && !fab->step.torn ? PETSC_TRUE : PETSC_FALSE;
}

/* Does crossing (i,j) exist? The shape cuts the grid: a point outside it has no mass, no
   segment and no force (the kernels read the ghosted mask patch.exists). */
static int PointExists(const Scene *s, PetscInt i, PetscInt j)
{
  PetscReal x, y;
  if (i < 0 || i >= s->spec.nx || j < 0 || j >= s->spec.ny) return 0;
  switch (s->spec.shape) {
  case SHAPE_RECTANGLE: return 1;
  case SHAPE_DISC:
    FromCentre(s, i, j, &x, &y);
    return x * x + y * y <= s->spec.disc_radius * s->spec.disc_radius * (1.0 + 1e-12);
  case SHAPE_BIAS: {
    const PetscReal tol = 1e-9 * s->spec.gauge;
    BiasCoords(s, i, j, &x, &y);
    return PetscAbsReal(x) <= 0.5 * s->spec.gauge + s->spec.jaw_depth + tol &&
           PetscAbsReal(y) <= 0.5 * s->spec.width + tol;
  }
  }
  return 0;
}

/* Is crossing (i,j) within the band of a line (x, y, angle, half-width) across the grid? */
static int OnLine(const Scene *s, const PetscReal line[4], PetscInt i, PetscInt j)
{
  PetscReal x, y;
  FromCentre(s, i, j, &x, &y);
  return PetscAbsReal(-(x - line[0]) * PetscSinReal(line[2]) + (y - line[1]) * PetscCosReal(line[2])) <=
         line[3] * (1.0 + 1e-9);
}

/* The clamp region (MODEL.md 6); the strip's moving jaw is its grip. */
static PointKind RegionKind(const Scene *s, PetscInt i, PetscInt j)
{
  PetscReal x, y, r2;
  switch (s->clamps.clamp) {
  case CLAMP_JAW: {                    /* clamped jaw at the start of the pull axis, moving jaw at its end */
    if (s->spec.shape == SHAPE_BIAS) { /* the jaws hold the specimen beyond the lines |s| = gauge/2 across it */
      const PetscReal tol = 1e-9 * s->spec.gauge;
      PetscReal       along, across;
      BiasCoords(s, i, j, &along, &across);
      return along <= -0.5 * s->spec.gauge + tol ? POINT_CLAMPED
                                                 : (along >= 0.5 * s->spec.gauge - tol ? POINT_GRIP : POINT_FREE);
    }
    const PetscInt along = s->spec.pull == PULL_WARP ? i : j, n = s->spec.pull == PULL_WARP ? s->spec.nx : s->spec.ny;
    if (along == 0) return POINT_CLAMPED;
    if (along == n - 1) return POINT_GRIP;
    return POINT_FREE;
  }
  case CLAMP_EDGE: /* the shape's outline: an existing crossing with a missing yarn neighbour */
    return (!PointExists(s, i - 1, j) || !PointExists(s, i + 1, j) || !PointExists(s, i, j - 1) ||
            !PointExists(s, i, j + 1))
               ? POINT_CLAMPED
               : POINT_FREE;
  case CLAMP_RING:
    FromCentre(s, i, j, &x, &y);
    r2 = x * x + y * y;
    return (r2 >= s->clamps.ring[0] * s->clamps.ring[0] * (1.0 - 1e-12) &&
            r2 <= s->clamps.ring[1] * s->clamps.ring[1] * (1.0 + 1e-12))
               ? POINT_CLAMPED
               : POINT_FREE;
  case CLAMP_NONE: return POINT_FREE;
  }
  return POINT_FREE;
}

/* The clamp region, then the clamp lines and the grip lines over it (they never overlap:
   FabricCreate checks it). */
static PointKind KindOf(const Scene *s, PetscInt i, PetscInt j)
{
  for (PetscInt l = 0; l < s->clamps.grip_lines; l++)
    if (OnLine(s, s->clamps.grip_line[l], i, j)) return POINT_GRIP;
  for (PetscInt l = 0; l < s->clamps.clamp_lines; l++)
    if (OnLine(s, s->clamps.clamp_line[l], i, j)) return POINT_CLAMPED;
  return RegionKind(s, i, j);
}

/* Every clamp or grip line, and a clamping ring, selects crossings of the specimen, and no crossing
   is on both a clamp line and a grip line, nor on a line of the other kind than its clamp region's
   (a clamp line in the moving jaw, a grip line in the fixed jaw or a clamped edge: the line took them
   over without a word) (integer counts: exact on any number of ranks). */
#define LINE_COUNTS (4 * MAX_LINES + MAX_LINES * MAX_LINES + 2)
static PetscErrorCode CheckLines(Fabric fab, const DMDALocalInfo *info)
{
  const Scene *s                  = &fab->s;
  const int    ring               = s->clamps.clamp == CLAMP_RING;
  PetscInt     count[LINE_COUNTS] = {0};
  PetscInt    *both = count + 2 * MAX_LINES, *ringed = both + MAX_LINES * MAX_LINES, *clash = ringed + 1;
  PetscInt    *freed = clash + 2 * MAX_LINES; /* the crossings left free */

  PetscFunctionBeginUser;
  if (!s->clamps.clamp_lines && !s->clamps.grip_lines && !ring) PetscFunctionReturn(0);
  for (PetscInt j = info->ys; j < info->ys + info->ym; j++)
    for (PetscInt i = info->xs; i < info->xs + info->xm; i++) {
      if (!PointExists(s, i, j)) continue;
      const PointKind region = RegionKind(s, i, j);
      if (ring) *ringed += region == POINT_CLAMPED;
      *freed += KindOf(s, i, j) == POINT_FREE;
      for (PetscInt c = 0; c < s->clamps.clamp_lines; c++) {
        const int on = OnLine(s, s->clamps.clamp_line[c], i, j);
        count[c] += on;
        clash[c] += on && region == POINT_GRIP;
      }
      for (PetscInt g = 0; g < s->clamps.grip_lines; g++) {
        const int on = OnLine(s, s->clamps.grip_line[g], i, j);
        count[MAX_LINES + g] += on;
        clash[MAX_LINES + g] += on && region == POINT_CLAMPED;
        for (PetscInt c = 0; c < s->clamps.clamp_lines; c++)
          both[g * MAX_LINES + c] += on && OnLine(s, s->clamps.clamp_line[c], i, j);
      }
    }
  PetscCall(GlobalSumInt(fab->comm, count, LINE_COUNTS));
  PetscCheck(!ring || *ringed > 0, fab->comm, PETSC_ERR_USER_INPUT,
             "-clamp ring with -clamp_ring_mm %.6g,%.6g (inner, outer diameter) selects no crossing of the specimen",
             (double) (2e3 * s->clamps.ring[0]), (double) (2e3 * s->clamps.ring[1]));
  for (PetscInt c = 0; c < s->clamps.clamp_lines; c++)
    PetscCheck(count[c] > 0, fab->comm, PETSC_ERR_USER_INPUT,
               "-clamp_line_mm line %" PetscInt_FMT
               " (%g,%g mm at %g deg, half-width %g mm) selects no crossing of the specimen",
               c + 1, (double) (1e3 * s->clamps.clamp_line[c][0]), (double) (1e3 * s->clamps.clamp_line[c][1]),
               (double) (s->clamps.clamp_line[c][2] * 180.0 / PETSC_PI), (double) (1e3 * s->clamps.clamp_line[c][3]));
  for (PetscInt c = 0; c < s->clamps.clamp_lines; c++)
    PetscCheck(clash[c] == 0, fab->comm, PETSC_ERR_USER_INPUT,
               "-clamp_line_mm line %" PetscInt_FMT " takes %" PetscInt_FMT
               " crossings of the moving jaw: a crossing cannot be clamped and gripped; keep the line off the jaw",
               c + 1, clash[c]);
  for (PetscInt g = 0; g < s->clamps.grip_lines; g++)
    PetscCheck(clash[MAX_LINES + g] == 0, fab->comm, PETSC_ERR_USER_INPUT,
               "-grip_line_mm line %" PetscInt_FMT " takes %" PetscInt_FMT
               " clamped crossings (-clamp %s): a crossing cannot be clamped and gripped; keep the line off them",
               g + 1, clash[MAX_LINES + g], ClampNames[s->clamps.clamp]);
  for (PetscInt g = 0; g < s->clamps.grip_lines; g++) {
    PetscCheck(count[MAX_LINES + g] > 0, fab->comm, PETSC_ERR_USER_INPUT,
               "-grip_line_mm line %" PetscInt_FMT
               " (%g,%g mm at %g deg, half-width %g mm) selects no crossing of the specimen",
               g + 1, (double) (1e3 * s->clamps.grip_line[g][0]), (double) (1e3 * s->clamps.grip_line[g][1]),
               (double) (s->clamps.grip_line[g][2] * 180.0 / PETSC_PI), (double) (1e3 * s->clamps.grip_line[g][3]));
    for (PetscInt c = 0; c < s->clamps.clamp_lines; c++)
      PetscCheck(both[g * MAX_LINES + c] == 0, fab->comm, PETSC_ERR_USER_INPUT,
                 "-grip_line_mm line %" PetscInt_FMT " and -clamp_line_mm line %" PetscInt_FMT " share %" PetscInt_FMT
                 " crossings: a crossing cannot be clamped and gripped",
                 g + 1, c + 1, both[g * MAX_LINES + c]);
  }
  if (!*freed) {
    char ringmm[64] = "";
    if (ring) PetscCall(PetscSNPrintf(ringmm, sizeof ringmm, " -clamp_ring_mm %g,%g", (double) (2e3 * s->clamps.ring[0]), (double) (2e3 * s->clamps.ring[1])));
    SETERRQ(fab->comm, PETSC_ERR_USER_INPUT,
            "-clamp %s%s with %" PetscInt_FMT " -clamp_line_mm and %" PetscInt_FMT
            " -grip_line_mm lines holds every crossing of the specimen: none is left free to move; narrow the "
            "clamping ring or the lines",
            ClampNames[s->clamps.clamp], ringmm, s->clamps.clamp_lines, s->clamps.grip_lines);
  }
  PetscFunctionReturn(0);
}

/* A bias specimen's jaws each hold crossings, and its central zone holds one with a yarn neighbour along each
   family (its shear angle is defined): with unequal densities the grid's diagonals are not the specimen's, and
   a shallow jaw or a narrow specimen can fall between the crossings (integer counts: exact on any number of
   ranks) */
static PetscErrorCode CheckBias(Fabric fab, const DMDALocalInfo *info)
{
  const Scene *s        = &fab->s;
  PetscInt     count[3] = {0, 0, 0}; /* the fixed jaw's crossings, the moving jaw's, the central zone's */

  PetscFunctionBeginUser;
  if (s->test != TEST_BIAS) PetscFunctionReturn(0);
  for (PetscInt j = info->ys; j < info->ys + info->ym; j++)
    for (PetscInt i = info->xs; i < info->xs + info->xm; i++) {
      if (!PointExists(s, i, j)) continue;
      if (s->clamps.clamp == CLAMP_JAW) {
        const PointKind region = RegionKind(s, i, j);
        count[0] += region == POINT_CLAMPED;
        count[1] += region == POINT_GRIP;
      }
      count[2] += BiasCentreZone(s, i, j) && (PointExists(s, i - 1, j) || PointExists(s, i + 1, j)) &&
                  (PointExists(s, i, j - 1) || PointExists(s, i, j + 1));
    }
  PetscCall(GlobalSumInt(fab->comm, count, 3));
  PetscCheck(s->clamps.clamp != CLAMP_JAW || (count[0] > 0 && count[1] > 0), fab->comm, PETSC_ERR_USER_INPUT,
             "-jaw_depth_mm %.6g at -ends_per_cm %.6g, -picks_per_cm %.6g: the bias specimen's %s jaw holds no crossing "
             "(with unequal densities the jaws are not rounded to the grid); make the jaws deeper than a yarn spacing",
             (double) (1e3 * s->spec.jaw_depth), (double) (1e-2 * s->spec.ends_per_m),
             (double) (1e-2 * s->spec.picks_per_m), count[0] > 0 ? "moving" : "fixed");
  PetscCheck(count[2] > 0, fab->comm, PETSC_ERR_USER_INPUT,
             "-width_mm %.6g, -gauge_mm %.6g at -ends_per_cm %.6g, -picks_per_cm %.6g: the bias specimen's central zone "
             "(within %.6g mm of its centre, where curve.csv's center_shear_deg is measured) holds no crossing; make the "
             "specimen wider or the thread densities higher",
             (double) (1e3 * s->spec.width), (double) (1e3 * s->spec.gauge), (double) (1e-2 * s->spec.ends_per_m),
             (double) (1e-2 * s->spec.picks_per_m),
             (double) (250 * PetscMin(s->spec.width, s->spec.gauge - s->spec.width)));
  PetscFunctionReturn(0);
}

/* an a x b split of an nx x ny grid leaves every rank at least 2 crossings (the stencil width)
   along each direction it splits */
static inline PetscBool SplitFits(PetscInt nx, PetscInt ny, PetscInt a, PetscInt b)
{
  return (a == 1 || nx / a >= 2) && (b == 1 || ny / b >= 2) ? PETSC_TRUE : PETSC_FALSE;
}

/* how well the quasi-static path's multigrid fits an a x b split of an nx x ny grid (MultigridCoarsens), the
   smaller the better: 2^40 with no coarser level (its preconditioner is then GAMG, which does not balance the
   slack nets: a 25 x 25 net on 4 ranks in rows), else the coarsest level's points (solved directly) but at
   least CoarsestEnough */
#define CoarsestEnough 4096
static PetscReal MultigridFit(PetscInt nx, PetscInt ny, PetscInt a, PetscInt b)
{
  PetscInt levels = 0;
  for (; levels < MG_MAX_LEVELS - 1 && MultigridCoarsens(nx, ny, a, b); levels++) nx = nx / 2 + 1, ny = ny / 2 + 1;
  return levels == 0 ? 1099511627776.0 : PetscMax((PetscReal) nx * ny, CoarsestEnough);
}

/* m x n = size ranks with at least 2 crossings per rank along each split direction (the
   stencil width), the split whose halo exchange moves the fewest points; m = 0 if there is none.
   A patch of 2 ghost rows or columns on each inner side sends and receives its ghost points (each
   counted twice: packed and unpacked), and a patch with ghost columns also copies its owned
   points (comm.c: only a patch that spans its rows keeps its positions in their ghosted home), so
   a split in rows alone is taken while it leaves each rank about 8 rows or more. levels (the
   quasi-static path): among the splits its multigrid fits best (MultigridFit) */
static PetscErrorCode RankGrid(PetscInt nx, PetscInt ny, PetscMPIInt size, PetscBool levels, PetscInt *m, PetscInt *n)
{
  PetscReal best = PETSC_MAX_REAL, fit_best = PETSC_MAX_REAL;

  PetscFunctionBeginUser;
  *m = *n = 0;
  for (PetscInt a = 1; a <= size; a++) {
    const PetscInt b = size / a;
    if (size % a || !SplitFits(nx, ny, a, b)) continue;
    const PetscReal fit = levels ? MultigridFit(nx, ny, a, b) : 0;
    const PetscReal w = (PetscReal) nx / a, h = (PetscReal) ny / b;
    const PetscReal ghosts = (a > 1 ? 4 * h : 0) + (b > 1 ? 4 * w : 0) + (a > 1 && b > 1 ? 16 : 0);
    const PetscReal moved  = 2 * ghosts + (a > 1 ? w * h : 0);
    if (fit < fit_best || (fit == fit_best && moved < best)) {
      best     = moved;
      fit_best = fit;
      *m   = a;
      *n   = b;
    }
  }
  PetscFunctionReturn(0);
}

/* a rank count option read as text: PETSc's own reading wraps 4294967297 to 1 */
static PetscErrorCode RankCountOption(MPI_Comm comm, const char *name, PetscInt *v, PetscBool *set)
{
  char      text[64], *end;
  long long l;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, name, text, sizeof text, set));
  if (!*set) PetscFunctionReturn(0);
  errno = 0;
  l     = strtoll(text, &end, 10);
  PetscCheck(end != text && !*end && errno != ERANGE && l >= 1 && l <= PETSC_MAX_INT, comm, PETSC_ERR_USER_INPUT,
             "%s %s: not a number of ranks (a whole number from 1)", name, text);
  *v = (PetscInt) l;
  PetscFunctionReturn(0);
}

/* PETSc's -da_processors_x and -da_processors_y, checked here on every rank alike (the DMDA would
   fail on some ranks only): a split of the size, 2 crossings a rank at least along a split
   direction; one of them given, the other is the rest of the ranks */
static PetscErrorCode UserRankGrid(PetscInt nx, PetscInt ny, PetscMPIInt size, MPI_Comm comm, PetscInt *m, PetscInt *n)
{
  PetscInt  px = 0, py = 0;
  PetscBool hx = PETSC_FALSE, hy = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(RankCountOption(comm, "-da_processors_x", &px, &hx));
  PetscCall(RankCountOption(comm, "-da_processors_y", &py, &hy));
  if (!hx && !hy) PetscFunctionReturn(0);
  PetscCheck(!hx || (px >= 1 && px <= size && size % px == 0), comm, PETSC_ERR_USER_INPUT,
             "-da_processors_x %" PetscInt_FMT ": must divide the %d ranks", px, size);
  PetscCheck(!hy || (py >= 1 && py <= size && size % py == 0), comm, PETSC_ERR_USER_INPUT,
             "-da_processors_y %" PetscInt_FMT ": must divide the %d ranks", py, size);
  if (!hx) px = size / py;
  if (!hy) py = size / px;
  PetscCheck(px * py == size, comm, PETSC_ERR_USER_INPUT,
             "-da_processors_x %" PetscInt_FMT " -da_processors_y %" PetscInt_FMT ": their product must be the %d ranks", px,
             py, size);
  PetscCheck(SplitFits(nx, ny, px, py), comm, PETSC_ERR_USER_INPUT,
             "-da_processors_x %" PetscInt_FMT " -da_processors_y %" PetscInt_FMT ": grid too small: %" PetscInt_FMT
             " x %" PetscInt_FMT " crossings leave a rank fewer than 2 crossings along a split direction",
             px, py, nx, ny);
  *m = px, *n = py;
  PetscFunctionReturn(0);
}

/* A grid this node cannot hold is refused before anything is allocated: the kernel's out-of-memory
   killer would stop the run without a word. A crossing takes about BYTES_PER_CROSSING (its state,
   masses, kinds and the force rows: 262 B between the peak resident sizes of the square test at
   1001 x 1001 and 3001 x 3001 crossings, one rank; with -solver static about BYTES_STATIC, the
   square net's 5 823 MiB at 1601 x 1601 in docs/static.md), shared among the ranks; the ranks on
   this node together need their share of the memory the node has available (Linux's MemAvailable,
   else its physical memory), and each rank its share within its address-space limit (ulimit -v),
   if one is set. What options add is counted too, from the peak resident sizes of the strip at 3000 and
   13000 mm on one rank (B a crossing: 271 with -output_dir none; 309 with frames, 38 more; 337 with -integrator
   paper, 66 more; the vectors alone are 48 B each, the rest their scatters and work arrays); the address space
   each of 2 ranks maps grows by 306 B a crossing (256 B let a rank within its ulimit -v fail in its allocations),
   and what a rank has mapped already (its libraries, MPI's segments: about 0.3 GB) is not free under its limit. */
#define BYTES_PER_CROSSING 310.0  /* the address space a rank maps, 2 ranks (306 B), above the resident size */
#define BYTES_STATIC       2300.0 /* (on a grid too small for multigrid each rank holds the whole LU: small ones) */
#define BYTES_FRAMES       40.0   /* fabric.h5's frames: the displacement and the point fields (38 B measured) */
#define BYTES_PAPER        72.0   /* -integrator paper's x(n-1) and V(n-1) (66 B measured) */
#define BYTES_EXTRAPOLATE  48.0   /* -predict extrapolate's converged states of the last two load steps */
#define BYTES_HELP         60.0   /* -help: the grid's DMDA alone (46 B measured on large.yaml, 1 rank) */
#define BYTES_TE_MEASURE   940.0  /* -te_measure's tangent block rows (936 B, docs/options.md) */
#define BYTES_STATIC_AIJ   7500.0 /* -static_tangent aij: 7.4 KB measured on large.yaml cut to 481 x 481 (docs/static.md) */
static double NodeMemory(void)
{
  FILE  *fp = fopen("/proc/meminfo", "r");
  char   line[256];
  double kb = -1;

  while (fp && fgets(line, sizeof line, fp))
    if (sscanf(line, "MemAvailable: %lf kB", &kb) == 1) break;
  if (fp) fclose(fp);
  return kb > 0 ? 1024 * kb : (double) sysconf(_SC_PHYS_PAGES) * (double) sysconf(_SC_PAGESIZE);
}

static PetscErrorCode CheckMemory(Fabric fab, PetscBool help)
{
  const SceneInput  *in     = &fab->s.in;
  const SceneOutput *o      = &fab->s.out;
  const PetscBool    frames = o->output_dir[0] && (o->output_every > 0 || o->output_te_every > 0 ||
                                                 o->output_tear_every > 0);
  const double       node   = NodeMemory();
  char               tangent[16] = "";
  PetscBool          aij = PETSC_FALSE;
  double             bytes, share, limit = -1;
  struct rlimit      as;
  MPI_Comm           shm;
  PetscMPIInt        here = 1;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-static_tangent", tangent, sizeof tangent, &aij)); /* static.c's */
  aij   = aij && !strcasecmp(tangent, "aij") ? PETSC_TRUE : PETSC_FALSE;
  bytes = help ? BYTES_HELP
               : (fab->s.num.solver == SOLVER_STATIC ? (aij ? BYTES_STATIC_AIJ : BYTES_STATIC) : BYTES_PER_CROSSING) +
                     (fab->s.num.te_measure > 0 ? BYTES_TE_MEASURE : 0.0) + (frames ? BYTES_FRAMES : 0.0) +
                     (fab->s.num.integrator == INTEGRATOR_PAPER ? BYTES_PAPER : 0.0) +
                     (fab->s.num.predict == PREDICT_EXTRAPOLATE ? BYTES_EXTRAPOLATE : 0.0);
  share = bytes * (double) fab->s.spec.nx * (double) fab->s.spec.ny / fab->size;
  PetscCallMPI(MPI_Comm_split_type(fab->comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &shm));
  PetscCallMPI(MPI_Comm_size(shm, &here));
  PetscCallMPI(MPI_Comm_free(&shm));
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) { /* less what the rank maps already */
    FILE  *fp    = fopen("/proc/self/statm", "r"); /* (its libraries, MPI's segments: ~0.3 GB) */
    double pages = 0;
    limit        = (double) as.rlim_cur;
    if (fp && fscanf(fp, "%lf", &pages) == 1) limit = PetscMax(limit - pages * (double) sysconf(_SC_PAGESIZE), 1.0);
    if (fp) fclose(fp);
  }
  { /* the least room of any rank, as a share of its node and within its limit (negated: a max) */
    PetscReal      room[2] = {-(node > 0 ? node / here : PETSC_MAX_REAL), -(limit > 0 ? limit : PETSC_MAX_REAL)};
    PetscBool      bad;
    int            w;
    PetscCall(GlobalMax(fab->comm, room, 2)); /* every rank refuses alike, and says the same */
    w   = -room[0] <= -room[1] ? 0 : 1;
    bad = share > -room[w] ? PETSC_TRUE : PETSC_FALSE;
    char           width[64];
    PetscCall(SceneWidthText(in, "%g", width, sizeof width));
    PetscCheck(!bad, fab->comm, PETSC_ERR_USER_INPUT,
               "-gauge_mm %g %s -ends_per_cm %g -picks_per_cm %g: %" PetscInt_FMT " x %" PetscInt_FMT
               " crossings need about %.3g GB (%.0f B a crossing): %.3g GB for a rank, more than %s %.3g GB",
               (double) in->gauge_mm, width, (double) in->ends_per_cm, (double) in->picks_per_cm,
               fab->s.spec.nx, fab->s.spec.ny, 1e-9 * share * fab->size, bytes, 1e-9 * share,
               w == 0 ? "its share of the node's available memory,"
                      : "what its address-space limit (ulimit -v) leaves it,",
               1e-9 * -room[w]);
  }
  PetscFunctionReturn(0);
}

/* the DMDA (dof 3, box stencil of width 2) and its dof-2 twin; the rank grid is picked here, since a patch narrower
 * than the stencil makes the DMDA fail on some ranks only (and the others wait forever) */
static PetscErrorCode CreateGrid(Fabric fab)
{
  const Scene *s    = &fab->s;
  MPI_Comm     comm = fab->comm;

  PetscFunctionBeginUser;
  {
    PetscInt m = 0, n = 0;
    PetscCall(RankGrid(s->spec.nx, s->spec.ny, fab->size, s->num.solver == SOLVER_STATIC, &m, &n));
    PetscCheck(m > 0, comm, PETSC_ERR_USER_INPUT,
               "grid too small: %" PetscInt_FMT " x %" PetscInt_FMT
               " crossings cannot be split over %d ranks (each rank needs at least 2 crossings along each direction "
               "the grid is split in); use fewer ranks",
               s->spec.nx, s->spec.ny, fab->size);
    PetscCall(UserRankGrid(s->spec.nx, s->spec.ny, fab->size, comm, &m, &n));
    PetscCall(DMDACreate2d(comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DMDA_STENCIL_BOX, s->spec.nx, s->spec.ny, m, n, 3,
                           2, NULL, NULL, &fab->grid.da));
    PetscCall(DMSetFromOptions(fab->grid.da));
    { /* PETSc's DMDA options may set the rank grid (as checked above), not the grid itself */
      PetscInt M, N, pm, pn, dof, sw;
      PetscCall(DMDAGetInfo(fab->grid.da, NULL, &M, &N, NULL, &pm, &pn, NULL, &dof, &sw, NULL, NULL, NULL, NULL));
      PetscCheck(M == s->spec.nx && N == s->spec.ny && pm == m && pn == n && dof == 3 && sw == 2, comm,
                 PETSC_ERR_USER_INPUT,
                 "the grid is the scene's, %" PetscInt_FMT " x %" PetscInt_FMT
                 " crossings (its size and thread densities) on %" PetscInt_FMT " x %" PetscInt_FMT
                 " ranks: PETSc's DMDA options (-da_grid_x, -da_grid_y, -da_refine, ...) made it %" PetscInt_FMT
                 " x %" PetscInt_FMT " on %" PetscInt_FMT " x %" PetscInt_FMT "; set the scene's -gauge_mm, -width_mm, "
                 "-ends_per_cm or -picks_per_cm instead",
                 s->spec.nx, s->spec.ny, m, n, M, N, pm, pn);
    }
    PetscCall(DMSetUp(fab->grid.da));
  }
  PetscCall(DMDASetFieldName(fab->grid.da, 0, "x"));
  PetscCall(DMDASetFieldName(fab->grid.da, 1, "y"));
  PetscCall(DMDASetFieldName(fab->grid.da, 2, "z"));
  PetscCall(DMDACreateCompatibleDMDA(fab->grid.da, 2, &fab->grid.da_seg));
  PetscFunctionReturn(0);
}

/* the state vectors and the rest positions X(i,j) = (i ax, j ay, 0) */
static PetscErrorCode CreateState(Fabric fab, const DMDALocalInfo *info_)
{
  const Scene        *s    = &fab->s;
  const DMDALocalInfo info = *info_;

  PetscFunctionBeginUser;
  PetscCall(DMCreateGlobalVector(fab->grid.da, &fab->state.X));
  PetscCall(PetscObjectSetName((PetscObject) fab->state.X, "positions"));
  PetscCall(VecDuplicate(fab->state.X, &fab->state.V));
  PetscCall(VecDuplicate(fab->state.X, &fab->state.F));
  PetscCall(VecDuplicate(fab->state.X, &fab->grid.X0));
  PetscCall(DMCreateLocalVector(fab->grid.da, &fab->state.Xl));
  PetscCall(HaloHome(fab->grid.da, fab->state.X, fab->state.Xl)); /* read-only ghosted positions: the ghosts alone move */

  {
    const PetscReal ax = 1.0 / s->spec.picks_per_m, ay = 1.0 / s->spec.ends_per_m;
    PetscScalar  ***x;
    PetscCall(DMDAVecGetArrayDOF(fab->grid.da, fab->grid.X0, &x));
    for (PetscInt j = info.ys; j < info.ys + info.ym; j++)
      for (PetscInt i = info.xs; i < info.xs + info.xm; i++) {
        x[j][i][0] = i * ax;
        x[j][i][1] = j * ay;
        x[j][i][2] = 0.0;
      }
    PetscCall(DMDAVecRestoreArrayDOF(fab->grid.da, fab->grid.X0, &x));
    PetscCall(VecCopy(fab->grid.X0, fab->state.X));
    fab->grid.centre[0] = 0.5 * (s->spec.nx - 1) * ax;
    fab->grid.centre[1] = 0.5 * (s->spec.ny - 1) * ay;
    fab->grid.centre[2] = 0.0;
    fab->grid.extent    = PetscSqrtReal(PetscSqr((s->spec.nx - 1) * ax) + PetscSqr((s->spec.ny - 1) * ay));
  }

  PetscFunctionReturn(0);
}

/* the force kernels' patch: ghosted existence, broken flags, constants of the force terms */
static PetscErrorCode SetUpPatch(Fabric fab, const DMDALocalInfo *info_)
{
  const Scene        *s    = &fab->s;
  const DMDALocalInfo info = *info_;

  PetscFunctionBeginUser;
  {
    Patch *p = &fab->grid.patch;
    p->nx    = s->spec.nx;
    p->ny    = s->spec.ny;
    p->xs = info.xs, p->ys = info.ys, p->xm = info.xm, p->ym = info.ym;
    p->gxs = info.gxs, p->gys = info.gys, p->gxm = info.gxm, p->gym = info.gym;
    p->ax       = 1.0 / s->spec.picks_per_m;
    p->ay       = 1.0 / s->spec.ends_per_m;
    p->warp     = &s->yarns.warp;
    p->weft     = &s->yarns.weft;
    p->traction = s->terms.traction;
    p->bending =
        (s->terms.bending && (s->yarns.warp.bending > 0 || s->yarns.weft.bending > 0)) ? PETSC_TRUE : PETSC_FALSE;
    p->shear     = (s->terms.shear && s->terms.shear_G > 0) ? PETSC_TRUE : PETSC_FALSE;
    p->kbx       = s->yarns.warp.bending / p->ax;
    p->kby       = s->yarns.weft.bending / p->ay;
    p->Ks        = s->terms.shear_G * p->ax * p->ay;
    p->Kj        = s->terms.jam_factor * p->Ks;
    p->s_lock    = PetscSinReal(s->terms.lock_deg * PETSC_PI / 180.0);
    p->k_contact = 0, p->ncb = 0; /* a crossing can touch every body at once */
    for (PetscInt q = 0; q < fab->bodies.n; q++) {
      const Body *b = &fab->bodies.body[q];
      if (BodyBoundAlongNormal(b) && p->ncb < CONTACT_BOUNDS_MAX) /* a sphere's centre: at each bound */
        p->cb[p->ncb++] =
            (ContactBound){(int) q, b->kind == BODY_SPHERE, b->k, {0, 0, 0}, {b->dir[0], b->dir[1], b->dir[2]}, 0};
      else p->k_contact += b->k;
    }
    PetscCall(PetscCalloc1((size_t) p->gxm * p->gym, &p->exists));
    PetscCall(PetscCalloc1((size_t) p->gxm * p->gym, &p->broken_x));
    PetscCall(PetscCalloc1((size_t) p->gxm * p->gym, &p->broken_y));
    for (PetscInt j = 0; j < p->gym; j++)
      for (PetscInt i = 0; i < p->gxm; i++)
        p->exists[j * p->gxm + i] = (unsigned char) PointExists(s, p->gxs + i, p->gys + j);
    if (s->yarns.warp.break_k > 0 || s->yarns.weft.break_k > 0) { /* scattered breaking strains */
      PetscCall(PetscMalloc2((size_t) p->gxm * p->gym, &p->break_x, (size_t) p->gxm * p->gym, &p->break_y));
      for (PetscInt j = 0; j < p->gym; j++)
        for (PetscInt i = 0; i < p->gxm; i++) {
          p->break_x[j * p->gxm + i] = SegmentBreakStrain(p->warp, s->rupture.seed, 0, p->gxs + i, p->gys + j);
          p->break_y[j * p->gxm + i] = SegmentBreakStrain(p->weft, s->rupture.seed, 1, p->gxs + i, p->gys + j);
        }
    }
    PetscCall(PatchSetUp(p));
  }

  PetscFunctionReturn(0);
}

/* The stiffnesses and masses the options give, before anything is integrated: each option is
   within its physical range (scene.c), but their products can still leave the doubles (a tabulated
   law's slope, a 1e-300 tex). A point whose mass is not a normal double has an infinite 1/m. */
static PetscErrorCode CheckStiffnessAndMass(Fabric fab)
{
  const Scene    *s      = &fab->s;
  const Patch    *p      = &fab->grid.patch;
  const YarnLaw  *law[2] = {&s->yarns.warp, &s->yarns.weft};
  const PetscReal L0[2] = {p->ax, p->ay}, density[2] = {s->in.picks_per_cm, s->in.ends_per_cm};
  PetscReal       kcontact = p->k_contact; /* and the bodies along their normals */
  PetscReal       m[2] = {0, 0}; /* minus the lightest and the heaviest positive point mass */

  PetscFunctionBeginUser;
  for (int q = 0; q < p->ncb; q++) kcontact += p->cb[q].k;
  PetscCheck(isfinite(p->kbx) && isfinite(p->kby) && isfinite(p->Ks) && isfinite(p->Kj) && isfinite(kcontact),
             fab->comm, PETSC_ERR_USER_INPUT,
             "a stiffness overflows: bending %g, %g N m, shear %g N m, jamming %g N m, contact %g N/m", (double) p->kbx,
             (double) p->kby, (double) p->Ks, (double) p->Kj, (double) kcontact);
  m[0] = -PETSC_MAX_REAL;
  for (PetscInt k = 0; k < fab->grid.nloc; k++) {
    const PetscReal mk = fab->grid.mass[k];
    if (mk > 0) m[0] = PetscMax(m[0], -mk);
    m[1] = PetscMax(m[1], mk);
  }
  PetscCall(GlobalMax(fab->comm, m, 2));
  /* no crossing has a segment (a disc too small for the grid: none inside it, or one alone) */
  PetscCheck(m[1] > 0 || s->spec.shape != SHAPE_DISC, fab->comm, PETSC_ERR_USER_INPUT,
             "-disc_diameter_mm %g at %g x %g threads/cm: the disc holds at most one crossing, no yarn segment",
             2e3 * (double) s->spec.disc_radius, (double) s->in.ends_per_cm, (double) s->in.picks_per_cm);
  PetscCheck(m[1] > 0, fab->comm, PETSC_ERR_USER_INPUT, "the specimen holds no yarn segment (-shape %s at %g x %g threads/cm)",
             ShapeNames[s->spec.shape], (double) s->in.ends_per_cm, (double) s->in.picks_per_cm);
  PetscCheck(m[1] > 0 && isfinite(m[1]) && -m[0] >= DBL_MIN && isfinite(-1.0 / m[0]), fab->comm, PETSC_ERR_USER_INPUT,
             "-warp_tex %g and -weft_tex %g at %g x %g threads/cm give crossing masses from %g to %g kg: too light to "
             "integrate (below 2.2e-308 kg, 1/m overflows)",
             (double) s->in.yarn[0].tex, (double) s->in.yarn[1].tex, (double) s->in.ends_per_cm,
             (double) s->in.picks_per_cm, (double) -m[0], (double) m[1]);
  for (int y = 0; y < 2; y++) { /* warp segments span the weft spacing, weft segments the warp spacing; after the
                                   masses, whose message says more of a tiny tex. At least YARN_K_MIN: a yarn so soft
                                   that its forces' squares underflow gave the balance test norms of 0, and a strip
                                   18 % off its force was reported balanced (-warp_modulus_cN_tex 5e-290) */
    const PetscReal k = law[y]->EA / L0[y];
    const char     *n = law[y]->name, *spacing = y ? "ends" : "picks";
    char            what[128];
    PetscCall(PetscSNPrintf(what, sizeof what, isnormal(k) ? "below %g N/m, where smaller forces underflow in the balance "
                                                             "test's sums of squares" : "not a normal positive number",
                            YARN_K_MIN));
    PetscCheck((isnormal(k) && k >= YARN_K_MIN) || law[y]->csv[0], fab->comm, PETSC_ERR_USER_INPUT,
               "the %s yarn segments' stiffness EA/L0 is %g N/m, %s: -%s_tex %g x -%s_modulus_cN_tex %g at %g %s/cm", n,
               (double) k, what, n, (double) law[y]->tex, n, (double) s->in.yarn[y].modulus_cN_tex, (double) density[y],
               spacing);
    PetscCheck(isnormal(k) && k >= YARN_K_MIN, fab->comm, PETSC_ERR_USER_INPUT,
               "the %s yarn segments' stiffness EA/L0 is %g N/m, %s: -%s_law_csv %s at %g %s/cm", n, (double) k, what, n,
               law[y]->csv, (double) density[y], spacing);
  }
  PetscFunctionReturn(0);
}

/* masses (MODEL.md 4): each existing segment gives half its yarn mass to each end; point kinds, the point load's
 * crossing and the balance test's force floor */
static PetscErrorCode SetUpMasses(Fabric fab, const DMDALocalInfo *info_)
{
  const Scene        *s    = &fab->s;
  MPI_Comm            comm = fab->comm;
  const DMDALocalInfo info = *info_;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc4(fab->grid.nloc, &fab->grid.mass, fab->grid.nloc, &fab->grid.inv_m, fab->grid.nloc,
                         &fab->grid.kind, fab->grid.nloc, &fab->grid.predict_w));
  {
    const PetscReal mx   = 0.5 * s->yarns.warp.mu * (1.0 + s->yarns.warp.crimp) * fab->grid.patch.ax;
    const PetscReal my   = 0.5 * s->yarns.weft.mu * (1.0 + s->yarns.weft.crimp) * fab->grid.patch.ay;
    PetscReal       gmag = PetscSqrtReal(PetscSqr(s->terms.gravity[0]) + PetscSqr(s->terms.gravity[1]) +
                                         PetscSqr(s->terms.gravity[2])),
              wmax       = 0;
    PetscInt count       = 0;
    fab->grid.load_index = -1;
    for (PetscInt j = info.ys; j < info.ys + info.ym; j++)
      for (PetscInt i = info.xs; i < info.xs + info.xm; i++) {
        const PetscInt k = (j - info.ys) * info.xm + (i - info.xs);
        PetscReal      m = 0;
        if (PointExists(s, i, j)) {
          m = mx * (PointExists(s, i - 1, j) + PointExists(s, i + 1, j)) +
              my * (PointExists(s, i, j - 1) + PointExists(s, i, j + 1));
          count++;
        }
        fab->grid.mass[k]  = m;
        fab->grid.kind[k]  = (unsigned char) (PointExists(s, i, j) ? KindOf(s, i, j) : POINT_CLAMPED);
        fab->grid.inv_m[k] = (fab->grid.kind[k] == POINT_FREE && m > 0) ? 1.0 / m : 0.0;
        wmax               = PetscMax(wmax, m * gmag);
        if (i == s->load.load_at[0] && j == s->load.load_at[1]) fab->grid.load_index = k;
      }
    { /* a point load needs a free crossing to act on: 1 absent, 2 held (clamped or gripped) */
      const PetscInt k   = fab->grid.load_index;
      PetscReal      bad = k < 0 ? 0 : !PointExists(s, s->load.load_at[0], s->load.load_at[1]) ? 1 : fab->grid.inv_m[k] > 0 ? 0 : 2;
      PetscCall(GlobalMax(comm, &bad, 1));
      PetscCheck(bad == 0 || (s->load.point_load[0] == 0 && s->load.point_load[1] == 0 && s->load.point_load[2] == 0), comm,
                 PETSC_ERR_USER_INPUT,
                 "-point_load_at %" PetscInt_FMT ",%" PetscInt_FMT "%s: the point load (-point_load_N %g,%g,%g) acts on a "
                 "crossing that %s; give a free crossing",
                 s->load.load_at[0], s->load.load_at[1], s->in.n_point_load_at ? "" : " (the default: the grid's centre)",
                 (double) s->load.point_load[0], (double) s->load.point_load[1], (double) s->load.point_load[2],
                 bad == 1 ? "is not in the specimen" : "is held (clamped or in a grip)");
    }
    fab->grid.points = count;
    PetscCall(GlobalSumInt(comm, &fab->grid.points, 1));
    PetscCall(GlobalMax(comm, &wmax, 1));
    /* the balance test's force scale never drops below a point's weight, nor below 1 uN unless the
       scene's own forces are smaller: its point load, or 1e-7 of the softer yarn's stiffness EA */
    {
      const PetscReal P = hypot(hypot(s->load.point_load[0], s->load.point_load[1]), s->load.point_load[2]);
      PetscReal       small = PetscMin(1e-6, 1e-7 * PetscMin(s->yarns.warp.EA, s->yarns.weft.EA));
      if (P > 0) small = PetscMin(small, P);
      fab->step.force_floor = PetscMax(wmax, small);
    }
  }
  PetscFunctionReturn(0);
}

/* the rigid bodies the scene has, at their places at rest (the grid centre is the origin of
   their options) */
static void SetUpBodies(Fabric fab)
{
  const Bodies   *sb         = &fab->s.bodies;
  const PetscReal half_thick = 0.5 * sb->thickness;
  RigidBodies    *rb         = &fab->bodies;

  rb->n = 0;
  if (sb->sphere_radius > 0) {
    Body *b = &rb->body[rb->n++];
    *b      = (Body){BODY_SPHERE,    {0}, {0}, sb->sphere_radius, 0, sb->sphere_radius + half_thick, sb->contact_k,
                     sb->friction_mu};
    for (int d = 0; d < 3; d++) b->ref[d] = fab->grid.centre[d] + sb->sphere_start[d], b->dir[d] = sb->sphere_dir[d];
  }
  if (sb->plane) {
    Body *b = &rb->body[rb->n++];
    *b      = (Body){BODY_PLANE, {0}, {0}, 0, 0, half_thick, sb->contact_k, sb->friction_mu};
    for (int d = 0; d < 3; d++) b->ref[d] = fab->grid.centre[d] + sb->plane_point[d], b->dir[d] = sb->plane_normal[d];
  }
  if (sb->pedestal_radius > 0) {
    Body *b = &rb->body[rb->n++];
    *b      = (Body){BODY_PEDESTAL,       {0},        {0},           sb->pedestal_radius,
                     sb->pedestal_height, half_thick, sb->contact_k, sb->friction_mu};
    for (int d = 0; d < 3; d++) b->ref[d] = fab->grid.centre[d] + sb->pedestal_top[d];
  }
}

/* The ball against the fabric at rest: it must not start inside a free crossing's reach (its
   penalty would fling the crossing out), and its path (start to start + travel along its direction)
   must not reach a held crossing, which the contact leaves alone (the ball would pass through the
   clamps). The deepest of each, over all ranks; refused beyond 1e-6 of the reach. */
static PetscErrorCode CheckSphere(Fabric fab, const DMDALocalInfo *info)
{
  const Bodies      *sb = &fab->s.bodies;
  const Body        *b  = &fab->bodies.body[0];
  const PetscScalar *x0;
  PetscReal          deep[2] = {-PETSC_MAX_REAL, -PETSC_MAX_REAL}; /* free at the start, held on the path */
  PetscInt           at[2]   = {-1, -1};

  PetscFunctionBeginUser;
  if (!(sb->sphere_radius > 0)) PetscFunctionReturn(0);
  PetscCall(VecGetArrayRead(fab->grid.X0, &x0));
  for (PetscInt j = info->ys; j < info->ys + info->ym; j++)
    for (PetscInt i = info->xs; i < info->xs + info->xm; i++) {
      const PetscInt k = (j - info->ys) * info->xm + i - info->xs;
      PetscReal      r[3], along = 0, d2 = 0, d2s = 0;
      if (!PointExists(&fab->s, i, j)) continue;
      for (int d = 0; d < 3; d++) r[d] = x0[3 * k + d] - b->ref[d], along += r[d] * b->dir[d];
      along = PetscMin(PetscMax(along, 0.0), sb->sphere_travel); /* the path's point nearest the crossing */
      for (int d = 0; d < 3; d++) d2 += PetscSqr(r[d] - along * b->dir[d]), d2s += r[d] * r[d];
      {
        const int       held = fab->grid.kind[k] != POINT_FREE;
        const PetscReal p    = b->reach - PetscSqrtReal(held ? d2 : d2s);
        if (p > deep[held]) deep[held] = p, at[held] = j * fab->s.spec.nx + i;
      }
    }
  PetscCall(VecRestoreArrayRead(fab->grid.X0, &x0));
  for (int h = 0; h < 2; h++) {
    PetscReal best = deep[h];
    PetscInt  code = at[h];
    PetscCall(GlobalArgMax(fab->comm, &best, &code));
    deep[h] = best, at[h] = code;
  }
  PetscCheck(!(deep[0] > 1e-6 * b->reach), fab->comm, PETSC_ERR_USER_INPUT,
             "-sphere_start_mm %g,%g,%g%s: the ball (-sphere_diameter_mm %g) starts %g mm into the fabric at crossing "
             "(%" PetscInt_FMT ", %" PetscInt_FMT "); start it clear of the fabric",
             (double) (1e3 * sb->sphere_start[0]), (double) (1e3 * sb->sphere_start[1]),
             (double) (1e3 * sb->sphere_start[2]),
             sb->sphere_start_set ? "" : " (the default: touching the fabric's plane from behind along -sphere_direction)",
             (double) (2e3 * sb->sphere_radius), (double) (1e3 * deep[0]), at[0] % fab->s.spec.nx, at[0] / fab->s.spec.nx);
  PetscCheck(!(deep[1] > 1e-6 * b->reach), fab->comm, PETSC_ERR_USER_INPUT,
             "-sphere_diameter_mm %g with -sphere_travel_mm %g: the ball's path reaches the held crossing (%" PetscInt_FMT
             ", %" PetscInt_FMT ") by %g mm, and contact leaves held crossings alone (it would pass through the clamps): "
             "a smaller ball, a shorter travel or a wider clamp",
             (double) (2e3 * sb->sphere_radius), (double) (1e3 * sb->sphere_travel), at[1] % fab->s.spec.nx,
             at[1] / fab->s.spec.nx, (double) (1e3 * deep[1]));
  PetscFunctionReturn(0);
}

/* The plane and the pedestal against the fabric at rest: no free crossing may start inside a body's reach (its
   penalty would throw it out at the first te step, through the fabric). The deepest, over all ranks; refused
   beyond 1e-6 of the reach. */
static PetscErrorCode CheckBodiesAtRest(Fabric fab, const DMDALocalInfo *info)
{
  const Bodies      *sb = &fab->s.bodies;
  const PetscScalar *x0;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(fab->grid.X0, &x0));
  for (PetscInt q = 0; q < fab->bodies.n; q++) {
    const Body *b = &fab->bodies.body[q];
    PetscReal   c[3], deep = -PETSC_MAX_REAL;
    PetscInt    at = -1;
    if (b->kind == BODY_SPHERE) continue; /* CheckSphere */
    BodyPosition(b, 0.0, c);
    for (PetscInt j = info->ys; j < info->ys + info->ym; j++)
      for (PetscInt i = info->xs; i < info->xs + info->xm; i++) {
        const PetscInt k = (j - info->ys) * info->xm + i - info->xs;
        PetscReal      g[3], K[9], p;
        if (!PointExists(&fab->s, i, j) || fab->grid.kind[k] != POINT_FREE) continue;
        p = PetscSqrtReal(2.0 * BodyEnergy(b, c, x0 + 3 * k, g, K) / b->k); /* the penalty k p^2 / 2 */
        if (p > deep) deep = p, at = j * fab->s.spec.nx + i;
      }
    PetscCall(GlobalArgMax(fab->comm, &deep, &at));
    if (b->kind == BODY_PEDESTAL) { /* the fabric's only support (a drape without a clamp, a net resting on it): a
                                       pedestal between crossings held none, and the fabric fell past it */
      const Clamps *cl   = &fab->s.clamps;
      PetscInt      over = 0;
      if (cl->clamp == CLAMP_NONE && !cl->clamp_lines && !cl->grip_lines && !sb->plane) {
        for (PetscInt j = info->ys; j < info->ys + info->ym; j++)
          for (PetscInt i = info->xs; i < info->xs + info->xm; i++) {
            const PetscScalar *xk = x0 + 3 * ((j - info->ys) * info->xm + i - info->xs);
            over += PointExists(&fab->s, i, j) && PetscSqr(xk[0] - c[0]) + PetscSqr(xk[1] - c[1]) <= PetscSqr(b->radius);
          }
        PetscCall(GlobalSumInt(fab->comm, &over, 1));
        if (!over) PetscCall(VecRestoreArrayRead(fab->grid.X0, &x0));
        PetscCheck(over > 0, fab->comm, PETSC_ERR_USER_INPUT,
                   "-pedestal_diameter_mm %g: no crossing lies over the pedestal (yarn spacing %g x %g mm), and nothing "
                   "else holds the fabric (-clamp none): it would fall past it; widen the pedestal or use a denser grid",
                   (double) (2e3 * sb->pedestal_radius), 1e3 / (double) fab->s.spec.ends_per_m,
                   1e3 / (double) fab->s.spec.picks_per_m);
      }
    }
    if (deep > 1e-6 * b->reach) PetscCall(VecRestoreArrayRead(fab->grid.X0, &x0)); /* refused below: X0 unlocked */
    if (b->kind == BODY_PLANE)
      PetscCheck(!(deep > 1e-6 * b->reach), fab->comm, PETSC_ERR_USER_INPUT,
                 "-plane_point_mm %g,%g,%g with -plane_normal %g,%g,%g: the plane starts %g mm into the fabric at "
                 "crossing (%" PetscInt_FMT ", %" PetscInt_FMT "), within half the thickness (-thickness_mm %g) of it or "
                 "behind it; put it clear of the fabric, which stays on the side the normal points to",
                 (double) (1e3 * sb->plane_point[0]), (double) (1e3 * sb->plane_point[1]),
                 (double) (1e3 * sb->plane_point[2]), (double) sb->plane_normal[0], (double) sb->plane_normal[1],
                 (double) sb->plane_normal[2], (double) (1e3 * deep), at % fab->s.spec.nx, at / fab->s.spec.nx,
                 (double) (1e3 * sb->thickness));
    else
      PetscCheck(!(deep > 1e-6 * b->reach), fab->comm, PETSC_ERR_USER_INPUT,
                 "-pedestal_top_mm %g,%g,%g (-pedestal_diameter_mm %g): the pedestal starts %g mm into the fabric at "
                 "crossing (%" PetscInt_FMT ", %" PetscInt_FMT "), within half the thickness (-thickness_mm %g) of it; "
                 "put its top at or below z = -thickness/2 (the default)",
                 (double) (1e3 * sb->pedestal_top[0]), (double) (1e3 * sb->pedestal_top[1]),
                 (double) (1e3 * sb->pedestal_top[2]), (double) (2e3 * sb->pedestal_radius), (double) (1e3 * deep),
                 at % fab->s.spec.nx, at / fab->s.spec.nx, (double) (1e3 * sb->thickness));
  }
  PetscCall(VecRestoreArrayRead(fab->grid.X0, &x0));
  PetscFunctionReturn(0);
}

/* friction anchors: each crossing's rest position in the frame of each body */
static PetscErrorCode SetUpAnchors(Fabric fab)
{
  PetscFunctionBeginUser;
  if (!(fab->s.bodies.friction_mu > 0)) PetscFunctionReturn(0);
  for (PetscInt q = 0; q < fab->bodies.n; q++) {
    const Body  *b = &fab->bodies.body[q];
    Vec         *A = &fab->state.anchor[b->kind];
    PetscScalar *a;
    PetscCall(VecDuplicate(fab->state.X, A));
    PetscCall(VecCopy(fab->grid.X0, *A));
    PetscCall(VecGetArray(*A, &a));
    for (PetscInt k = 0; k < fab->grid.nloc; k++)
      for (int d = 0; d < 3; d++) a[3 * k + d] -= b->ref[d];
    PetscCall(VecRestoreArray(*A, &a));
  }
  PetscFunctionReturn(0);
}

/* The pull points from the clamped crossings to the grip (-grip_line_mm may put the grip on either side): a grip
   whose crossings lie, on average, before the clamped ones along the pull turns it round, so that the grip moves
   away from the clamps, and the elongation and the reaction are positive in tension */
static PetscErrorCode PullAwayFromClamps(Fabric fab)
{
  const PetscScalar *x0;
  const PetscReal   *u = fab->grid.pull_dir;
  PetscReal          sum[4] = {0, 0, 0, 0}; /* along the pull: the grip's, their number, the clamps', theirs */

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(fab->grid.X0, &x0));
  for (PetscInt k = 0; k < fab->grid.nloc; k++) {
    const PetscReal a = x0[3 * k] * u[0] + x0[3 * k + 1] * u[1] + x0[3 * k + 2] * u[2];
    if (fab->grid.kind[k] == POINT_GRIP) sum[0] += a, sum[1] += 1;
    else if (fab->grid.kind[k] == POINT_CLAMPED) sum[2] += a, sum[3] += 1;
  }
  PetscCall(VecRestoreArrayRead(fab->grid.X0, &x0));
  PetscCall(GlobalSum(fab->comm, sum, 4));
  if (sum[1] > 0 && sum[3] > 0 && sum[0] / sum[1] < sum[2] / sum[3])
    for (int d = 0; d < 3; d++) fab->grid.pull_dir[d] = -fab->grid.pull_dir[d];
  PetscFunctionReturn(0);
}

/* the grid, state and set-up of the scene fab->s */
static PetscErrorCode FabricSetUp(Fabric fab)
{
  Scene        *s = &fab->s;
  DMDALocalInfo info;
  PetscBool     help;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  PetscCall(CheckMemory(fab, help)); /* -help: the DMDA's share alone */
  PetscCall(CreateGrid(fab));
  /* -help: the grid has listed its -da_* options; the rest would cost time and memory alone (and its checks of
     the scene, of the clamps, bodies and masses, are the run's) */
  if (help) PetscFunctionReturn(0);
  PetscCall(DMDAGetLocalInfo(fab->grid.da, &info));
  fab->grid.nloc = (PetscInt) info.xm * info.ym;
  PetscCall(CreateState(fab, &info));
  SetUpBodies(fab);
  PetscCall(SetUpPatch(fab, &info));
  PetscCall(CheckLines(fab, &info));
  PetscCall(CheckBias(fab, &info));
  PetscCall(SetUpMasses(fab, &info));
  PetscCall(CheckStiffnessAndMass(fab));
  PetscCall(CheckSphere(fab, &info));
  PetscCall(CheckBodiesAtRest(fab, &info));
  fab->grid.pull_dir[0] = s->spec.pull == PULL_WARP ? 1.0 : 0.0;
  fab->grid.pull_dir[1] = s->spec.pull == PULL_WARP ? 0.0 : 1.0;
  fab->grid.pull_dir[2] = 0.0;
  for (int d = 0; d < 3; d++) fab->load.gravity_now[d] = s->terms.gravity[d];
  if (s->spec.shape == SHAPE_BIAS)
    fab->grid.pull_dir[0] = fab->grid.pull_dir[1] = 1.0 / PetscSqrtReal(2.0); /* along the specimen */
  PetscCall(PullAwayFromClamps(fab));
  if (s->num.integrator == INTEGRATOR_PAPER) {
    PetscCall(VecDuplicate(fab->state.X, &fab->state.Xold));
    PetscCall(VecDuplicate(fab->state.X, &fab->state.Vold));
    PetscCall(VecCopy(fab->state.X, fab->state.Xold));
  }
  if (s->num.kinetic_damping) PetscCall(PetscCalloc1(fab->grid.nloc, &fab->step.ke_terms));
  PetscCall(PetscCalloc1(2 * fab->grid.patch.xm, &fab->step.tally_rows));
  PetscCall(SetUpAnchors(fab));
  /* the linear prediction's weights (two graph-distance passes over the grid): a ball's are found per load step */
  if (s->num.predict != PREDICT_NONE && !(s->bodies.sphere_radius > 0)) PetscCall(PredictSetUp(fab));
  else PetscCall(PetscArrayzero(fab->grid.predict_w, fab->grid.nloc));
  PetscCall(FrontSetUp(fab));
  fab->stats.converged = PETSC_TRUE;
  fab->stats.rupture.peak_balanced = PETSC_TRUE; /* no unbalanced state has given the largest force */
  fab->stats.rupture.peak_force    = -PETSC_MAX_REAL; /* none yet: the first row's force is the first maximum */
  PetscCall(PetscCalloc1(s->load.load_steps, &fab->stats.curve));
  PetscCall(IOSetUp(&s->out, &fab->io)); /* the output state of frames and checkpoints */
  PetscFunctionReturn(0);
}

PetscErrorCode FabricCreate(MPI_Comm comm, Fabric *out)
{
  Fabric fab;

  PetscFunctionBeginUser;
  PetscCall(EventsRegister());
  PetscCall(PetscNew(&fab));
  fab->comm = comm;
  PetscCall(CommRank(comm, &fab->rank));
  PetscCall(CommSize(comm, &fab->size));
  PetscCall(SceneLoad(comm, &fab->s));
  PetscCall(FabricSetUp(fab));
  *out = fab;
  PetscFunctionReturn(0);
}

/* The coarse fabric takes the fine one's clamps, bodies and load at half the density: where they do not fit it (a
   clamping ring between its crossings, a point load on its outline), its set-up refuses it as user input; then
   the fine fabric is solved without it, with a notice (the indices of the refusal are the coarse grid's) */
PetscErrorCode FabricCreateCoarse(Fabric fine, Fabric *out)
{
  Fabric         fab;
  PetscBool      fits = PETSC_FALSE;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  *out = NULL;
  PetscCall(PetscNew(&fab));
  fab->comm = fine->comm, fab->rank = fine->rank, fab->size = fine->size;
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = SceneCoarsen(fine->comm, &fine->s, &fab->s, &fits);
  if (!ierr && fits) ierr = FabricSetUp(fab);
  PetscCall(PetscPopErrorHandler());
  if (ierr) {
    const char *text;
    char       *specific = NULL;
    PetscCall(PetscErrorMessage(ierr, &text, &specific));
    PetscCheck(ierr == PETSC_ERR_USER_INPUT, fine->comm, ierr, "the coarser fabric of -static_sequence: %s",
               specific && specific[0] ? specific : text); /* the handler above printed nothing */
    PetscCall(PetscPrintf(fine->comm, /* with -quiet too: the option given does not act */
                            "fabric: -static_sequence: no coarser fabric below %" PetscInt_FMT " x %" PetscInt_FMT
                            ": at half the density this scene does not fit (%s); solved without it\n",
                            fine->s.spec.nx, fine->s.spec.ny, specific && specific[0] ? specific : text));
    fits = PETSC_FALSE;
  }
  if (!fits) {
    PetscCall(FabricDestroy(&fab));
    PetscFunctionReturn(0);
  }
  *out = fab;
  PetscFunctionReturn(0);
}

PetscErrorCode FabricDestroy(Fabric *pfab)
{
  Fabric fab = *pfab;

  PetscFunctionBeginUser;
  if (!fab) PetscFunctionReturn(0);
  if (fab->stats.curve_fp) fclose(fab->stats.curve_fp);
  if (fab->stats.lock_fp) fclose(fab->stats.lock_fp); /* the lock with it */
  PetscCall(IODestroy(&fab->io));
  PetscCall(PetscFree(fab->stats.curve));
  PetscCall(PetscFree(fab->step.ke_terms));
  PetscCall(PetscFree(fab->step.tally_rows));
  PetscCall(PetscFree(fab->front.front_box));
  PetscCall(PetscFree4(fab->grid.mass, fab->grid.inv_m, fab->grid.kind, fab->grid.predict_w));
  PetscCall(PetscFree(fab->grid.patch.exists));
  PetscCall(PetscFree(fab->grid.patch.broken_x));
  PetscCall(PetscFree(fab->grid.patch.broken_y));
  PetscCall(PetscFree2(fab->grid.patch.break_x, fab->grid.patch.break_y));
  PetscCall(PatchDestroy(&fab->grid.patch));
  PetscCall(VecDestroy(&fab->state.X));
  PetscCall(VecDestroy(&fab->state.V));
  PetscCall(VecDestroy(&fab->state.F));
  PetscCall(VecDestroy(&fab->grid.X0));
  PetscCall(VecDestroy(&fab->state.Xl));
  for (int q = 0; q < 3; q++) PetscCall(VecDestroy(&fab->state.hist.Xh[q]));
  PetscCall(VecDestroy(&fab->state.Xold));
  PetscCall(VecDestroy(&fab->state.Vold));
  PetscCall(VecDestroy(&fab->state.Xconv));
  PetscCall(VecDestroy(&fab->state.Xconv_prev));
  PetscCall(VecDestroy(&fab->state.watch_x));
  PetscCall(VecDestroy(&fab->state.Xbelow));
  PetscCall(VecDestroy(&fab->state.Xabove));
  PetscCall(VecDestroy(&fab->state.watch_v));
  for (int b = 0; b < 3; b++) PetscCall(VecDestroy(&fab->state.anchor[b]));
  PetscCall(DMDestroy(&fab->grid.da_seg));
  PetscCall(DMDestroy(&fab->grid.da));
  PetscCall(SceneDestroy(&fab->s));
  PetscCall(PetscFree(fab));
  *pfab = NULL;
  PetscFunctionReturn(0);
}
