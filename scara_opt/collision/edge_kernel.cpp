/* The conservative edge proof of scara_opt.planning.ompl_backend.EdgeProver, in C++.
 *
 * The same rule, the same order of intervals, the same counts as the Python form
 * (EdgeProver._split); only the calls change: coal's distance on our own coal shapes, the
 * robot bodies placed by the compiled casadi Function of their world placements (the chain
 * walk of scara_opt.model.symbolic), no Python between two configurations.
 * edge_kernel.py builds it (once per machine) and checks it against the Python form.
 *
 * Shapes: 0 sphere (r), 1 box (x, y, z full sides), 2 capsule (r, length),
 * 3 cylinder (r, length); nothing else (edge_kernel.py keeps the Python form then).
 */
#include <coal/distance.h>
#include <coal/shape/geometric_shapes.h>

#include <cstring>
#include <deque>
#include <memory>
#include <vector>

typedef long long int casadi_int; /* casadi's default; edge_kernel.py checks the size */
typedef int (*casadi_function)(const double **arg, double **res, casadi_int *iw, double *w,
                               int mem);

namespace {

struct Interval {
    double h, s0;                 /* half its length, its start (fractions of the edge) */
    std::vector<int> pairs;       /* open pairs */
    std::vector<double> d0, d1;   /* their distances at its ends, less the shift */
};

struct Kernel {
    int nq = 0, nmoving = 0;
    casadi_function fk = nullptr;   /* q -> 12 numbers per moving body: R row-major, p */
    std::vector<casadi_int> iw;
    std::vector<double> w, placed, q;
    std::vector<std::shared_ptr<coal::CollisionGeometry>> shapes;
    std::vector<coal::Transform3s> tf;
    std::vector<int> slot;          /* a body's row in the Function's output, or -1: fixed */
    std::vector<int> first, second; /* the pairs' bodies */
    double shift = 0.0;
    /* per pair, as Pinocchio's GeometryData: coal's functor, its request (the GJK guess
     * cached from the pair's last call) and result */
    std::vector<coal::ComputeDistance> functors;
    std::vector<coal::DistanceRequest> requests;
    std::vector<coal::DistanceResult> results;

    void place(const double *config) {
        const double *arg[1] = {config};
        double *res[1] = {placed.data()};
        fk(arg, res, iw.data(), w.data(), 0);
        for (size_t g = 0; g < slot.size(); ++g) {
            if (slot[g] < 0) continue;
            const double *x = &placed[12 * slot[g]];
            coal::Matrix3s R;
            R << x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], x[8];
            tf[g].setRotation(R);
            tf[g].setTranslation(coal::Vec3s(x[9], x[10], x[11]));
        }
    }

    double raw(int k) { /* the pair's signed distance [m] at the placed configuration */
        coal::DistanceResult &result = results[k];
        result.clear();
        functors[k](tf[first[k]], tf[second[k]], requests[k], result);
        return result.min_distance;
    }

    double distance(int k) { return raw(k) - shift; }
};

std::shared_ptr<coal::CollisionGeometry> shape(int type, const double *p) {
    switch (type) {
    case 0: return std::make_shared<coal::Sphere>(p[0]);
    case 1: return std::make_shared<coal::Box>(p[0], p[1], p[2]);
    case 2: return std::make_shared<coal::Capsule>(p[0], p[1]);
    case 3: return std::make_shared<coal::Cylinder>(p[0], p[1]);
    default: return nullptr;
    }
}

/* Whether interval [lo, hi] lies inside pair k's spans apart along a SCARA's axis. */
inline bool apart(const double *spans, int k, double lo, double hi) {
    if (!spans) return false;
    const double *sp = spans + 4 * k;
    return (sp[0] < lo && hi < sp[1]) || (sp[2] < lo && hi < sp[3]);
}

} // namespace

extern "C" {

int edge_kernel_casadi_int_size(void) { return (int)sizeof(casadi_int); }

/* A kernel for nbodies bodies (types, params 3 each, fixed world placements 12 each for
 * slot -1) and npairs pairs; fk: the casadi entry, its work sizes; shift: margin + tol. */
void *edge_kernel_new(int nq, void *fk, int sz_iw, int sz_w, int nmoving, int nbodies,
                      const int *types, const double *params, const double *fixed,
                      const int *slot, int npairs, const int *pairs, double shift) {
    auto *k = new Kernel();
    k->nq = nq;
    k->nmoving = nmoving;
    k->fk = (casadi_function)fk;
    k->iw.assign(sz_iw > 0 ? sz_iw : 1, 0);
    k->w.assign(sz_w > 0 ? sz_w : 1, 0.0);
    k->placed.assign(12 * (nmoving > 0 ? nmoving : 1), 0.0);
    k->q.assign(nq, 0.0);
    k->shift = shift;
    for (int g = 0; g < nbodies; ++g) {
        auto s = shape(types[g], params + 3 * g);
        if (!s) { delete k; return nullptr; }
        k->shapes.push_back(s);
        k->slot.push_back(slot[g]);
        coal::Transform3s t;
        const double *x = fixed + 12 * g;
        coal::Matrix3s R;
        R << x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], x[8];
        t.setRotation(R);
        t.setTranslation(coal::Vec3s(x[9], x[10], x[11]));
        k->tf.push_back(t);
    }
    for (int p = 0; p < npairs; ++p) {
        const int a = pairs[2 * p], b = pairs[2 * p + 1];
        k->first.push_back(a);
        k->second.push_back(b);
        k->functors.emplace_back(k->shapes[a].get(), k->shapes[b].get());
        coal::DistanceRequest request(true);
        request.enable_cached_gjk_guess = true;
        k->requests.push_back(request);
        k->results.emplace_back();
    }
    return k;
}

void edge_kernel_free(void *kernel) { delete (Kernel *)kernel; }

/* Every pair's distance less the shift at configuration q (nq,): out (npairs,). */
void edge_kernel_distances(void *kernel, const double *q, double *out) {
    auto *k = (Kernel *)kernel;
    k->place(q);
    for (size_t p = 0; p < k->first.size(); ++p) out[p] = k->distance((int)p);
}

/* Signed distances [m] of the pairs cols (ncols; NULL: all) at each of the n rows of Q
 * (n, nq): out (n, ncols), as CollisionChecker.pair_distances. */
void edge_kernel_batch(void *kernel, const double *Q, int n, const int *cols, int ncols,
                       double *out) {
    auto *k = (Kernel *)kernel;
    for (int i = 0; i < n; ++i) {
        k->place(Q + (size_t)i * k->nq);
        for (int c = 0; c < ncols; ++c) out[(size_t)i * ncols + c] = k->raw(cols ? cols[c] : c);
    }
}

/* EdgeProver._split: the edge qa -> qb, its open pairs (n of them: indices, bounds M
 * over the whole edge, distances at the ends less the shift, spans 4 each or NULL),
 * resolution [m]. Returns 1 when proven clear, 0 when not; *midpoints counts the
 * configurations computed. */
int edge_kernel_split(void *kernel, const double *qa, const double *qb, int n,
                      const int *open, const double *M, const double *da, const double *db,
                      const double *spans, double resolution, long long *midpoints) {
    auto *k = (Kernel *)kernel;
    const int nq = k->nq;
    double least = M[0];
    for (int i = 1; i < n; ++i) least = M[i] < least ? M[i] : least;
    const double wide = resolution / least;  /* wider intervals do not graze */
    std::deque<Interval> queue;
    queue.push_back({0.5, 0.0, std::vector<int>(n), std::vector<double>(da, da + n),
                     std::vector<double>(db, db + n)});
    for (int i = 0; i < n; ++i) queue.back().pairs[i] = i;
    std::vector<double> dm;
    std::vector<int> next;
    while (!queue.empty()) {
        Interval iv = std::move(queue.front());
        queue.pop_front();
        const double h = iv.h;
        double most = 0.0;
        for (int i : iv.pairs) most = M[i] > most ? M[i] : most;
        if (2 * h < wide && 2 * h * most < resolution) return 0; /* grazing: not proven */
        const double s = iv.s0 + h;
        for (int j = 0; j < nq; ++j) k->q[j] = qa[j] + s * (qb[j] - qa[j]);
        k->place(k->q.data());
        ++*midpoints;
        const size_t m = iv.pairs.size();
        dm.resize(m);
        for (size_t i = 0; i < m; ++i) {
            dm[i] = k->distance(open[iv.pairs[i]]);
            if (dm[i] <= 0) return 0;
        }
        for (int half = 0; half < 2; ++half) {
            const double lo = half ? iv.s0 + h : iv.s0, hi = lo + h;
            const std::vector<double> &dl = half ? dm : iv.d0;
            const std::vector<double> &dh = half ? iv.d1 : dm;
            Interval sub{h / 2, lo, {}, {}, {}};
            for (size_t i = 0; i < m; ++i) {
                const int p = iv.pairs[i];
                if (h * M[p] < dl[i] + dh[i] || apart(spans, p, lo, hi)) continue;
                sub.pairs.push_back(p);
                sub.d0.push_back(dl[i]);
                sub.d1.push_back(dh[i]);
            }
            if (!sub.pairs.empty()) queue.push_back(std::move(sub));
        }
    }
    return 1;
}

} // extern "C"
