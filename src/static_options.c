/* static_options.c - the quasi-static solver's own options (StaticOptionsRead) and, before a run writes anything,
 * the checks of PETSc's solver options that this path cannot run or that PETSc would read wrongly
 * (StaticOptionsCheck): each refusal says which option, which value and why. */
#include "static_options.h"
#include "scene.h"

#include <petscsnes.h>
#include <petsctao.h>

#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#define SHIFT_START  1e-2  /* k_s / k_ref at the first Newton step of the run (-snes_shift_start) */
#define SHIFT_CARRY  10.0  /* a later load step starts from this times the last one's final shift (-snes_shift_carry) */
#define EXACT_BELOW  0.1   /* the exact tangent below this balance ratio (-static_exact_tangent) */
#define GMRES_RESTART_MAX 5000 /* -ksp_gmres_restart at most (StaticOptionsCheck) */
#define HISTORY_MAX       1000 /* -snes_qn_m, -snes_ngmres_m ... at most: each keeps that many vectors or more */
#define SNES_TYPES_RUN "newtonls,newtontr,ksponly,qn,ncg,ngmres,anderson,nrichardson,ngs,ms"

/* the solver's own options: their defaults, then the options database's values */
PetscErrorCode StaticOptionsRead(MPI_Comm comm, StaticOptions *o)
{
  PetscFunctionBeginUser;
  o->shift_start   = SHIFT_START;
  o->shift_carry   = SHIFT_CARRY;
  o->order         = 2;
  o->line_smoother = PETSC_TRUE;
  o->convex        = PETSC_FALSE;
  o->line_lump     = 1.0;
  o->tao           = PETSC_FALSE;
  o->tangent       = TANGENT_STENCIL;
  o->tangent_set   = PETSC_FALSE;
  o->sequence      = 0;
  o->exact_below   = EXACT_BELOW;
  { /* a value left out (-static_sequence $N with N unset): PETSc's readers keep the default without a word */
    static const char *const valued[] = {"-snes_shift_start", "-snes_shift_carry", "-snes_extrapolate", "-mg_line_lump",
                                         "-static_minimizer", "-static_tangent",   "-static_sequence",
                                         "-static_exact_tangent"};
    for (size_t k = 0; k < sizeof valued / sizeof valued[0]; k++) {
      char      value[8] = "";
      PetscBool set;
      PetscCall(PetscOptionsGetString(NULL, NULL, valued[k], value, sizeof value, &set));
      PetscCheck(!set || value[0], comm, PETSC_ERR_USER_INPUT, "%s: empty value (give a value or leave the option out)",
                 valued[k]);
    }
  }
  PetscOptionsBegin(comm, NULL, "Quasi-static solver (-solver static, docs/static.md)", NULL);
  PetscCall(PetscOptionsReal("-snes_shift_start", "pretension shift k_s / k_ref at the run's first Newton step", NULL,
                             o->shift_start, &o->shift_start, NULL));
  PetscCall(PetscOptionsReal("-snes_shift_carry",
                             "a load step's first shift: this times the last load step's final one (at most -snes_shift_start)",
                             NULL, o->shift_carry, &o->shift_carry, NULL));
  PetscCall(PetscOptionsInt("-snes_extrapolate",
                            "first guess: polynomial of this order through the last balanced states (0: the last one)", NULL,
                            o->order, &o->order, NULL));
  PetscCall(PetscOptionsBool("-mg_line_smoother", "geometric multigrid smoothed by alternating block lines (else PETSc's)",
                             NULL, o->line_smoother, &o->line_smoother, NULL));
  PetscCall(PetscOptionsBool("-snes_convex_tangent",
                             "tangent of bending, shear and contact: their positive parts (else their exact Hessians)", NULL,
                             o->convex, &o->convex, NULL));
  PetscCall(PetscOptionsReal("-mg_line_lump",
                             "each fine-grid line's diagonal carries this times its couplings outside the star, in magnitude (0: none)",
                             NULL, o->line_lump, &o->line_lump, NULL));
  {
    const char *const minimizers[] = {"snes", "tao"};
    PetscInt          which        = o->tao ? 1 : 0;
    PetscCall(PetscOptionsEList("-static_minimizer",
                                "Newton on Pi by SNES (shifted tangent, line search on Pi) or by TAO (-tao_type nls, ntr ...)",
                                NULL, minimizers, 2, minimizers[which], &which, NULL));
    o->tao = which == 1 ? PETSC_TRUE : PETSC_FALSE;
  }
  {
    const char *const storages[] = {"stencil", "aij"};
    PetscCall(PetscOptionsEList("-static_tangent",
                                "the tangent's storage: by stencil (3x3 blocks, no indices; Galerkin levels of our "
                                "own) or PETSc's AIJ (any -pc_type)",
                                NULL, storages, 2, storages[o->tangent], &o->tangent, &o->tangent_set));
  }
  PetscCall(PetscOptionsInt("-static_sequence",
                            "solve each load step first on this many coarser fabrics (half the thread density each, "
                            "yarns of twice the tex), the coarsest first: each one's change is the next one's first guess",
                            NULL, o->sequence, &o->sequence, NULL));
  PetscCall(PetscOptionsReal("-static_exact_tangent",
                             "the exact tangent (compressed yarns' negative geometric part kept) once the largest free "
                             "force is below this times the balance test's scale (0: never, the tension field throughout)",
                             NULL, o->exact_below, &o->exact_below, NULL));
  PetscOptionsEnd();
  PetscCheck(o->exact_below >= 0 && isfinite(o->exact_below), comm, PETSC_ERR_USER_INPUT,
             "-static_exact_tangent %.6g: must be a finite number, 0 or more", (double) o->exact_below);
  PetscCheck(o->sequence >= 0 && o->sequence <= 8, comm, PETSC_ERR_USER_INPUT,
             "-static_sequence %" PetscInt_FMT ": 0 (none) to 8 coarser fabrics", o->sequence);
  PetscCheck(o->order >= 0 && o->order <= 2, comm, PETSC_ERR_USER_INPUT, "-snes_extrapolate %" PetscInt_FMT ": 0, 1 or 2",
             o->order);
  { /* below the smallest normal double every product with it loses its digits (the scene's reals are refused so too) */
    const char *const names[] = {"-snes_shift_start", "-snes_shift_carry", "-mg_line_lump"};
    const PetscReal   vals[]  = {o->shift_start, o->shift_carry, o->line_lump};
    for (int k = 0; k < 3; k++) {
      char text[64] = "";
      if (vals[k] == 0 || !(PetscAbsReal(vals[k]) < DBL_MIN)) continue;
      PetscCall(PetscOptionsGetString(NULL, NULL, names[k], text, sizeof text, NULL));
      SETERRQ(comm, PETSC_ERR_USER_INPUT, "%s %s: too small for a double (non-zero values must exceed 2.2e-308 in magnitude)",
              names[k], text);
    }
  }
  PetscCheck(o->line_lump >= 0 && isfinite(o->line_lump), comm, PETSC_ERR_USER_INPUT,
             "-mg_line_lump %.6g: must be a finite number, 0 or more", (double) o->line_lump);
  PetscCheck(o->shift_start >= 0 && isfinite(o->shift_start), comm, PETSC_ERR_USER_INPUT,
             "-snes_shift_start %.6g: must be a finite number, 0 or more", (double) o->shift_start);
  PetscCheck(o->shift_carry >= 0 && isfinite(o->shift_carry), comm, PETSC_ERR_USER_INPUT,
             "-snes_shift_carry %.6g: must be a finite number, 0 or more", (double) o->shift_carry);
  /* 1e300 ran every load step to nothing (Newton's steps 1e-100 of the fabric's), said only as unbalanced */
  PetscCheck(o->shift_start <= 1e6, comm, PETSC_ERR_USER_INPUT,
             "-snes_shift_start %.6g is beyond its range (at most 1e6: the tangent shifted by this times a segment's "
             "stiffness; Newton's steps vanish)",
             (double) o->shift_start);
  PetscCheck(o->shift_carry <= 1e6, comm, PETSC_ERR_USER_INPUT,
             "-snes_shift_carry %.6g is beyond its range (at most 1e6: a load step's first shift, this times the last "
             "one's)",
             (double) o->shift_carry);
  PetscFunctionReturn(0);
}

/* the tangent by stencil serves the multigrid with the line smoother (its products, its levels'
   Galerkin operators and line blocks): not another -pc_type (SNES's, or TAO's Newton's under its prefix), nor
   PETSc's smoothers (SOR) */
PetscBool StaticOptionsStencilFits(const StaticOptions *o)
{
  char      name[64] = "-pc_type", pc[64] = "", type[64] = TAONLS;
  PetscBool set = PETSC_FALSE, mg = PETSC_TRUE;

  if (o->tao) { /* TAO's Newton's KSP: under its type's prefix (bnls: PETSc's bnk) */
    if (PetscOptionsGetString(NULL, NULL, "-tao_type", type, sizeof type, NULL)) return PETSC_FALSE;
    snprintf(name, sizeof name, "-tao_%s_pc_type", strcmp(type, TAOBNLS) ? type : "bnk");
  }
  if (PetscOptionsGetString(NULL, NULL, name, pc, sizeof pc, &set)) return PETSC_FALSE;
  if (set && (PetscStrcmp(pc, PCMG, &mg) || !mg)) return PETSC_FALSE;
  return o->line_smoother ? PETSC_TRUE : PETSC_FALSE;
}

/* a whole number from lo to hi */
static PetscBool WholeIn(const char *value, long lo, long hi)
{
  char      *end;
  const long v = strtol(value, &end, 10);
  return value[0] && !*end && v >= lo && v <= hi ? PETSC_TRUE : PETSC_FALSE;
}

static PetscBool GmresRestartOk(const char *value) { return WholeIn(value, 1, GMRES_RESTART_MAX); }

/* an iteration limit: a whole number, 0 or more. PETSc 3.18 reads its words default and DECIDE as -2 and -1, which
   it took for limits (-snes_max_it default stopped the first solve on "Internal error", -ksp_max_it default ran as
   0: no load step balanced) */
static PetscBool CountOk(const char *value)
{
  char      *end;
  const long v = strtol(value, &end, 10);
  if (isalpha((unsigned char) value[0])) return PETSC_FALSE; /* a word (1e3 is PETSc's to refuse: digits only) */
  return end != value && !*end && v < 0 ? PETSC_FALSE : PETSC_TRUE;
}

/* value is a real number and nothing else (into v); a word (PETSc's default, DECIDE: -2, -1) is none */
static PetscBool WholeReal(const char *value, double *v)
{
  char *end;
  *v = strtod(value, &end);
  return end != value && !*end ? PETSC_TRUE : PETSC_FALSE;
}

/* a linear solve's relative tolerance: a number from 0 to below 1; -ksp_rtol 2 let the first residual pass, every
   Newton step was zero and no load step balanced, and -1 ran */
static PetscBool RtolOk(const char *value)
{
  double v;
  return WholeReal(value, &v) && v >= 0 && v < 1 ? PETSC_TRUE : PETSC_FALSE;
}

/* the line search's options (EnergyLineSearch, and PETSc's own line searches): its first step, a fraction of
   Newton's step above 0 and at most 2; the smallest it tries, from 0 to below 1 (damping nan, -1 or inf and
   minlambda nan, 2 or inf ran every load step unbalanced with zero Newton steps, and damping 0 took 600 steps of
   length 0; default, read as -2, zero Newton steps too); its tries are an iteration limit (-1 ran as 0) */
static PetscBool LineDampingOk(const char *value)
{
  double v;
  return WholeReal(value, &v) && v > 0 && v <= 2 ? PETSC_TRUE : PETSC_FALSE;
}

/* a lag (-snes_lag_jacobian, -snes_lag_preconditioner): a whole number, PETSc judges which (default, read as -2,
   froze the tangent: 200 Newton steps, unbalanced) */
static PetscBool LagOk(const char *value) { return WholeIn(value, LONG_MIN, LONG_MAX); }
static PetscBool LineMinOk(const char *value) { return RtolOk(value); } /* the same range */

/* the multigrid's cycles per application: a whole number, 1 or more (0, -1 and PETSc's word "default", read as -2,
   made a zero preconditioner; no load step balanced) */
static PetscBool CyclesOk(const char *value) { return WholeIn(value, 1, PETSC_MAX_INT); }

static PetscBool GamgTypeOk(const char *value)
{
  return !strcmp(value, PCGAMGAGG) ? PETSC_TRUE : PETSC_FALSE;
}

/* preconditioners that need what the quasi-static path does not give them: telescope asks the grid's DM for the
   tangent in a matrix of its own (FormJacobian refused it, "assembles its own matrix", naming no option), patch
   converts the grid's DMDA to a DMPlex (PETSc's "No conversion possible between DM types da and plex") */
static PetscBool PcTypeOk(const char *value)
{
  return strcmp(value, "telescope") && strcmp(value, "patch") ? PETSC_TRUE : PETSC_FALSE;
}

/* a type PETSc has registered (PCInitializePackage and KSPInitializePackage have run): a typo under a prefix
   (-mg_levels_pc_type) is read as the multigrid sets up, mid-run, after the output is made */
static PetscBool InList(PetscFunctionList list, const char *value)
{
  void (*f)(void) = NULL;
  return !PetscFunctionListFind(list, value, &f) && f ? PETSC_TRUE : PETSC_FALSE;
}
static PetscBool PcKnown(const char *value) { return InList(PCList, value); }
/* -snes_converged_reason's format ascii_info_detail: PETSc then measures the error against the exact solution of
   a DMPlex's discretisation (DMComputeL2Diff), which a DMDA has not: a null call, a segmentation fault */
static PetscBool NotDetail(const char *value)
{
  const char *c = strchr(value, ':');
  c = c ? strchr(c + 1, ':') : NULL;
  return c && !strncasecmp(c + 1, "ascii_info_detail", 17) && (!c[18] || c[18] == ':') ? PETSC_FALSE : PETSC_TRUE;
}
static PetscBool KspKnown(const char *value) { return InList(KSPList, value); }
/* a matrix type for the multigrid's coarse operators (-mat_type): one PETSc knows, and one the coarsest level's
   LU factorisation takes (not sbaij, is: "Could not locate a solver type", mid-run) */
static PetscBool MatOk(const char *value)
{
  char seq[64];
  snprintf(seq, sizeof seq, "seq%s", value); /* aij, baij, dense: root names of seqaij, ... */
  return (InList(MatList, value) || InList(MatList, seq)) && !strstr(value, "sbaij") && strcmp(value, "is") ? PETSC_TRUE
                                                                                                      : PETSC_FALSE;
}

/* The first option given whose name is suffix under any prefix (-ksp_gmres_restart,
   -mg_levels_ksp_gmres_restart, -tao_nls_ksp_gmres_restart ...) and whose value ("" if none) ok()
   refuses: "-name value" into bad, else "". Read without marking any option used (an option no
   solver reads is still reported unused). */
static PetscErrorCode FindBadOption(const char *suffix, PetscBool (*ok)(const char *), char *bad, size_t len)
{
  OptionsGiven g;

  PetscFunctionBeginUser;
  bad[0] = 0;
  PetscCheck(!OptionsGivenGet(&g), PETSC_COMM_SELF, PETSC_ERR_MEM, "cannot list the options given");
  for (PetscInt q = 0; q < g.n && !bad[0]; q++)
    if (OptionIs(g.name[q], suffix) && !ok(g.value[q]))
      snprintf(bad, len, "%s%s%s", g.name[q], g.value[q][0] ? " " : "", g.value[q]);
  OptionsGivenFree(&g);
  PetscFunctionReturn(0);
}

static PetscBool NeverOk(const char *value)
{
  (void) value;
  return PETSC_FALSE;
}

/* With -static_minimizer tao, no factors by MUMPS under TAO's prefix: given (-tao_nls_pc_factor_mat_solver_type mumps), or
   PETSc's choice for LU and Cholesky on more than one rank (-tao_nls_pc_type lu). TAO's Newton factors the tangent
   unshifted first; on a slack fabric it is singular, MUMPS's factorisation fails, and MUMPS then factors no more:
   TAO's shifted retries failed too, and on 2 ranks the square net ran 2 400 Newton steps with no load step balanced
   (1 rank: PETSc's own LU, balanced in 45); given on 1 rank, the run stopped in MUMPS's solve (INFOG(1)=-3). */
static PetscErrorCode CheckTaoFactors(MPI_Comm comm)
{
  OptionsGiven g;
  PetscMPIInt  size;
  char         bad[PETSC_MAX_PATH_LEN] = "";

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCheck(!OptionsGivenGet(&g), PETSC_COMM_SELF, PETSC_ERR_MEM, "cannot list the options given");
  for (PetscInt q = 0; q < g.n && !bad[0]; q++) {
    const char *name = g.name[q], *value = g.value[q];
    if (strncmp(name, "-tao_", 5)) continue;
    if (OptionIs(name, "pc_factor_mat_solver_type") && !strcasecmp(value, MATSOLVERMUMPS))
      snprintf(bad, sizeof bad, "%s %s", name, value);
    else if (size > 1 && OptionIs(name, "pc_type") && (!strcasecmp(value, PCLU) || !strcasecmp(value, PCCHOLESKY)) &&
             strchr(name + 5, '_') == name + strlen(name) - strlen("_pc_type")) { /* TAO's own (-tao_nls_pc_type), not
                                                                                      a block's or redundant's, which
                                                                                      factor on one rank */
      const size_t head = strlen(name) - strlen("pc_type"); /* the option's prefix, with its '-' */
      PetscBool    chosen = PETSC_FALSE;
      for (PetscInt r = 0; r < g.n; r++)
        chosen |= !strncmp(g.name[r], name, head) && !strcmp(g.name[r] + head, "pc_factor_mat_solver_type");
      if (!chosen) snprintf(bad, sizeof bad, "%s %s (on %d ranks PETSc factors it by MUMPS)", name, value, (int) size);
    }
  }
  OptionsGivenFree(&g);
  PetscCheck(!bad[0], comm, PETSC_ERR_USER_INPUT,
             "%s with -static_minimizer tao: TAO's Newton factors a slack fabric's tangent unshifted first, MUMPS's "
             "factorisation of it fails, and MUMPS then factors no more, so no load step balances; give LU by another "
             "package (-tao_nls_pc_type lu -tao_nls_pc_factor_mat_solver_type superlu_dist, under TAO's prefix), or "
             "leave TAO's preconditioner to the default",
             bad);
  PetscFunctionReturn(0);
}

/* With -static_minimizer tao, the options of the SNES path, which its solves never read (TAO's Newton reads
   its own linear solver's under its prefix): the first given, "" if none, into bad */
static PetscErrorCode FindSnesPathOption(char *bad, size_t len)
{
  static const char *const path[]   = {"-snes_", "-ksp_", "-pc_", "-mg_levels_", "-mg_coarse_"};
  static const char *const shared[] = {"-snes_extrapolate", "-snes_convex_tangent"}; /* the first guess, the tangent */
  OptionsGiven             g;

  PetscFunctionBeginUser;
  bad[0] = 0;
  PetscCheck(!OptionsGivenGet(&g), PETSC_COMM_SELF, PETSC_ERR_MEM, "cannot list the options given");
  for (PetscInt q = 0; q < g.n && !bad[0]; q++) {
    PetscBool on = PETSC_FALSE;
    for (size_t k = 0; k < sizeof path / sizeof path[0]; k++) on = on || !strncmp(g.name[q], path[k], strlen(path[k]));
    for (size_t k = 0; k < sizeof shared / sizeof shared[0]; k++) on = on && strcmp(g.name[q], shared[k]);
    if (on) snprintf(bad, len, "%s%s%s", g.name[q], g.value[q][0] ? " " : "", g.value[q]);
  }
  OptionsGivenFree(&g);
  PetscFunctionReturn(0);
}

/* A whole number beyond PETSc's integers (32 bits): PETSc reads it wrapped round (-snes_max_it 4294967296 was 0,
   -static_sequence 4294967297 was 1), so any option given so is refused, with -solver static (the solvers' options
   are read then only), but for a tolerance (-ksp_divtol 10000000000 is a real). The scene's own options are checked
   before, each as its type. */
static PetscErrorCode CheckWideIntegers(MPI_Comm comm)
{
  OptionsGiven g;
  char         bad[PETSC_MAX_PATH_LEN] = "";

  PetscFunctionBeginUser;
  PetscCheck(!OptionsGivenGet(&g), PETSC_COMM_SELF, PETSC_ERR_MEM, "cannot list the options given");
  for (PetscInt q = 0; q < g.n && !bad[0]; q++) {
    const char *v = g.value[q] + (g.value[q][0] == '-' || g.value[q][0] == '+');
    char       *end;
    long long   l;
    const size_t n = strlen(g.name[q]);
    if (!isdigit((unsigned char) v[0]) || v[strspn(v, "0123456789")]) continue; /* not a whole number */
    if (n > 3 && !strcasecmp(g.name[q] + n - 3, "tol")) continue;              /* a tolerance: a real (-ksp_divtol) */
    errno = 0;
    l     = strtoll(g.value[q], &end, 10);
    if (errno == ERANGE || l > PETSC_MAX_INT || l < PETSC_MIN_INT) snprintf(bad, sizeof bad, "%s %s", g.name[q], g.value[q]);
  }
  OptionsGivenFree(&g);
  PetscCheck(!bad[0], comm, PETSC_ERR_USER_INPUT,
             "%s: beyond PETSc's integers (%d to %d), which would read it wrapped round (a real number this large: write "
             "it with an exponent, 1e10)",
             bad, (int) PETSC_MIN_INT, (int) PETSC_MAX_INT);
  PetscFunctionReturn(0);
}

/* a method's history (PETSc's defaults 2 to 30) */
static PetscBool HistoryOk(const char *value) { return WholeIn(value, 1, HISTORY_MAX); }

/* a load step converges on the balance test alone: Converged and TaoBalanced take over every other reason */
static PetscErrorCode CheckBalanceTestOnly(MPI_Comm comm)
{
  const char *const tols[] = {"snes_rtol", "snes_atol", "snes_stol", "tao_gatol", "tao_grtol", "tao_gttol", "tao_fmin"};
  char              bad[PETSC_MAX_PATH_LEN] = "";

  PetscFunctionBeginUser;
  for (size_t k = 0; k < sizeof tols / sizeof tols[0] && !bad[0]; k++)
    PetscCall(FindBadOption(tols[k], NeverOk, bad, sizeof bad));
  PetscCheck(!bad[0], comm, PETSC_ERR_USER_INPUT,
             "%s: the quasi-static solver converges a load step on the balance test alone, as the explicit path does; "
             "set -balance_tol",
             bad);
  PetscFunctionReturn(0);
}

/* with -static_minimizer tao: no option of the SNES path, which TAO's Newton does not read */
static PetscErrorCode CheckTaoReadsNoSnes(MPI_Comm comm)
{
  char bad[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(FindSnesPathOption(bad, sizeof bad));
  PetscCheck(!bad[0], comm, PETSC_ERR_USER_INPUT,
             "%s with -static_minimizer tao: an option of the SNES path, which TAO's Newton does not read; give its "
             "linear solver's options under its prefix (-tao_nls_ksp_type, -tao_nls_pc_type ... for -tao_type nls)",
             bad);
  PetscFunctionReturn(0);
}

/* PETSc's finite-difference operator with the assembled tangent as preconditioner: the
   multigrid forms its Galerkin products from the operator, and the energy line search never
   sets the difference's base, so it fails mid-run; -snes_mf (no preconditioner) runs */
static PetscErrorCode CheckMfOperator(MPI_Comm comm)
{
  PetscBool mfop = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-snes_mf_operator", &mfop, NULL));
  PetscCheck(!mfop, comm, PETSC_ERR_USER_INPUT,
             "-snes_mf_operator with -solver static: its multigrid and line search need the assembled tangent as "
             "the operator; leave it out (or use -snes_mf: finite differences, no preconditioner)");
  PetscFunctionReturn(0);
}

/* PETSc's finite-difference Jacobians set the tangent's entries one by one: the tangent by
   stencil is a shell, which failed on one rank and left the other waiting */
static PetscErrorCode CheckFiniteDifferences(MPI_Comm comm)
{
  const char *fd[] = {"-snes_fd", "-snes_fd_color"};

  PetscFunctionBeginUser;
  for (int k = 0; k < 2; k++) {
    PetscBool on = PETSC_FALSE;
    PetscCall(PetscOptionsGetBool(NULL, NULL, fd[k], &on, NULL));
    PetscCheck(!on, comm, PETSC_ERR_USER_INPUT,
               "%s with -solver static: the quasi-static path assembles its own tangent; leave it out (or use "
               "-snes_mf: finite differences, no preconditioner)",
               fd[k]);
  }
  PetscFunctionReturn(0);
}

/* PETSc's nonlinear solvers that run on this problem (Newton's line search and trust region converge; the
   others end unbalanced or stop on the numerical failure check); the rest failed mid-run, after the output
   was opened, with PETSc's words (vinewton*: a shell tangent or an unset product; fas, nasm: their own
   matrices; composite, patch, shell, ksptransposeonly, aspin: what this problem does not give them) */
static PetscErrorCode CheckSnesType(MPI_Comm comm)
{
  char      type[64] = SNESNEWTONLS;
  PetscBool runs;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-snes_type", type, sizeof type, NULL));
  PetscCall(PetscStrInList(type, SNES_TYPES_RUN, ',', &runs));
  PetscCheck(runs, comm, PETSC_ERR_USER_INPUT,
             "-snes_type %s with -solver static: the quasi-static path runs one of " SNES_TYPES_RUN
             " (Newton: newtonls, the default, or newtontr)",
             type);
  PetscFunctionReturn(0);
}

/* the multigrid's levels and coarse tangents are the grid's (MultigridHierarchy): PETSc's -pc_mg_levels and
   -pc_mg_galerkin, under any prefix
   (-tao_nls_pc_mg_levels), would set others on top of its interpolations (0 crashed PCSetFromOptions,
   also under TAO's prefix); GAMG (its -pc_type given under the same prefix) takes it as its most */
static PetscErrorCode CheckMultigridLevels(MPI_Comm comm)
{
  OptionsGiven g;
  char         msg[512] = "";

  PetscFunctionBeginUser;
  PetscCheck(!OptionsGivenGet(&g), PETSC_COMM_SELF, PETSC_ERR_MEM, "cannot list the options given");
  for (PetscInt q = 0; q < g.n && !msg[0]; q++) {
    const char     *name = g.name[q], *value = g.value[q], *pc = NULL;
    char            pc_opt[256], *end;
    const long      levels   = strtol(value, &end, 10);
    const PetscBool galerkin = OptionIs(name, "pc_mg_galerkin");
    if (!OptionIs(name, "pc_mg_levels") && !galerkin) continue;
    snprintf(pc_opt, sizeof pc_opt, "%.*spc_type",
             (int) (strlen(name) - strlen(galerkin ? "pc_mg_galerkin" : "pc_mg_levels")), name);
    for (PetscInt r = 0; r < g.n; r++)
      if (!strcmp(g.name[r], pc_opt)) pc = g.value[r]; /* the last given */
    if (galerkin) {
      /* the coarse tangents are the solver's (Galerkin products, or the stencil's own); with none PETSc
         asked for coarse matrices nobody gave ("Must call DMShellSetGlobalVector()") after the output opened */
      if (!pc || !strcmp(pc, PCMG))
        snprintf(msg, sizeof msg,
                 "%s%s%s with -solver static: the multigrid's coarse tangents are the solver's own (Galerkin "
                 "products of the tangent); leave it unset",
                 name, value[0] ? " " : "", value);
    } else if (!pc || !strcmp(pc, PCMG))
      snprintf(msg, sizeof msg,
               "%s%s%s with -solver static: the multigrid's levels come from the grid (coarsened while every rank "
               "keeps 4 crossings a side); leave it unset",
               name, value[0] ? " " : "", value);
    else if (!value[0] || *end || levels < 1)
      snprintf(msg, sizeof msg, "%s %s: the most levels %s %s may make, a whole number, 1 or more", name, value,
               pc_opt, pc);
  }
  OptionsGivenFree(&g);
  PetscCheck(!msg[0], comm, PETSC_ERR_USER_INPUT, "%s", msg);
  PetscFunctionReturn(0);
}

/* PETSc's counts, limits and tolerances that this path cannot take, under any prefix */
static PetscErrorCode CheckSolverCounts(MPI_Comm comm)
{
  char bad[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  /* GMRES keeps its Hessenberg matrices, 2 (restart + 2)^2 reals, on every rank beside its restart + 1
     vectors: PETSc's allocation overflowed at 1e8 (a segfault) and failed at 40 000 with a line that named
     no option */
  PetscCall(FindBadOption("ksp_gmres_restart", GmresRestartOk, bad, sizeof bad));
  PetscCheck(!bad[0], comm, PETSC_ERR_USER_INPUT,
             "%s: GMRES's restart, a whole number from 1 to %d (its Hessenberg matrices take 2 (restart + 2)^2 "
             "reals on every rank: %d takes %.0f MB, beside restart + 1 vectors)",
             bad, GMRES_RESTART_MAX, GMRES_RESTART_MAX, 16.0 * PetscSqr(GMRES_RESTART_MAX + 2.0) / 1e6);
  { /* the vectors a method keeps (-snes_qn_m 1e8 and the like were killed for memory, their files left behind) */
    const char *const histories[] = {"snes_qn_m", "snes_ngmres_m", "snes_anderson_m", "ksp_gcr_restart", "ksp_bcgsl_ell"};
    for (int k = 0; k < 5 && !bad[0]; k++) PetscCall(FindBadOption(histories[k], HistoryOk, bad, sizeof bad));
    PetscCheck(!bad[0], comm, PETSC_ERR_USER_INPUT,
               "%s with -solver static: a method's history, a whole number from 1 to %d (it keeps that many vectors of "
               "the grid's size, or twice as many, on every rank)",
               bad, HISTORY_MAX);
  }
  /* the solvers' iteration limits, a count (-snes_max_it -1 stopped the first solve with "Internal error,
     solver returned without setting converged reason"; 0 runs, and the load step does not balance) */
  {
    const char *const limits[] = {"snes_max_it", "tao_max_it", "ksp_max_it", "snes_linesearch_max_it"};
    for (int k = 0; k < 4 && !bad[0]; k++) PetscCall(FindBadOption(limits[k], CountOk, bad, sizeof bad));
    PetscCheck(!bad[0], comm, PETSC_ERR_USER_INPUT, "%s with -solver static: an iteration limit, a whole number, 0 or more",
               bad);
    const char *const lags[] = {"snes_lag_jacobian", "snes_lag_preconditioner"};
    for (int k = 0; k < 2 && !bad[0]; k++) PetscCall(FindBadOption(lags[k], LagOk, bad, sizeof bad));
    PetscCheck(!bad[0], comm, PETSC_ERR_USER_INPUT,
               "%s with -solver static: a lag, a whole number (PETSc reads the word as -2 or -1: a tangent never "
               "formed again)",
               bad);
  }
  PetscCall(FindBadOption("ksp_rtol", RtolOk, bad, sizeof bad));
  PetscCheck(!bad[0], comm, PETSC_ERR_USER_INPUT,
             "%s with -solver static: a linear solve's relative tolerance, from 0 to below 1 (at 1 or more the first "
             "residual passes and Newton's steps are zero)",
             bad);
  PetscFunctionReturn(0);
}

/* PETSc's methods, monitors and matrix types that this grid or path cannot take, under any prefix */
static PetscErrorCode CheckSolverTypes(MPI_Comm comm)
{
  char bad[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  /* GAMG's aggregation only: its classical coarsening hung in PETSc's set-up on 2 ranks (on the 25 x 25
     net), and its geometric one needs the crossings' coordinates, which it is not given */
  PetscCall(FindBadOption("pc_gamg_type", GamgTypeOk, bad, sizeof bad));
  PetscCheck(!bad[0], comm, PETSC_ERR_USER_INPUT,
             "%s with -solver static: GAMG's aggregation (agg) only; classical hung in PETSc's set-up on 2 ranks, "
             "geo needs coordinates it is not given",
             bad);
  { /* PETSc's solver options whose value this grid or path cannot take, found before any output exists (under a
       prefix, -mg_levels_pc_type, PETSc reads them as the multigrid sets up, mid-run) */
    static const struct {
      const char *suffix;
      PetscBool (*ok)(const char *);
      const char *why;
    } solver[] = {
        {"pc_type", PcKnown, "not a preconditioner PETSc knows (see -help)"},
        {"snes_monitor_fields", NeverOk,
         "PETSc's monitor by field needs the fields of a DMPlex discretisation, which the fabric's grid has not (it "
         "crashed there); use -snes_monitor"},
        {"snes_converged_reason", NotDetail,
         "PETSc's detailed reason measures the error against the exact solution of a DMPlex discretisation, which "
         "the fabric's grid has not (it crashed there); use -snes_converged_reason"},
        {"ksp_type", KspKnown, "not a Krylov method PETSc knows (see -help)"},
        {"snes_linesearch_damping", LineDampingOk,
         "the line search's first step, a fraction of Newton's step above 0 and at most 2"},
        {"snes_linesearch_minlambda", LineMinOk, "the smallest step the line search tries, from 0 to below 1"},
        {"pc_mg_multiplicative_cycles", CyclesOk,
         "the multigrid's cycles each time it is applied, a whole number, 1 or more (with none it gives zero and no "
         "load step balances)"},
        {"pc_type", PcTypeOk,
         "telescope needs the tangent assembled by PETSc on a sub-grid, patch a DMPlex; the quasi-static path "
         "assembles its own tangent on the grid's DMDA (use mg, gamg, lu ...)"},
    };
    PetscCall(PCInitializePackage());
    PetscCall(KSPInitializePackage());
    PetscCall(MatInitializePackage());
    for (size_t k = 0; k < sizeof solver / sizeof solver[0]; k++) {
      PetscCall(FindBadOption(solver[k].suffix, solver[k].ok, bad, sizeof bad));
      PetscCheck(!bad[0], comm, PETSC_ERR_USER_INPUT, "%s with -solver static: %s", bad, solver[k].why);
    }
  }
  { /* PETSc's X11 plots without a display: "Unable to open display", a traceback (-draw_type image or tikz
       draws to files) */
    const char *display = getenv("DISPLAY");
    PetscBool   drawtype;
    PetscCall(PetscOptionsHasName(NULL, NULL, "-draw_type", &drawtype));
    if (!drawtype && !(display && display[0])) {
      PetscCall(FindBadOption("ksp_plot_eigenvalues", NeverOk, bad, sizeof bad));
      if (!bad[0]) PetscCall(FindBadOption("ksp_plot_eigenvalues_explicitly", NeverOk, bad, sizeof bad));
      PetscCheck(!bad[0], comm, PETSC_ERR_USER_INPUT,
                 "%s: PETSc draws it in an X window, and DISPLAY is not set; give a display, or -draw_type image "
                 "(files)",
                 bad);
    }
  }
  { /* -mat_type itself (-dm_mat_type is refused: SceneCheckUnused) */
    OptionsGiven g;
    bad[0] = 0;
    PetscCheck(!OptionsGivenGet(&g), PETSC_COMM_SELF, PETSC_ERR_MEM, "cannot list the options given");
    for (PetscInt q = 0; q < g.n && !bad[0]; q++)
      if (!strcasecmp(g.name[q], "-mat_type") && !MatOk(g.value[q]))
        PetscCall(PetscSNPrintf(bad, sizeof bad, "%s %s", g.name[q], g.value[q]));
    OptionsGivenFree(&g);
  }
  PetscCheck(!bad[0], comm, PETSC_ERR_USER_INPUT,
             "%s with -solver static: not a matrix type PETSc knows, or one the multigrid's coarsest LU factorisation "
             "does not take (sbaij, is); aij, baij or dense",
             bad);
  PetscFunctionReturn(0);
}

/* block counts PETSc checks against the ranks as the preconditioner sets up, on some ranks only (the others
   waited, and the run was stopped 10 s later, the option unnamed): -pc_asm_blocks below the ranks,
   -pc_redundant_number above them (under any prefix) */
static PetscErrorCode CheckBlockCounts(MPI_Comm comm)
{
  OptionsGiven g;
  PetscMPIInt  size;
  char         msg[512] = "";

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCheck(!OptionsGivenGet(&g), PETSC_COMM_SELF, PETSC_ERR_MEM, "cannot list the options given");
  for (PetscInt q = 0; q < g.n && !msg[0]; q++) {
    const PetscBool asm_ = OptionIs(g.name[q], "pc_asm_blocks"), red = OptionIs(g.name[q], "pc_redundant_number");
    char           *end;
    const long      v = strtol(g.value[q], &end, 10);
    if (!asm_ && !red) continue;
    if (!g.value[q][0] || *end || (asm_ && v < size) || (red && (v < 1 || v > size)))
      snprintf(msg, sizeof msg, "%s %s with -solver static on %d rank%s: %s", g.name[q], g.value[q], size,
               size > 1 ? "s" : "",
               asm_ ? "the additive Schwarz blocks in all, a whole number, at least one a rank"
                    : "the redundant solves, a whole number from 1 to the ranks");
  }
  OptionsGivenFree(&g);
  PetscCheck(!msg[0], comm, PETSC_ERR_USER_INPUT, "%s", msg);
  PetscFunctionReturn(0);
}

/* TAO's Newton line search or trust region, on the unconstrained Pi (the others
   crashed or ran out of memory on the pushing test: ntl, ipm, pdipm) */
static PetscErrorCode CheckTaoType(MPI_Comm comm)
{
  char      type[64] = TAONLS;
  PetscBool newton;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-tao_type", type, sizeof type, NULL));
  PetscCall(PetscStrInList(type, TAONLS "," TAONTR "," TAOBNLS, ',', &newton));
  PetscCheck(newton, comm, PETSC_ERR_USER_INPUT,
             "-tao_type %s with -static_minimizer tao: the quasi-static path runs TAO's Newton line search or "
             "trust region (-tao_type nls, ntr or bnls)",
             type);
  PetscCall(CheckTaoFactors(comm));
  PetscFunctionReturn(0);
}

/* PETSc reads -matptap_via when the multigrid first forms its Galerkin products, mid-run: a
   product of small matrices of the tangent's type (AIJ on this communicator) reads it now */
static PetscErrorCode CheckPtapVia(MPI_Comm comm, const StaticOptions *o)
{
  Mat      A, C;
  PetscInt r0;

  PetscFunctionBeginUser;
  PetscCall(MatCreateAIJ(comm, 1, 1, PETSC_DETERMINE, PETSC_DETERMINE, 1, NULL, 0, NULL, &A));
  PetscCall(MatGetOwnershipRange(A, &r0, NULL));
  PetscCall(MatSetValue(A, r0, r0, 1.0, INSERT_VALUES));
  PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatPtAP(A, A, MAT_INITIAL_MATRIX, PETSC_DEFAULT, &C));
  PetscCall(MatDestroy(&C));
  PetscCall(MatDestroy(&A));
  { /* ... which the tangent by stencil never forms: its coarse operators are its own (StaticGalerkin) */
    char      via[64] = "";
    PetscBool set     = PETSC_FALSE;
    PetscCall(PetscOptionsGetString(NULL, NULL, "-matptap_via", via, sizeof via, &set));
    PetscCheck(!set || !(o->tangent == TANGENT_STENCIL && StaticOptionsStencilFits(o)), comm, PETSC_ERR_USER_INPUT,
               "-matptap_via %s with the tangent stored by stencil: it forms the multigrid's coarse operators itself, "
               "not by PETSc's Galerkin products; it applies with -static_tangent aij",
               via);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode StaticOptionsCheck(MPI_Comm comm)
{
  StaticOptions o;

  PetscFunctionBeginUser;
  PetscCall(CheckWideIntegers(comm)); /* before anything reads one */
  PetscCall(StaticOptionsRead(comm, &o));
  PetscCall(CheckBalanceTestOnly(comm));
  if (o.tao) PetscCall(CheckTaoReadsNoSnes(comm));
  PetscCheck(!(o.tangent_set && o.tangent == TANGENT_STENCIL && !StaticOptionsStencilFits(&o)), comm, PETSC_ERR_USER_INPUT,
             "-static_tangent stencil: the tangent by stencil needs the multigrid preconditioner with the line "
             "smoother (-pc_type mg, -mg_line_smoother 1); use -static_tangent aij with another");
  PetscCall(CheckMfOperator(comm));
  PetscCall(CheckFiniteDifferences(comm));
  PetscCall(CheckSnesType(comm));
  PetscCall(CheckMultigridLevels(comm));
  PetscCall(CheckSolverCounts(comm));
  PetscCall(CheckSolverTypes(comm));
  PetscCall(CheckBlockCounts(comm));
  if (o.tao) PetscCall(CheckTaoType(comm));
  PetscCall(CheckPtapVia(comm, &o));
  PetscFunctionReturn(0);
}
