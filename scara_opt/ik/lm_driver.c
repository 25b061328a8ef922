/* One start of the fast IK solver's three phases (scara_opt.ik.lm_run.Run.start), in C.
 *
 * The Python loop of Run calls the compiled casadi iterations a few times a start, and
 * its own work between the calls (reading outputs, the stop rules, the counts) costs about
 * as much as the iterations themselves on a 6- or 7-joint arm. This file is that loop,
 * line for line, calling the same compiled Functions (their C entry points, taken from
 * the libraries scara_opt.model.compiled keeps) on the same arrays: the same iterates,
 * counts and history, bit for bit (tests/test_lm_driver.py compares them).
 *
 *   descend       phase 1 (and 3): lm_step calls until converged, stalled or out of budget
 *   slide_toward  phase 2: the Newton step alone, the full candidate set where it was
 *                 refused while the pull toward q0 remains, until the step is tiny
 *   lm_start      the three phases from one start (phase 1 alone where run->nearest is
 *                 0); the state (budget, counts, best, the history) lives in struct lm_run
 *                 across the starts of a solve
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#pragma STDC FP_CONTRACT OFF

typedef long long int casadi_int;   /* casadi's default; lm_driver.py checks the size */
typedef int (*casadi_function)(const double **arg, double **res, casadi_int *iw, double *w,
                               int mem);

/* One compiled Function with its argument and work arrays (made once a thread, by
 * lm_driver.Phase), and the arrays of its named inputs and outputs. */
struct lm_phase {
    casadi_function f;
    const double **arg;
    double **res;
    casadi_int *iw;
    double *w;
    double *q, *lam;                   /* inputs written here (lam: lm_step only) */
    const double *q_next, *lam_next;   /* outputs read here (lam_next: lm_step only) */
    const double *e_next, *step, *extra;   /* extra: "slide" of lm_step, "pull" of a slide */
    int64_t iterations, evaluations;   /* what one call counts (lm.ITERATIONS, lm.EVALS) */
};

/* A solve's constants (lm's module constants) and its state across starts. */
struct lm_run {
    struct lm_phase lm, newton, slide;
    int64_t nq, stall_calls;
    double lambda0, lambda_max, step_tol, slide_tol, stall_decrease;
    double e_tol;
    int64_t nearest;                   /* 0: no slide (lm's nearest=False) */
    int64_t budget, iterations, evaluations, slide_needed;
    double best;
    double *history;                   /* sqrt(best) after each call */
    int64_t n_history, history_size;
};

/* Evaluate p and count it as Run._count does; 0, or < 0 on an error. */
static int call(struct lm_run *run, struct lm_phase *p)
{
    double e;

    if (p->f(p->arg, p->res, p->iw, p->w, 0) != 0)
        return -1;
    e = *p->e_next;
    run->iterations += p->iterations;
    run->budget -= p->iterations;
    run->evaluations += p->evaluations;
    if (e < run->best)
        run->best = e;
    if (run->n_history == run->history_size)
        return -2;
    run->history[run->n_history++] = sqrt(run->best);
    return 0;
}

/* Phase 1 (and 3) from q (overwritten): *e = |r|^2; returns 1 converged, 0 not, < 0 error. */
static int descend(struct lm_run *run, double *q, double *e)
{
    struct lm_phase *f = &run->lm;
    double prev = INFINITY, step, lam;
    int64_t stall = 0;
    int status;

    memcpy(f->q, q, run->nq * sizeof(double));
    *f->lam = run->lambda0;
    *e = INFINITY;
    while (run->budget > 0) {
        if ((status = call(run, f)) != 0)
            return status;
        *e = *f->e_next;
        step = *f->step;
        lam = *f->lam_next;
        memcpy(f->q, f->q_next, run->nq * sizeof(double));
        *f->lam = lam;
        if (*e <= run->e_tol && step <= run->step_tol) {
            run->slide_needed = *f->extra > run->slide_tol;
            memcpy(q, f->q, run->nq * sizeof(double));
            return 1;
        }
        stall = *e >= (1 - run->stall_decrease) * prev ? stall + 1 : 0;
        if (*e < prev)
            prev = *e;
        if (stall >= run->stall_calls || lam >= run->lambda_max)
            break;
    }
    memcpy(q, f->q, run->nq * sizeof(double));
    return *e <= run->e_tol;
}

/* Phase 2 from the solution q (overwritten); returns 1 if it moved, 0 if not, < 0 error. */
static int slide_toward(struct lm_run *run, double *q)
{
    struct lm_phase *f;
    int moved = 0, status;
    double step;

    while (run->budget > 0) {
        f = &run->newton;
        memcpy(f->q, q, run->nq * sizeof(double));
        if ((status = call(run, f)) != 0)
            return status;
        if (*f->step == 0 && *f->extra > run->slide_tol) {
            f = &run->slide;
            memcpy(f->q, q, run->nq * sizeof(double));
            if ((status = call(run, f)) != 0)
                return status;
        }
        step = *f->step;
        memcpy(q, f->q_next, run->nq * sizeof(double));
        moved = moved || step > 0;
        if (step <= run->slide_tol)
            break;
    }
    return moved;
}

/* All three phases from q (the start; overwritten by the result): 0, or < 0 on an error
 * (-1 a Function failed, -2 the history is full). *e: |r|^2 at the result. */
int lm_start(struct lm_run *run, double *q, double *e)
{
    double slid[64], polished[64], e_p;   /* nq <= 64: lm_driver.py checks */
    int converged, moved, ok;

    if ((converged = descend(run, q, e)) < 0)
        return converged;
    if (!(converged && run->nearest && run->slide_needed))
        return 0;
    memcpy(slid, q, run->nq * sizeof(double));
    if ((moved = slide_toward(run, slid)) < 0)
        return moved;
    if (moved) {
        memcpy(polished, slid, run->nq * sizeof(double));
        if ((ok = descend(run, polished, &e_p)) < 0)
            return ok;
        if (ok) {
            memcpy(q, polished, run->nq * sizeof(double));
            *e = e_p;
        }
    }
    return 0;
}
