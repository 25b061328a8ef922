/* TOPP-RA's two passes over the stage LPs toppra's seidel wrapper builds (toppra_passes.py).

   Stage i (0 <= i <= N) has m rows  a u + b x + c <= 0  (row-major (N+1, m) arrays; rows 0
   and 1 are left for the next set, filled here) and boxes  ulo <= u <= uhi,
   xlo <= x <= xhi.  The next set  lo <= x + 2 delta_i u <= hi  is rows 0 and 1, as in
   toppra's seidelWrapper.solve_stagewise_optim.

   Backward pass: K_i = [min x, max x] over the stage's (u, x), both by eliminating u
   (Fourier-Motzkin: every pair of a row bounding u from above and one bounding it from
   below gives one row in x alone), exact up to round-off where seidel's LP is exact up to
   its tolerances. Forward pass: x fixed, the greatest u, toppra's own 1-D LP (rows with
   |a| <= 1e-10 ignored and x's box not looked at, as cy_solve_lp1d does), with toppra's safeguards (TINY, 0.999,
   0.9999, MAX_TRIES), in its order: the same u from the same sets. */

#include <math.h>

#define LP1D_TINY 1e-10   /* cy_seidel_solverwrapper's TINY (its 1-D LP) */
#define UNBOUNDED 1e8     /* its VAR_MAX: a variable without a box */

/* The x range [*lo, *hi] of stage rows with u eliminated; 0 if empty (or NaN). */
static int x_range(int m, const double *a, const double *b, const double *c,
                   double ulo, double uhi, double xlo, double xhi, double *lo, double *hi) {
    double bl = xlo, bh = xhi;
    /* the u box as two rows: u - uhi <= 0, -u + ulo <= 0 */
    for (int p = -1; p < m; ++p) {
        double ap = p < 0 ? 1.0 : a[p], bp = p < 0 ? 0.0 : b[p], cp = p < 0 ? -uhi : c[p];
        if (!(ap > 0.0)) {
            if (p >= 0 && ap == 0.0) {          /* a row in x alone */
                if (bp > 0.0) { double v = -cp / bp; if (v < bh) bh = v; }
                else if (bp < 0.0) { double v = -cp / bp; if (v > bl) bl = v; }
                else if (cp > 0.0) return 0;
            }
            continue;
        }
        for (int n = -1; n < m; ++n) {
            double an = n < 0 ? -1.0 : a[n], bn = n < 0 ? 0.0 : b[n], cn = n < 0 ? ulo : c[n];
            if (!(an < 0.0)) continue;
            /* u <= -(bp x + cp)/ap and u >= (bn x + cn)/(-an) meet where
               ap (bn x + cn) - an (bp x + cp) <= 0 */
            double B = ap * bn - an * bp, C = ap * cn - an * cp;
            if (B > 0.0) { double v = -C / B; if (v < bh) bh = v; }
            else if (B < 0.0) { double v = -C / B; if (v > bl) bl = v; }
            else if (C > 1e-12 * (fabs(ap * cn) + fabs(an * cp))) return 0;
        }
    }
    *lo = bl;
    *hi = bh;
    return bl <= bh && !isnan(bl) && !isnan(bh);
}

/* Returns 0 (Ok), 1 (uncontrollable) or 2 (the forward pass failed); xs (N+1,) the squared
   path velocities, lower / upper (N+1,) the controllable sets. */
int toppra_passes(int N, int m, double *a, double *b, double *c, const double *ulo,
                  const double *uhi, const double *xlo, const double *xhi, const double *delta,
                  double small, double tiny, int max_tries,
                  double *lower, double *upper, double *xs) {
    lower[N] = upper[N] = 0.0;
    for (int i = N - 1; i >= 0; --i) {
        double *ai = a + (long)i * m, *bi = b + (long)i * m, *ci = c + (long)i * m;
        double d2 = 2.0 * delta[i];
        ai[0] = -d2; bi[0] = -1.0; ci[0] = lower[i + 1];   /* x + 2 delta u >= lower */
        ai[1] = d2;  bi[1] = 1.0;  ci[1] = -upper[i + 1];  /* x + 2 delta u <= upper */
        double lo, hi;
        if (!x_range(m, ai, bi, ci, ulo[i], uhi[i], xlo[i], xhi[i], &lo, &hi)) return 1;
        upper[i] = hi;
        lower[i] = lo > 0.0 ? lo : 0.0;
    }
    if (small < lower[0] || upper[0] + small < 0.0) return 1;
    xs[0] = 0.0;
    int tries = 0;
    for (int i = 0; i < N;) {
        const double *ai = a + (long)i * m, *bi = b + (long)i * m, *ci = c + (long)i * m;
        double x = xs[i], umin = ulo[i], umax = uhi[i];
        for (int k = 0; k < m; ++k) {
            double r = bi[k] * x + ci[k];
            if (ai[k] > LP1D_TINY) { double v = -r / ai[k]; if (v < umax) umax = v; }
            else if (ai[k] < -LP1D_TINY) { double v = -r / ai[k]; if (v > umin) umin = v; }
        }
        if (umin > umax) {  /* infeasible by round-off: lower x[i], as toppra */
            if (tries < max_tries) {
                double t1 = x - tiny, t2 = 0.999 * x;
                xs[i] = t1 > t2 ? t1 : t2;
                ++tries;
                continue;
            }
            return 2;
        }
        tries = 0;
        double next = x + 2.0 * delta[i] * umax;
        double t1 = next - tiny, t2 = 0.9999 * next;
        next = t1 > t2 ? t1 : t2;
        if (next < lower[i + 1]) next = lower[i + 1];
        if (next > upper[i + 1]) next = upper[i + 1];
        xs[i + 1] = next;
        ++i;
    }
    return 0;
}
