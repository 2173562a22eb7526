/* material.c - yarn laws: the tabulated yarn law's fast form and the tangent bound.
 *
 * A tabulated law is a CSV file with the header "strain_pct,force_cN" and rows of
 * yarn strain (%) and yarn force (cN), starting at 0,0 with strictly increasing
 * strain. It is interpolated with GSL's Steffen spline (monotone between the data,
 * no overshoot), extended linearly past the last row, and resampled at load time
 * on YARN_TABLE_NODES uniform nodes (value and slope) for an O(1) cubic Hermite
 * evaluation in the force kernel (see material.h).
 */
#include "material.h"
#include "hash.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_interp.h>
#include <gsl/gsl_sf_gamma.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

/* The header line p (trimmed) is "strain_pct,force_cN"; else msg says what was found. */
static void CheckYarnHeader(const YarnLaw *y, PetscInt lineno, char *p, char *msg, size_t len)
{
  p[strcspn(p, "\r\n")] = 0;
  if (strcmp(p, "strain_pct,force_cN"))
    snprintf(msg, len, "-%s_law_csv %s line %d: expected the header 'strain_pct,force_cN', found '%.64s'", y->name,
             y->csv, (int) lineno, p);
}

/* A data row p: two finite numbers s (strain, %) and f (force, cN) that continue a physical law
   after count rows, the last of them prev_s, prev_f: the first row 0,0, then strictly increasing
   strains and forces that never fall (a yarn does not soften: there is no softening model) nor
   go negative. Otherwise msg says what is wrong, with the file, the line and the values. */
#define YARN_STRAIN_PCT_MAX 1e6 /* a table's largest strain, % */

static void CheckYarnRow(const YarnLaw *y, PetscInt lineno, char *p, PetscInt count, double prev_s, double prev_f,
                         double *s, double *f, char *msg, size_t len)
{
  char  *end, *q, at[PETSC_MAX_PATH_LEN + 64];
  size_t n;

  snprintf(at, sizeof at, "-%s_law_csv %s line %d", y->name, y->csv, (int) lineno);
  p[strcspn(p, "\r\n")] = 0;
  *s                    = strtod(p, &end);
  if (end == p || *end != ',') {
    snprintf(msg, len, "%s: expected 'strain_pct,force_cN' numbers, found '%.64s'", at, p);
    return;
  }
  q  = end + 1;
  *f = strtod(q, &end);
  n  = strspn(end, " \t");
  if (end == q || end[n] || !isfinite(*s) || !isfinite(*f))
    snprintf(msg, len, "%s: expected two finite numbers 'strain_pct,force_cN', found '%.64s'", at, p);
  else if (count == 0 && (*s != 0.0 || *f != 0.0))
    snprintf(msg, len, "%s: the first row must be 0,0 (no force at zero yarn strain), found %g,%g", at, *s, *f);
  else if (*f < 0)
    snprintf(msg, len, "%s: force %g cN is negative: the law is the tension of a stretched yarn (>= 0)", at, *f);
  else if (*s > YARN_STRAIN_PCT_MAX) /* the energy's integral of a law over 1e300 % overflowed (the static path) */
    snprintf(msg, len, "%s: strain %g %% is beyond %g %% (ten thousand times the yarn's length, which no yarn survives): strains are in %%",
             at, *s, YARN_STRAIN_PCT_MAX);
  else if (count > 0 && *s == prev_s)
    snprintf(msg, len, "%s: strain %g %% repeats the line before: two forces at one strain", at, *s);
  else if (count > 0 && !(*s > prev_s))
    snprintf(msg, len, "%s: strain %g %% does not increase (%g %% on the line before)", at, *s, prev_s);
  else if (count > 0 && *f < prev_f)
    snprintf(msg, len,
             "%s: force %g cN falls below %g cN of the line before: a yarn law must not soften (no softening model)",
             at, *f, prev_f);
}

/* Read the CSV into SI arrays: yarn strain (-) and force (N), and each row's line in the file. */
static PetscErrorCode ReadYarnCSV(MPI_Comm comm, const YarnLaw *y, PetscInt *n, double **strain, double **force,
                                  PetscInt **at)
{
  FILE     *fp;
  char     *line = NULL, msg[PETSC_MAX_PATH_LEN + 256] = "";
  size_t    linecap = 0;
  PetscInt  cap = 64, count = 0, lineno = 0;
  PetscBool header = PETSC_FALSE;
  double    prev_s = 0, prev_f = 0;

  PetscFunctionBeginUser;
  { /* a device or a pipe (/dev/zero, a FIFO) would be read for ever */
    struct stat st;
    PetscCheck(stat(y->csv, &st) != 0 || S_ISREG(st.st_mode), comm, PETSC_ERR_FILE_OPEN,
               "-%s_law_csv %s: not a regular file (a yarn law is a CSV file)", y->name, y->csv);
  }
  fp = fopen(y->csv, "r");
  PetscCheck(fp, comm, PETSC_ERR_FILE_OPEN, "-%s_law_csv %s: cannot open the yarn law file", y->name, y->csv);
  PetscCall(PetscMalloc3(cap, strain, cap, force, cap, at));
  for (ssize_t got; !msg[0] && (got = getline(&line, &linecap, fp)) >= 0;) { /* whole lines, of any length */
    char       *p = line + strspn(line, " \t");
    const char *cr;
    double      s = 0, f = 0;
    lineno++;
    if (memchr(line, 0, (size_t) got)) { /* the line would end there: '1.5,10\0' '4.1' read as 1.5,10 */
      PetscCall(PetscSNPrintf(msg, sizeof msg, "-%s_law_csv %s line %" PetscInt_FMT ": a NUL byte (not a text file?)",
                              y->name, y->csv, lineno));
      break;
    }
    if (lineno == 1 && !strncmp(p, "\xEF\xBB\xBF", 3)) p += 3 + strspn(p + 3, " \t"); /* a spreadsheet's UTF-8 BOM */
    cr = strchr(p, '\r');
    if (cr) cr += strspn(cr, "\r");
    if (cr && *cr && *cr != '\n') { /* CRs before LF end a line as LF does; a CR alone would hide every line after it */
      PetscCall(PetscSNPrintf(msg, sizeof msg,
                              "-%s_law_csv %s line %" PetscInt_FMT
                              ": a carriage return within the line (old Mac line ends, CR alone): save the file with "
                              "LF or CR LF line ends",
                              y->name, y->csv, lineno));
      break;
    }
    if (*p == '#' || *p == '\n' || *p == '\r' || *p == 0) continue;
    if (!header) {
      CheckYarnHeader(y, lineno, p, msg, sizeof msg);
      header = PETSC_TRUE;
      continue;
    }
    CheckYarnRow(y, lineno, p, count, prev_s, prev_f, &s, &f, msg, sizeof msg);
    if (msg[0]) break;
    if (count == cap) {
      double   *s2, *f2;
      PetscInt *a2;
      PetscCall(PetscMalloc3(2 * cap, &s2, 2 * cap, &f2, 2 * cap, &a2));
      PetscCall(PetscArraycpy(s2, *strain, count));
      PetscCall(PetscArraycpy(f2, *force, count));
      PetscCall(PetscArraycpy(a2, *at, count));
      PetscCall(PetscFree3(*strain, *force, *at));
      *strain = s2;
      *force  = f2;
      *at     = a2;
      cap *= 2;
    }
    (*at)[count]     = lineno;
    (*strain)[count] = s / 100.0;
    (*force)[count]  = f / 100.0 * (y->bundle > 1 ? y->bundle : 1.0);
    prev_s           = s; /* as given: the next row is compared with it exactly */
    prev_f           = f;
    count++;
  }
  free(line);
  fclose(fp);
  if (msg[0] || !header || count < 3) PetscCall(PetscFree3(*strain, *force, *at));
  PetscCheck(!msg[0], comm, PETSC_ERR_FILE_UNEXPECTED, "%s", msg);
  PetscCheck(header, comm, PETSC_ERR_FILE_UNEXPECTED,
             "-%s_law_csv %s: empty file (expected the header 'strain_pct,force_cN' and rows)", y->name, y->csv);
  PetscCheck(count >= 3, comm, PETSC_ERR_FILE_UNEXPECTED,
             "-%s_law_csv %s: %" PetscInt_FMT
             " data row%s, a yarn law needs at least 3 (0,0 and two more, for the spline)",
             y->name, y->csv, count, count == 1 ? "" : "s");
  *n = count;
  PetscFunctionReturn(0);
}

/* slope of the cubic Hermite of cell k at t in [0,1] */
static PetscReal HermiteSlope(const YarnLaw *y, PetscInt k, PetscReal t)
{
  const PetscReal h = y->tab_h;
  return 6.0 * t * (1.0 - t) * (y->tab_T[k + 1] - y->tab_T[k]) / h + (1.0 - 4.0 * t + 3.0 * t * t) * y->tab_dT[k] +
         (3.0 * t * t - 2.0 * t) * y->tab_dT[k + 1];
}

/* The table (YARN_TABLE_NODES uniform nodes over [0, last strain]) must reproduce each of the n data
   rows (strain es, force fs): within YARN_TABLE_TOL of the row's own force (a row of no force: of the least
   positive force). A last row far beyond the others leaves them between two nodes, and the law they give is
   lost; a tolerance of the largest force let a far row of a large force pass, and the rows before it came out
   up to 37 % off. The first row it misses, or -1. */
#define YARN_TABLE_TOL 0.01
static PetscInt TableMissesRow(const YarnLaw *y, PetscInt n, const double *es, const double *fs)
{
  double least = fs[n - 1]; /* forces never fall: the last is the largest */

  for (PetscInt i = 0; i < n; i++)
    if (fs[i] > 0) least = PetscMin(least, fs[i]);
  for (PetscInt i = 0; i < n; i++)
    if (!(PetscAbsReal(YarnTension(y, es[i]) - fs[i]) <= YARN_TABLE_TOL * PetscMax(fs[i], least))) return i;
  return -1;
}

static PetscErrorCode BuildTable(MPI_Comm comm, YarnLaw *y)
{
  PetscInt          n, N = YARN_TABLE_NODES, ncell = N - 1;
  double           *es, *fs;
  PetscInt         *at;
  gsl_interp       *interp;
  gsl_interp_accel *acc;
  PetscBool         finite = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscCall(ReadYarnCSV(comm, y, &n, &es, &fs, &at));
  gsl_set_error_handler_off();
  interp = gsl_interp_alloc(gsl_interp_steffen, (size_t) n);
  acc    = gsl_interp_accel_alloc();
  if (!interp || !acc || gsl_interp_init(interp, es, fs, (size_t) n)) { /* freed before the refusal */
    const PetscBool built = interp && acc ? PETSC_TRUE : PETSC_FALSE;
    if (acc) gsl_interp_accel_free(acc);
    if (interp) gsl_interp_free(interp);
    PetscCall(PetscFree3(es, fs, at));
    SETERRQ(comm, built ? PETSC_ERR_FILE_UNEXPECTED : PETSC_ERR_MEM, "-%s_law_csv %s: GSL could not %s the Steffen spline",
            y->name, y->csv, built ? "build" : "allocate");
  }
  y->ntab      = N;
  y->tab_end   = es[n - 1];
  y->tab_h     = y->tab_end / (PetscReal) ncell;
  y->tab_inv_h = 1.0 / y->tab_h;
  PetscCall(PetscMalloc2(N, &y->tab_T, N, &y->tab_dT));
  for (PetscInt k = 0; k < N; k++) {
    double e     = PetscMin(k * y->tab_h, es[n - 1]);
    y->tab_T[k]  = gsl_interp_eval(interp, es, fs, e, acc);
    y->tab_dT[k] = gsl_interp_eval_deriv(interp, es, fs, e, acc);
  }
  gsl_interp_accel_free(acc);
  gsl_interp_free(interp);
  { /* the Hermite cells between the nodes rise monotonically, as the Steffen spline does: no node's slope above
       3 times its cells' secants (Fritsch and Carlson). A row that jumps within a cell gave its nodes slopes that
       took the cubic far above the data (7e8 N from rows up to 1e3 N); smooth data never reach the bound. */
    PetscInt limited = 0;
    for (PetscInt k = 0; k < N; k++) {
      PetscReal m = y->tab_dT[k];
      if (k > 0) m = PetscMin(m, 3.0 * (y->tab_T[k] - y->tab_T[k - 1]) * y->tab_inv_h);
      if (k < ncell) m = PetscMin(m, 3.0 * (y->tab_T[k + 1] - y->tab_T[k]) * y->tab_inv_h);
      m = PetscMax(m, 0.0);
      if (m != y->tab_dT[k]) limited++;
      y->tab_dT[k] = m;
    }
    PetscCall(PetscInfo(NULL, "-%s_law_csv %s: %" PetscInt_FMT " node slopes limited to 3 times a secant\n", y->name,
                        y->csv, limited));
  }

  /* range-max (sparse) table of the slope per cell, for ChordTangentMax */
  y->nlev = 1;
  while ((1 << y->nlev) <= ncell) y->nlev++;
  PetscCall(PetscMalloc1(y->nlev, &y->tab_slope_max));
  PetscCall(PetscMalloc1(ncell, &y->tab_slope_max[0]));
  y->EA = 0.0;
  finite = finite && isfinite(y->tab_T[0]);
  for (PetscInt k = 0; k < ncell; k++) {
    PetscReal m = 0.0;
    for (int q = 0; q <= 4; q++) {
      const PetscReal slope = PetscAbsReal(HermiteSlope(y, k, 0.25 * q));
      finite                = finite && isfinite(slope); /* PetscMax would pass over a NaN */
      m                     = PetscMax(m, slope);
    }
    y->tab_slope_max[0][k] = m;
    y->EA                  = PetscMax(y->EA, m);
    finite                 = finite && isfinite(m) && isfinite(y->tab_T[k + 1]);
  }
  {
    const PetscInt miss = finite ? TableMissesRow(y, n, es, fs) : -1;
    const double   cN   = 100.0 / (y->bundle > 1 ? y->bundle : 1.0); /* N of the table as cN of the file */
    double         row[4] = {0, 0, 0, 0};                            /* its line, strain, force, table's force */
    if (miss >= 0) row[0] = at[miss], row[1] = es[miss], row[2] = fs[miss], row[3] = YarnTension(y, es[miss]);
    PetscCall(PetscFree3(es, fs, at)); /* before any refusal */
    PetscCheck(miss < 0, comm, PETSC_ERR_FILE_UNEXPECTED,
               "-%s_law_csv %s line %.0f: the yarn table gives %.6g cN at %.6g %%, the row %.6g cN, off by more "
               "than %.6g %% of the row's force: its node spacing (last strain %.6g %% / %d = %.6g %%) is too "
               "coarse for the data (end the law nearer its other rows, or add rows where it bends)",
               y->name, y->csv, row[0], row[3] * cN, row[1] * 100.0, row[2] * cN, 100.0 * YARN_TABLE_TOL,
               y->tab_end * 100.0, YARN_TABLE_NODES - 1, y->tab_h * 100.0);
  }
  PetscCheck(finite, comm, PETSC_ERR_FILE_UNEXPECTED,
             "-%s_law_csv %s: the law's slope overflows (not a finite number of N per unit yarn strain): forces are "
             "in cN, strains in %%",
             y->name, y->csv);
  PetscCheck(y->EA > 0, comm, PETSC_ERR_FILE_UNEXPECTED,
             "-%s_law_csv %s: every force is 0: a yarn law needs a positive stiffness", y->name, y->csv);
  /* as -warp_modulus_cN_tex (EA / tex is the same for a coarse fabric's bundle of yarns) */
  PetscCheck(y->EA * 100.0 / y->tex <= 1e6, comm, PETSC_ERR_FILE_UNEXPECTED,
             "-%s_law_csv %s: the law's largest slope, %.6g cN/tex at -%s_tex %.6g, is beyond the physical range (at "
             "most 1e6 cN/tex, as -%s_modulus_cN_tex: the stiffest fibres, high-modulus carbon, reach about 3e4 "
             "cN/tex): forces are in cN, strains in %%",
             y->name, y->csv, (double) (y->EA * 100.0 / y->tex), y->name, (double) (y->tex / PetscMax(1.0, (double) y->bundle)), y->name);
  for (PetscInt l = 1; l < y->nlev; l++) {
    PetscInt w = 1 << l;
    PetscCall(PetscMalloc1(ncell - w + 1, &y->tab_slope_max[l]));
    for (PetscInt k = 0; k + w <= ncell; k++)
      y->tab_slope_max[l][k] = PetscMax(y->tab_slope_max[l - 1][k], y->tab_slope_max[l - 1][k + w / 2]);
  }
  PetscFunctionReturn(0);
}

/* slope of the piecewise law on the side dir (-1 left, +1 right) of e */
static PetscReal PiecewiseSlope(const YarnLaw *y, PetscReal e, int dir)
{
  const PetscReal c = y->crimp, h = 1e-7 * dir;
  if (e < y->e_contact || (e == y->e_contact && dir < 0)) return y->EA;
  if (e < 0 || (e == 0 && dir < 0)) return y->k_comp * y->EA;
  if (e < c || (e == c && dir < 0)) return y->Ec;
  /* yarn extension: slope of the (tabulated) yarn law */
  if (!y->ntab) return y->EA / (1.0 + c);
  return (ChordTensionPiecewise(y, e + PetscAbsReal(h)) - ChordTensionPiecewise(y, e)) / PetscAbsReal(h);
}

/* Replace each kink e0 by the cubic Hermite on [e0-d, e0+d] ([0, 2d] for the kink at rest)
   matching the piecewise law's values and slopes at both ends (d shrinks so that blends
   never overlap). */
PetscErrorCode YarnLawSetUp(YarnLaw *y, MPI_Comm comm)
{
  PetscReal kinks[3];
  PetscInt  nk = 0;

  PetscFunctionBeginUser;
  y->mu      = y->tex * 1e-6;
  y->break_e = y->break_ey > 0.0 ? y->crimp + y->break_ey * (1.0 + y->crimp) : INFINITY;
  if (y->csv[0]) PetscCall(BuildTable(comm, y));
  if (y->decrimp_ratio > 0) y->Ec = y->decrimp_ratio * y->EA; /* before the blends, which join this piece */
  y->nblend   = 0;
  kinks[nk++] = y->e_contact;
  kinks[nk++] = 0.0;
  if (y->crimp > 0) kinks[nk++] = y->crimp;
  for (PetscInt k = 0; k < nk && y->smoothing > 0; k++) {
    const PetscReal e0 = kinks[k], prev = k > 0 ? kinks[k - 1] : -1.0, next = k + 1 < nk ? kinks[k + 1] : 1.0;
    const PetscReal d = PetscMin(y->smoothing, 0.3 * PetscMin(e0 - prev, next - e0));
    /* the blend at e = 0 lies on the tension side, so that a fabric at rest is stress-free */
    const PetscReal lo = e0 == 0.0 ? 0.0 : e0 - d, hi = e0 == 0.0 ? 2.0 * d : e0 + d, h = hi - lo;
    const PetscReal T0 = ChordTensionPiecewise(y, lo), T1 = ChordTensionPiecewise(y, hi);
    const PetscReal m0 = PiecewiseSlope(y, lo, -1), m1 = PiecewiseSlope(y, hi, +1);
    PetscReal       smax = 0;
    if (PiecewiseSlope(y, e0, -1) == PiecewiseSlope(y, e0, +1)) continue; /* no kink */
    y->blend[y->nblend].lo = lo;
    y->blend[y->nblend].hi = hi;
    y->blend[y->nblend].c0 = T0;
    y->blend[y->nblend].c1 = m0;
    y->blend[y->nblend].c2 = (3.0 * (T1 - T0) / h - 2.0 * m0 - m1) / h;
    y->blend[y->nblend].c3 = (m0 + m1 - 2.0 * (T1 - T0) / h) / (h * h);
    for (int q = 0; q <= 64; q++) {
      const PetscReal s = h * q / 64.0, c1 = y->blend[y->nblend].c1, c2 = y->blend[y->nblend].c2;
      smax = PetscMax(smax, PetscAbsReal(c1 + s * (2.0 * c2 + 3.0 * s * y->blend[y->nblend].c3)));
    }
    y->blend[y->nblend].slope_max = 1.05 * smax;
    y->nblend++;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode YarnLawDestroy(YarnLaw *y)
{
  PetscFunctionBeginUser;
  if (y->ntab) {
    PetscCall(PetscFree2(y->tab_T, y->tab_dT));
    for (PetscInt l = 0; l < y->nlev; l++) PetscCall(PetscFree(y->tab_slope_max[l]));
    PetscCall(PetscFree(y->tab_slope_max));
    y->ntab = 0;
  }
  PetscFunctionReturn(0);
}

/* ---------------- the scatter of the breaking strain ---------------- */

/* the coefficient of variation of a Weibull distribution of shape k:
   CV^2 = Gamma(1 + 2/k) / Gamma(1 + 1/k)^2 - 1, which falls as k grows */
static PetscReal WeibullCV(PetscReal k)
{
  return PetscSqrtReal(PetscExpReal(gsl_sf_lngamma(1.0 + 2.0 / k) - 2.0 * gsl_sf_lngamma(1.0 + 1.0 / k)) - 1.0);
}

PetscReal WeibullShape(PetscReal cv)
{
  PetscReal lo = 0.0, hi = 20.0; /* log k: k from 1 (CV 1) to 4.9e8 (CV 2.6e-9) */
  for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; it++) {
    const PetscReal mid = 0.5 * (lo + hi);
    if (WeibullCV(PetscExpReal(mid)) > cv) lo = mid;
    else hi = mid;
  }
  return PetscExpReal(0.5 * (lo + hi));
}

/* Weakest link: a yarn of n segments breaks where its weakest segment does, and the smallest of n
   draws of Weibull(k, scale) is Weibull(k, scale n^(-1/k)). A yarn test at gauge G (ISO 2062:
   500 mm) spans n = G / ((1 + c) L0) segments, so segments of scale lambda_g n^(1/k) give yarns of
   that gauge the measured mean break_ey = lambda_g Gamma(1 + 1/k) and the measured CV. */
PetscErrorCode YarnBreakSetUp(YarnLaw *y, PetscReal L0, MPI_Comm comm)
{
  PetscReal n;

  PetscFunctionBeginUser;
  y->break_k = y->break_scale = 0;
  if (!(y->break_ey > 0) || !(y->break_cv > 0)) PetscFunctionReturn(0);
  n = y->break_gauge / ((1.0 + y->crimp) * L0);
  PetscCheck(n >= 1.0, comm, PETSC_ERR_USER_INPUT,
             "-break_gauge_mm %.6g: shorter than one %s segment of yarn (%.6g mm): the yarn test's gauge must span segments",
             (double) (1e3 * y->break_gauge), y->name, (double) (1e3 * (1.0 + y->crimp) * L0));
  y->break_k     = WeibullShape(y->break_cv);
  y->break_scale = y->break_ey / PetscExpReal(gsl_sf_lngamma(1.0 + 1.0 / y->break_k)) *
                   PetscPowReal(n, 1.0 / y->break_k);
  PetscFunctionReturn(0);
}

/* one step of splitmix64: the state advanced by the increment, then mixed */
static uint64_t Step64(uint64_t z)
{
  return Mix64(z + HASH_GOLDEN);
}

PetscReal SegmentBreakStrain(const YarnLaw *y, PetscInt64 seed, int dir, PetscInt i, PetscInt j)
{
  uint64_t  h;
  PetscReal u, ey;

  if (!(y->break_k > 0)) return y->break_e;
  h  = Step64(Step64(Step64(Step64((uint64_t) seed) ^ (uint64_t) dir) ^ (uint64_t) j) ^ (uint64_t) i);
  u  = ((PetscReal) (h >> 11) + 0.5) * 0x1.0p-53; /* uniform in (0, 1) */
  ey = y->break_scale * PetscPowReal(-PetscLogReal(u), 1.0 / y->break_k);
  return y->crimp + ey * (1.0 + y->crimp);
}
