/* The firefly algorithm's all-pairs sweep (scara_opt.metaheuristics.fa.sweep_all), in C.
 *
 * The same rule and the same random draws as the numpy form, in the same order: for each
 * attractor k from the dimmest to the brightest (rows sorted brightest first), every row
 * i >= first_dimmer[k] moves toward row k's start-of-generation position:
 *     D = xs[k] - x[i];  beta = beta0 exp(-gamma sum_j w_j D_j^2)
 *     x[i] += beta u D + (v - 1/2) step        (u, v: the next draws, u block then v block)
 * for the attractors k_hi down to k_lo (the caller goes through them in blocks, so the draws
 * of one block are all it holds). The random step of the brightest rows is the caller's.
 *
 * n, nq: fireflies, joints; xs (n, nq): sorted start positions; x (n, nq): a copy of xs,
 * moved in place; first_dimmer (n,); w (nq,): 1 / span^2; step (nq,); r: the block's
 * draws, in the order the numpy form takes them. */
#include <math.h>
#include <stdint.h>

void fa_sweep(int64_t n, int64_t nq, int64_t k_hi, int64_t k_lo, const double *xs, double *x,
              const int64_t *first_dimmer, const double *w, double beta0, double gamma,
              const double *step, const double *r)
{
    for (int64_t k = k_hi; k >= k_lo; k--) {
        int64_t s = first_dimmer[k], m = n - s;
        if (m <= 0)
            continue;
        const double *u = r, *v = r + m * nq;
        r += 2 * m * nq;
        for (int64_t i = 0; i < m; i++) {
            double *xi = x + (s + i) * nq, r2 = 0.0;
            for (int64_t j = 0; j < nq; j++) {
                double d = xs[k * nq + j] - xi[j];
                r2 += d * d * w[j];
            }
            double beta = beta0 * exp(-gamma * r2);
            for (int64_t j = 0; j < nq; j++) {
                double d = xs[k * nq + j] - xi[j];
                xi[j] += beta * u[i * nq + j] * d + (v[i * nq + j] - 0.5) * step[j];
            }
        }
    }
}
