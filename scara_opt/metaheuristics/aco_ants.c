/* One generation of ACO_R's ants (scara_opt.metaheuristics.aco.sample_ants), in C.
 *
 * The numpy form's floating-point operations, in its order, so the ants are the same bit
 * for bit (compiled without -ffast-math; x86-64's baseline has no FMA to contract into):
 *   1. per joint j, the archive column sorted by a stable merge sort (numpy's stable
 *      argsort: with ties, the one permutation that keeps equal values in row order; NaN
 *      last), its running sum C (numpy's cumsum: C_0 = v_0, then C_r = C_{r-1} + v_r),
 *      and dev[row of rank r][j] = (2r - (k-1)) v_r - 2 C_r + v_r + C_{k-1}, left to right;
 *   2. per ant i, its guide g = min(#{l : cum[l] <= cum[k-1] u_i}, k-1) (searchsorted,
 *      side='right'), and per joint x = S[g][j] + (xi dev[g][j]) / (k-1) normal[i][j];
 *   3. Problem.repair: a continuous joint wrapped, (x + pi) mod 2pi - pi with numpy's
 *      remainder (fmod, then moved to the divisor's sign); any other reflected, then
 *      clipped: y = max(x, 2 lo - x); y = min(y, 2 hi - y); y = max(y, lo), where max/min
 *      are numpy's maximum/minimum (NaN propagates; of +0 and -0, the second operand).
 *
 * k, nq: archive rows, joints; S (k, nq): the archive; cum (k,): cumulative rank weights;
 * u (k,), normal (k, nq): the draws; lo, hi (nq,): the search box; periodic (nq,): 1 for a
 * continuous joint; ants (k, nq): written. Returns 0, or -1 when out of memory. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.141592653589793;   /* math.pi, the same double */

/* numpy's maximum and minimum: a NaN in either operand is the result; of equals (+0.0 and
 * -0.0) the second operand (numpy 2.x, every array length: tests/test_ga_kernel.py) */
static double max_np(double a, double b) { return (a > b || a != a) ? a : b; }
static double min_np(double a, double b) { return (a < b || a != a) ? a : b; }

/* a sorts strictly before b: the smaller, or a number before a NaN */
static int before(double a, double b) { return a < b || (b != b && a == a); }

/* key[0..n) sorted stably, idx[] moved along; tk, ti: n scratch each. Short runs by
 * insertion, then merges; an element passes another only if strictly before it, so ties keep
 * their row order */
static void merge_sort(double *key, int64_t *idx, double *tk, int64_t *ti, int64_t n)
{
    if (n <= 16) {
        for (int64_t i = 1; i < n; i++) {
            double x = key[i];
            int64_t xi = idx[i], j = i;
            for (; j > 0 && before(x, key[j - 1]); j--) {
                key[j] = key[j - 1];
                idx[j] = idx[j - 1];
            }
            key[j] = x;
            idx[j] = xi;
        }
        return;
    }
    int64_t h = n / 2, i = 0, j = h, o = 0;
    merge_sort(key, idx, tk, ti, h);
    merge_sort(key + h, idx + h, tk, ti, n - h);
    while (i < h && j < n) {
        if (before(key[j], key[i])) {
            tk[o] = key[j];
            ti[o++] = idx[j++];
        } else {
            tk[o] = key[i];
            ti[o++] = idx[i++];
        }
    }
    while (i < h) {
        tk[o] = key[i];
        ti[o++] = idx[i++];
    }
    memcpy(key, tk, o * sizeof *key);   /* the rest of the right half is in place */
    memcpy(idx, ti, o * sizeof *idx);
}

/* Python's (numpy's) float remainder: fmod moved to the sign of b, a zero signed as b */
static double remainder_np(double a, double b)
{
    double m = fmod(a, b);
    if (m != 0.0) {
        if ((b < 0) != (m < 0))
            m += b;
    } else {
        m = copysign(0.0, b);
    }
    return m;
}

int aco_ants(int64_t k, int64_t nq, const double *S, const double *cum, const double *u,
             const double *normal, double xi, const double *lo, const double *hi,
             const uint8_t *periodic, double *ants)
{
    int64_t *idx = malloc(2 * k * sizeof *idx);
    double *buf = malloc((3 * k + k * nq) * sizeof *buf);
    if (idx == NULL || buf == NULL) {
        free(idx);
        free(buf);
        return -1;
    }
    int64_t *ti = idx + k;
    double *v = buf, *tk = buf + k, *C = buf + 2 * k, *dev = buf + 3 * k;
    for (int64_t j = 0; j < nq; j++) {                   /* 1. deviation sums, joint j */
        for (int64_t l = 0; l < k; l++) {
            v[l] = S[l * nq + j];
            idx[l] = l;
        }
        merge_sort(v, idx, tk, ti, k);                   /* v: column j, ascending */
        C[0] = v[0];
        for (int64_t r = 1; r < k; r++)
            C[r] = C[r - 1] + v[r];
        for (int64_t r = 0; r < k; r++) {
            double w = 2.0 * (double)r - (double)(k - 1);
            dev[idx[r] * nq + j] = w * v[r] - 2.0 * C[r] + v[r] + C[k - 1];
        }
    }
    for (int64_t i = 0; i < k; i++) {                    /* 2. guide, then 3. the ant */
        double x = cum[k - 1] * u[i];
        const double *base = cum;                        /* g = #{l : cum[l] <= x}, */
        for (int64_t n = k; n > 1; n -= n / 2)           /* a branch-free bisection */
            base = base[n / 2] <= x ? base + n / 2 : base;
        int64_t g = (base - cum) + (*base <= x);
        g = g < k - 1 ? g : k - 1;
        for (int64_t j = 0; j < nq; j++) {
            double sigma = xi * dev[g * nq + j] / (double)(k - 1);
            double y = S[g * nq + j] + sigma * normal[i * nq + j];
            if (periodic[j]) {
                y = remainder_np(y + PI, 2.0 * PI) - PI;
            } else {
                y = max_np(y, 2.0 * lo[j] - y);
                y = min_np(y, 2.0 * hi[j] - y);
                y = max_np(y, lo[j]);
            }
            ants[i * nq + j] = y;
        }
    }
    free(idx);
    free(buf);
    return 0;
}
