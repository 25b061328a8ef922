/* The GA's children from its draws (scara_opt.metaheuristics.ga_breed.offspring), in C.
 *
 * The same operations as the numpy form (ga_breed.offspring_numpy, then Problem.repair),
 * in the same order, so the same bits: no -ffast-math and no fused multiply-add (none in
 * x86-64's base set; the pragma asks the compilers that honour it), each operation below
 * one IEEE operation as in numpy (tests/test_ga_kernel.py compares the bits). For child i (row i of out):
 *     p1, p2  the winners of tournaments i and n + i (entrants (2, n, t)): the cheapest
 *             entrant, the first of equals, the first NaN if any (numpy's argmin)
 *     w       u_low + u_range * u   (the blend weight U(-g, 1 + g): numpy's uniform)
 *     c       crossed (rc[i] < p_cross) ? (p2 - p1) * w + p1 : p1
 *     c      += (step * (sigma * span)) * mutate  (mutate = rm < p_mut as 0.0 or 1.0,
 *                                                  numpy's bool -> float: -0.0 kept)
 *     repair  (if asked) reflect at lower, at upper, clip at lower, as Problem.repair:
 *             y = max(c, 2 lo - c); y = min(y, 2 hi - y); y = max(y, lo)
 * n, nq: individuals, joints; X (n, nq), f (n,): the population; u, rm, step (n, nq) and
 * rc (n,): the draws; span, lo, hi (nq,); sigma: the mutation step's scale. */
#include <stdint.h>

#pragma STDC FP_CONTRACT OFF

/* numpy's maximum and minimum: a NaN in either operand is the result; of equals (+0.0 and
 * -0.0) the second operand (numpy 2.x, every array length; tests/test_ga_kernel.py). */
static double np_max(double a, double b) { return (a > b || a != a) ? a : b; }
static double np_min(double a, double b) { return (a < b || a != a) ? a : b; }

/* The row of the cheapest of the t entrants e[0..t-1], as argmin picks it. */
static int64_t winner(const int64_t *e, int64_t t, const double *f)
{
    int64_t best = e[0];
    for (int64_t k = 1; k < t && f[best] == f[best]; k++)   /* a NaN wins: stop */
        if (f[e[k]] < f[best] || f[e[k]] != f[e[k]])
            best = e[k];
    return best;
}

/* The kernel's arrays and sizes, set once a solve (ga_breed.Draws.args mirrors it). */
struct ga_args {
    int64_t n, nq, t, repair;
    const double *X, *f;
    const int64_t *entrants;
    const double *u, *rc, *rm, *step, *span, *lo, *hi;
    double *out;
};

void ga_children(const struct ga_args *a, double sigma, double p_cross, double p_mut,
                 double u_low, double u_range)
{
    int64_t n = a->n, nq = a->nq, t = a->t;
    for (int64_t i = 0; i < n; i++) {
        const double *p1 = a->X + winner(a->entrants + i * t, t, a->f) * nq;
        const double *p2 = a->X + winner(a->entrants + (n + i) * t, t, a->f) * nq;
        int crossed = a->rc[i] < p_cross;
        for (int64_t j = 0; j < nq; j++) {
            int64_t ij = i * nq + j;
            double w = u_low + u_range * a->u[ij];
            double c = crossed ? (p2[j] - p1[j]) * w + p1[j] : p1[j];
            double s = a->step[ij] * (sigma * a->span[j]);
            s = s * (double)(a->rm[ij] < p_mut);
            c = c + s;
            if (a->repair) {
                c = np_max(c, 2.0 * a->lo[j] - c);
                c = np_min(c, 2.0 * a->hi[j] - c);
                c = np_max(c, a->lo[j]);
            }
            a->out[ij] = c;
        }
    }
}
