/* The GA's children from its draws (scara_opt.metaheuristics.ga.offspring), in C.
 *
 * The same operations as the numpy form (ga.offspring_numpy, then Problem.repair), in the
 * same order, so the same bits: no -ffast-math, each line below one IEEE operation as in
 * numpy. For child i (row i of out):
 *     p1, p2  the winners of tournaments i and n + i (entrants (2, n, t)): the cheapest
 *             entrant, the first of equals, the first NaN if any (numpy's argmin)
 *     c       crossed (rc[i] < p_cross) ? (p2 - p1) * u + p1 : p1
 *     c      += (step * sigma_span) * mutate      (mutate = rm < p_mut as 0.0 or 1.0,
 *                                                  numpy's bool -> float: -0.0 kept)
 *     repair  (if asked) reflect at lower, at upper, clip at lower, as Problem.repair:
 *             y = max(c, 2 lo - c); y = min(y, 2 hi - y); y = max(y, lo)
 * n, nq: individuals, joints; X (n, nq), f (n,): the population; u, rm, step (n, nq) and
 * rc (n,): the draws; sigma_span, lo, hi (nq,). */
#include <stdint.h>

/* numpy's maximum and minimum: a NaN in either operand is the result. */
static double np_max(double a, double b) { return (a >= b || a != a) ? a : b; }
static double np_min(double a, double b) { return (a <= b || a != a) ? a : b; }

/* The row of the cheapest of the t entrants e[0..t-1], as argmin picks it. */
static int64_t winner(const int64_t *e, int64_t t, const double *f)
{
    int64_t best = e[0];
    for (int64_t k = 1; k < t && f[best] == f[best]; k++)   /* a NaN wins: stop */
        if (f[e[k]] < f[best] || f[e[k]] != f[e[k]])
            best = e[k];
    return best;
}

void ga_children(int64_t n, int64_t nq, int64_t t, const double *X, const double *f,
                 const int64_t *entrants, const double *u, const double *rc, double p_cross,
                 const double *rm, double p_mut, const double *step,
                 const double *sigma_span, int64_t repair, const double *lo,
                 const double *hi, double *out)
{
    for (int64_t i = 0; i < n; i++) {
        const double *p1 = X + winner(entrants + i * t, t, f) * nq;
        const double *p2 = X + winner(entrants + (n + i) * t, t, f) * nq;
        int crossed = rc[i] < p_cross;
        for (int64_t j = 0; j < nq; j++) {
            int64_t ij = i * nq + j;
            double c = crossed ? (p2[j] - p1[j]) * u[ij] + p1[j] : p1[j];
            double s = step[ij] * sigma_span[j];
            s = s * (double)(rm[ij] < p_mut);
            c = c + s;
            if (repair) {
                c = np_max(c, 2.0 * lo[j] - c);
                c = np_min(c, 2.0 * hi[j] - c);
                c = np_max(c, lo[j]);
            }
            out[ij] = c;
        }
    }
}
