/* test_kernels.c - unit tests of the force kernel and the yarn law.
 *
 *  forces:  the kernel's forces equal minus the gradient of the energies of MODEL.md 5.1-5.3,
 *           written here independently and differentiated by central differences, on a
 *           randomly distorted grid with absent points (holes, a cut corner) that exercises
 *           compression, de-crimping, extension, one-sided shear at edges and jamming.
 *  law:     d/de ChordEnergy = ChordTension and ChordTensionSlope = dT/de (central differences)
 *           over every regime of a linear and a tabulated law with smoothing blends; the energy's
 *           increments equal Gauss integrals of T.
 *  table:   the fast yarn table equals GSL's Steffen spline of the CSV, and extends linearly.
 *  tangent: ChordTangentMax of the piecewise-linear law over strain windows.
 */
#include "kernels.h"

#include <gsl/gsl_interp.h>
#include <math.h>

static int failures = 0;

static void Check(const char *what, double err, double tol)
{
  int ok = err <= tol;
  printf("%s %s: %.3e (tolerance %.1e)\n", ok ? "PASS" : "FAIL", what, err, tol);
  if (!ok) failures++;
}

#define NX 9
#define NY 7

static int Ex(const Patch *p, int i, int j) { return i >= 0 && i < NX && j >= 0 && j < NY && p->exists[j * NX + i]; }

/* traction energy per unit rest length: W(e) = integral of T(e) de (linear laws) */
static double W(const YarnLaw *y, double e)
{
  const double c = y->crimp;
  if (e <= y->e_contact) return 0.5 * y->k_comp * y->EA * y->e_contact * y->e_contact + y->k_comp * y->EA * y->e_contact * (e - y->e_contact) + 0.5 * y->EA * (e - y->e_contact) * (e - y->e_contact);
  if (e <= 0) return 0.5 * y->k_comp * y->EA * e * e;
  if (e <= c) return 0.5 * y->Ec * e * e;
  return 0.5 * y->Ec * c * c + y->Ec * c * (e - c) + y->EA * (e - c) * (e - c) / (2 * (1 + c));
}

static double Dist(const double *a, const double *b) { return sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2])); }

/* total energy of MODEL.md 5.1-5.3 */
static double Energy(const Patch *p, const double *x)
{
  double E = 0;
#define X(i, j) (x + 3 * ((j) * NX + (i)))
  for (int j = 0; j < NY; j++)
    for (int i = 0; i < NX; i++) {
      if (!Ex(p, i, j)) continue;
      /* traction */
      if (Ex(p, i + 1, j)) E += p->ax * W(p->warp, Dist(X(i, j), X(i + 1, j)) / p->ax - 1);
      if (Ex(p, i, j + 1)) E += p->ay * W(p->weft, Dist(X(i, j), X(i, j + 1)) / p->ay - 1);
      /* bending, centre (i,j) along x and along y */
      for (int dir = 0; dir < 2; dir++) {
        int di = dir == 0, dj = dir == 1;
        if (!Ex(p, i - di, j - dj) || !Ex(p, i + di, j + dj)) continue;
        const double *a = X(i - di, j - dj), *b = X(i, j), *c = X(i + di, j + dj);
        double        e1[3], e2[3], s = 0;
        for (int d = 0; d < 3; d++) e1[d] = b[d] - a[d], e2[d] = c[d] - b[d];
        for (int d = 0; d < 3; d++) s += e1[d] * e2[d];
        s /= Dist(a, b) * Dist(b, c);
        E += (dir == 0 ? p->kbx : p->kby) * (1 - s);
      }
      /* shear at crossing (i,j), one-sided tangents at edges */
      {
        int hl = Ex(p, i - 1, j), hr = Ex(p, i + 1, j), hd = Ex(p, i, j - 1), hu = Ex(p, i, j + 1);
        if ((hl || hr) && (hd || hu)) {
          const double *xp = X(hr ? i + 1 : i, j), *xm = X(hl ? i - 1 : i, j), *yp = X(i, hu ? j + 1 : j), *ym = X(i, hd ? j - 1 : j);
          double        tw[3], tf[3], s = 0;
          for (int d = 0; d < 3; d++) tw[d] = xp[d] - xm[d], tf[d] = yp[d] - ym[d];
          for (int d = 0; d < 3; d++) s += tw[d] * tf[d];
          s /= Dist(xm, xp) * Dist(ym, yp);
          double jam = fabs(s) > p->s_lock ? fabs(s) - p->s_lock : 0;
          E += 0.5 * p->Ks * s * s + 0.5 * p->Kj * jam * jam;
        }
      }
    }
#undef X
  return E;
}

static PetscErrorCode TestForces(void)
{
  YarnLaw warp = {0}, weft = {0};
  Patch   p    = {0};
  double  x[3 * NX * NY], f[3 * NX * NY], tmax, fbig = 0, errmax = 0;
  int     jammed = 0, compressed = 0, extended = 0, contact = 0;

  PetscFunctionBeginUser;
  warp.name = "warp", warp.EA = 52, warp.crimp = 0.08, warp.Ec = 2.6, warp.k_comp = 1e-3, warp.e_contact = -0.08, warp.break_e = INFINITY;
  weft.name = "weft", weft.EA = 40, weft.crimp = 0.05, weft.Ec = 3.0, weft.k_comp = 1e-3, weft.e_contact = -0.2, weft.break_e = INFINITY;
  p.nx = NX, p.ny = NY, p.xm = p.gxm = NX, p.ym = p.gym = NY;
  p.ax = 4.2e-4, p.ay = 3.9e-4, p.warp = &warp, p.weft = &weft;
  p.traction = p.bending = p.shear = PETSC_TRUE;
  p.kbx = 1e-6 / p.ax, p.kby = 2e-6 / p.ay;
  p.Ks = 5000 * p.ax * p.ay, p.Kj = 30 * p.Ks, p.s_lock = sin(10 * M_PI / 180);
  PetscCall(PetscCalloc1(NX * NY, &p.exists));
  PetscCall(PetscCalloc1(NX * NY, &p.broken_x));
  PetscCall(PetscCalloc1(NX * NY, &p.broken_y));
  for (int k = 0; k < NX * NY; k++) p.exists[k] = 1;
  p.exists[3 * NX + 4] = 0; /* a hole */
  p.exists[0]          = 0; /* a cut corner */
  p.exists[NX - 1]     = 0;
  PetscCall(PatchSetUp(&p));

  srand(12345);
  for (int j = 0; j < NY; j++)
    for (int i = 0; i < NX; i++) {
      double *q = x + 3 * (j * NX + i);
      q[0]      = i * p.ax * 1.04 + 0.3 * j * p.ay + 0.12 * p.ax * (2.0 * rand() / RAND_MAX - 1); /* ~17 deg shear: jams */
      q[1]      = j * p.ay + 0.12 * p.ay * (2.0 * rand() / RAND_MAX - 1);
      q[2]      = 0.2 * p.ax * (2.0 * rand() / RAND_MAX - 1);
    }
  {
    const PetscInt box[4] = {0, NX, 0, NY};
    ComputeInternalForces(&p, x, box, f, &tmax);
  }
  for (int k = 0; k < 3 * NX * NY; k++) {
    const int    point = k / 3;
    const double h     = 1e-6 * p.ax, keep = x[k];
    double       Ep, Em, fd;
    if (!p.exists[point]) continue;
    x[k] = keep + h;
    Ep   = Energy(&p, x);
    x[k] = keep - h;
    Em   = Energy(&p, x);
    x[k] = keep;
    fd   = -(Ep - Em) / (2 * h);
    fbig   = fbig > fabs(fd) ? fbig : fabs(fd);
    errmax = errmax > fabs(fd - f[k]) ? errmax : fabs(fd - f[k]);
  }
  /* what the distorted state exercises */
  for (int j = 0; j < NY; j++)
    for (int i = 0; i + 1 < NX; i++)
      if (Ex(&p, i, j) && Ex(&p, i + 1, j)) {
        double e = Dist(x + 3 * (j * NX + i), x + 3 * (j * NX + i + 1)) / p.ax - 1;
        compressed += e < 0, extended += e > warp.crimp, contact += e < warp.e_contact;
      }
  for (int j = 1; j + 1 < NY; j++)
    for (int i = 1; i + 1 < NX; i++) {
      const double *a = x + 3 * (j * NX + i - 1), *b = x + 3 * (j * NX + i + 1), *c = x + 3 * ((j - 1) * NX + i), *d = x + 3 * ((j + 1) * NX + i);
      double        s = 0;
      if (!Ex(&p, i, j) || !Ex(&p, i - 1, j) || !Ex(&p, i + 1, j) || !Ex(&p, i, j - 1) || !Ex(&p, i, j + 1)) continue;
      for (int q = 0; q < 3; q++) s += (b[q] - a[q]) * (d[q] - c[q]);
      jammed += fabs(s / (Dist(a, b) * Dist(c, d))) > p.s_lock;
    }
  /* a sub-box computes exactly the forces the full sweep computes on its points */
  {
    const PetscInt boxes[4][4] = {{3, NX, 0, NY}, {0, 4, 2, 6}, {2, 7, 1, 5}, {5, 6, 6, 7}};
    double         g[3 * NX * NY], tm, worst = 0;
    for (int b = 0; b < 4; b++) {
      for (int k = 0; k < 3 * NX * NY; k++) g[k] = -12345.0;
      ComputeInternalForces(&p, x, boxes[b], g, &tm);
      for (int j = boxes[b][2]; j < boxes[b][3]; j++)
        for (int i = boxes[b][0]; i < boxes[b][1]; i++)
          for (int d = 0; d < 3; d++) worst = fmax(worst, fabs(g[3 * (j * NX + i) + d] - f[3 * (j * NX + i) + d]));
    }
    Check("forces on sub-boxes equal the full sweep's (bit-identical: max difference)", worst, 0.0);
  }
  printf("segments along x: %d compressed (%d in contact), %d in yarn extension; %d jammed crossings; largest force %.3e N\n", compressed, contact, extended, jammed, fbig);
  Check("kernel force vs -grad(energy) by central differences, max error / max force", errmax / fbig, 1e-6);
  Check("distorted state has compressed, in-contact, extended segments and jammed crossings (0 = yes)", (compressed > 0 && contact > 0 && extended > 0 && jammed > 0) ? 0 : 1, 0);
  PetscCall(PatchDestroy(&p));
  PetscCall(PetscFree(p.exists));
  PetscCall(PetscFree(p.broken_x));
  PetscCall(PetscFree(p.broken_y));
  PetscFunctionReturn(0);
}

/* ============================ the law's slope and integral ============================ */

/* the test's two laws: warp tabulated (csv, or linear if none), weft linear; both with crimp
   and smoothing blends at their kinks */
static PetscErrorCode LawsSetUp(YarnLaw *warp, YarnLaw *weft, const char *csv)
{
  PetscFunctionBeginUser;
  warp->name = "warp", warp->tex = 20, warp->EA = 52, warp->crimp = 0.08, warp->Ec = 2.6, warp->k_comp = 1e-3;
  warp->e_contact = -0.08, warp->smoothing = 0.004;
  weft->name = "weft", weft->tex = 20, weft->EA = 40, weft->crimp = 0.05, weft->Ec = 3.0, weft->k_comp = 1e-3;
  weft->e_contact = -0.2, weft->smoothing = 0.003;
  PetscCall(PetscStrncpy(warp->csv, csv, sizeof warp->csv));
  PetscCall(YarnLawSetUp(warp, PETSC_COMM_SELF));
  PetscCall(YarnLawSetUp(weft, PETSC_COMM_SELF));
  PetscFunctionReturn(0);
}

/* the law's kinks and blend ends (where dT/de jumps) and the end of its table; returns how many */
static int LawBreaks(const YarnLaw *y, double ends[10])
{
  int n = 0;
  ends[n++] = y->e_contact, ends[n++] = 0.0, ends[n++] = y->crimp;
  for (PetscInt k = 0; k < y->nblend; k++) ends[n++] = y->blend[k].lo, ends[n++] = y->blend[k].hi;
  if (y->ntab) ends[n++] = y->crimp + y->tab_end * (1 + y->crimp);
  return n;
}

/* a strain at least 2h away from every kink and blend end of the law */
static int AwayFromKinks(const YarnLaw *y, double e, double h)
{
  double ends[10];
  int    n = LawBreaks(y, ends);
  for (int k = 0; k < n; k++)
    if (fabs(e - ends[k]) < 2 * h) return 0;
  return 1;
}

/* integral of ChordTension over [a, b]: 5-point Gauss-Legendre on each piece between the law's breaks */
static double GaussIntegral(const YarnLaw *y, double a, double b)
{
  const double xg[5] = {0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640, 0.9061798459386640};
  const double wg[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665, 0.2369268850561891,
                        0.2369268850561891};
  double       ends[10], cuts[12], sum = 0;
  int          n = LawBreaks(y, ends), m = 0;
  cuts[m++] = a;
  for (int k = 0; k < n; k++)
    if (ends[k] > a && ends[k] < b) cuts[m++] = ends[k];
  cuts[m++] = b;
  for (int k = 1; k < m; k++) /* sort */
    for (int q = k; q > 0 && cuts[q] < cuts[q - 1]; q--) {
      double t = cuts[q];
      cuts[q] = cuts[q - 1], cuts[q - 1] = t;
    }
  for (int k = 0; k + 1 < m; k++) {
    const double mid = 0.5 * (cuts[k] + cuts[k + 1]), half = 0.5 * (cuts[k + 1] - cuts[k]);
    for (int g = 0; g < 5; g++) sum += half * wg[g] * ChordTension(y, mid + half * xg[g]);
  }
  return sum;
}

/* over e in [-0.3, 0.3]: d/de ChordEnergy = ChordTension and ChordTensionSlope = dT/de by central
   differences (h 1e-7, away from the kinks), ChordEnergy(0) = 0 and its increments = Gauss
   integrals of T (a jump of the energy anywhere would show), and the energy with the table of
   cell integrals = the energy summing the cells */
static void CheckLaw(const char *name, const YarnLaw *y, const PetscReal *integral)
{
  const double h = 1e-7, de = 0.6 / 4000;
  double       tbig = 0, kbig = 0, eW = 0, eK = 0, eI = 0, eG = 0, prev = -0.3;
  char         what[256];
  for (int q = 0; q <= 4000; q++) {
    const double e = -0.3 + de * q + 1.234567e-5; /* contact, compression, blends, crimp, table, beyond */
    const double T = ChordTension(y, e), dT = ChordTensionSlope(y, e);
    tbig = fmax(tbig, fabs(T)), kbig = fmax(kbig, fabs(dT));
    eG   = fmax(eG, fabs(ChordEnergy(y, integral, e) - ChordEnergy(y, integral, prev) - GaussIntegral(y, prev, e)));
    eI   = fmax(eI, fabs(ChordEnergy(y, integral, e) - ChordEnergy(y, NULL, e)));
    prev = e;
    if (!AwayFromKinks(y, e, h)) continue;
    const double dW = (ChordEnergy(y, integral, e + h) - ChordEnergy(y, integral, e - h)) / (2 * h);
    const double fd = (ChordTension(y, e + h) - ChordTension(y, e - h)) / (2 * h);
    eW = fmax(eW, fabs(dW - T)), eK = fmax(eK, fabs(fd - dT));
  }
  snprintf(what, sizeof what, "%s: d/de ChordEnergy vs ChordTension (h 1e-7), max error / max |T|", name);
  Check(what, eW / tbig, 1e-7);
  snprintf(what, sizeof what, "%s: ChordEnergy increments vs Gauss integrals of T, max error / (max |T| de)", name);
  Check(what, eG / (tbig * de), 1e-8);
  snprintf(what, sizeof what, "%s: ChordEnergy(0)", name);
  Check(what, fabs(ChordEnergy(y, integral, 0.0)), 0.0);
  snprintf(what, sizeof what, "%s: ChordTensionSlope vs dT/de (h 1e-7), max error / max slope", name);
  Check(what, eK / kbig, 1e-6);
  snprintf(what, sizeof what, "%s: ChordEnergy with the cell table vs summing the cells (bits)", name);
  Check(what, eI, 0.0);
}

static PetscErrorCode TestLaw(const char *csv)
{
  YarnLaw       warp = {0}, weft = {0}, sharp = {0};
  unsigned char one = 1;
  Patch   p    = {0};

  PetscFunctionBeginUser;
  PetscCall(LawsSetUp(&warp, &weft, csv));
  p.warp = &warp, p.weft = &weft, p.exists = &one, p.gxm = p.gym = 1;
  PetscCall(PatchSetUp(&p)); /* the warp law's integral table */
  printf("laws: warp %s, %" PetscInt_FMT " blends, EA %.4g N; weft linear, %" PetscInt_FMT " blends\n",
         warp.ntab ? "tabulated" : "linear", warp.nblend, (double)warp.EA, weft.nblend);
  CheckLaw("warp law", &warp, p.yarn_integral[0]);
  CheckLaw("weft law", &weft, NULL);
  sharp = weft, sharp.nblend = 0; /* sharp kinks */
  CheckLaw("linear law with sharp kinks", &sharp, NULL);
  p.exists = NULL;
  PetscCall(PatchDestroy(&p));
  PetscCall(YarnLawDestroy(&warp));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestTable(const char *csv)
{
  YarnLaw           y = {0};
  double            es[64], fs[64], errmax = 0, tmax;
  size_t            n = 0;
  char              line[256];
  FILE             *fp;
  gsl_interp       *sp;
  gsl_interp_accel *acc;

  PetscFunctionBeginUser;
  y.name = "warp", y.crimp = 0.0, y.k_comp = 1e-3, y.e_contact = -0.5, y.tex = 20;
  PetscCall(PetscStrncpy(y.csv, csv, sizeof y.csv));
  PetscCall(YarnLawSetUp(&y, PETSC_COMM_SELF));
  fp = fopen(csv, "r");
  PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot open %s", csv);
  while (fgets(line, sizeof line, fp))
    if (line[0] != '#' && sscanf(line, "%lf,%lf", &es[n], &fs[n]) == 2) {
      es[n] /= 100, fs[n] /= 100;
      n++;
    }
  fclose(fp);
  sp  = gsl_interp_alloc(gsl_interp_steffen, n);
  acc = gsl_interp_accel_alloc();
  gsl_interp_init(sp, es, fs, n);
  tmax = fs[n - 1];
  for (int k = 0; k <= 10000; k++) {
    double e = es[n - 1] * k / 10000.0, d = fabs(YarnTension(&y, e) - gsl_interp_eval(sp, es, fs, e, acc));
    errmax = errmax > d ? errmax : d;
  }
  Check("fast yarn table vs GSL Steffen spline, max error / max tension", errmax / tmax, 1e-6);
  {
    double slope = gsl_interp_eval_deriv(sp, es, fs, es[n - 1], acc), e = es[n - 1] + 0.01;
    Check("linear extension past the table, relative error", fabs(YarnTension(&y, e) - (tmax + slope * 0.01)) / tmax, 1e-9);
  }
  gsl_interp_accel_free(acc);
  gsl_interp_free(sp);
  PetscCall(YarnLawDestroy(&y));
  PetscFunctionReturn(0);
}

static void TestTangent(void)
{
  YarnLaw y = {0};
  y.EA = 52, y.crimp = 0.08, y.Ec = 2.6, y.k_comp = 1e-3, y.e_contact = -0.5, y.break_e = INFINITY;
  Check("tangent in compression window", fabs(ChordTangentMax(&y, -0.2, -0.1) - 52e-3), 1e-12);
  Check("tangent reaching yarn contact", fabs(ChordTangentMax(&y, -0.6, -0.1) - 52), 1e-12);
  Check("chord tension in contact", fabs(ChordTension(&y, -0.6) - (52e-3 * -0.5 + 52 * -0.1)), 1e-12);
  Check("tangent across the crimp start", fabs(ChordTangentMax(&y, -0.01, 0.01) - 2.6), 1e-12);
  Check("tangent across the knee", fabs(ChordTangentMax(&y, 0.07, 0.09) - 52 / 1.08), 1e-12);
  Check("chord tension in extension", fabs(ChordTension(&y, 0.1) - (2.6 * 0.08 + 52 * 0.02 / 1.08)), 1e-12);
}

int main(int argc, char **argv)
{
  char csv[PETSC_MAX_PATH_LEN] = "";

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-csv", csv, sizeof csv, NULL));
  PetscCall(TestForces());
  PetscCall(TestLaw(csv));
  if (csv[0]) PetscCall(TestTable(csv));
  TestTangent();
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
