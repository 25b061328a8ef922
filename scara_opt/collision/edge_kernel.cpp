/* The collision proofs' inner loops in C++ (scara_opt.collision.edge_kernel says which).
 *
 * Each does what its Python form does, with the same rule, the same order of intervals and
 * the same counts: EdgeProver's states and edges (edge_prover_*, edge_kernel_split),
 * continuous.check_path (edge_kernel_prove_path), the checker's batches of distances and
 * contact tests (edge_kernel_batch, edge_kernel_collides). Only the calls change: coal's
 * functors on our own coal shapes, the robot's bodies placed by the compiled casadi
 * Function of their world placements (the chain walk of scara_opt.model.symbolic), no
 * Python between two configurations. edge_kernel.py builds it (once per machine);
 * tests/test_edge_kernel.py holds it to the Python forms and to Pinocchio.
 *
 * Shapes: 0 sphere (r), 1 box (x, y, z full sides), 2 capsule (r, length),
 * 3 cylinder (r, length), 4 a triangle mesh (edge_kernel_add_mesh: coal's BVH for its
 * exact surface distance, the convex pieces covering it for the proofs' lower bound, its
 * hull and triangles for the inside test of a closed mesh; scara_opt.collision.mesh_bounds
 * gives the argument); nothing else (edge_kernel.py keeps the Python forms then). */
#include <coal/BVH/BVH_model.h>
#include <coal/collision.h>
#include <coal/distance.h>
#include <coal/narrowphase/narrowphase.h>
#include <coal/shape/convex.h>
#include <coal/shape/geometric_shapes.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <vector>

/* hulls farther apart than this (beyond the proofs' shift) [m] are the bound: nearer,
 * the pieces (measured on the UR5's meshes in benchmarks/bench_plan.py) */
const double HULL_NEAR = 0.01;

/* what lower() takes off a convex distance [m]: twice GJK's tolerance */
const double SLACK = 2e-6;

typedef long long int casadi_int; /* casadi's default; edge_kernel.py checks the size */
typedef int (*casadi_function)(const double **arg, double **res, casadi_int *iw, double *w,
                               int mem);

namespace {

struct Interval {
    double h, s0;                 /* half its length, its start (fractions of the edge) */
    std::vector<int> pairs;       /* open pairs */
    std::vector<double> d0, d1;   /* their distances at its ends, less the shift */
};

/* A placement from the 12 numbers edge_kernel.py passes: rotation row by row, translation. */
void set_placement(coal::Transform3s &tf, const double *x) {
    coal::Matrix3s R;
    R << x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], x[8];
    tf.setRotation(R);
    tf.setTranslation(coal::Vec3s(x[9], x[10], x[11]));
}

/* A convex part of a body and the ball holding it (centre in the body's frame, radius). */
struct Part {
    std::shared_ptr<coal::CollisionGeometry> shape;
    double ball[4];
};

/* A pair of nodes of two bodies' trees of hulls, and a lower bound on their distance
 * (measured: their hulls' convex distance; else their parent's, or their balls'). */
struct OpenPair {
    double bound;
    int i, j;
    bool measured;
};

/* A mesh body's tree of hulls, triangles and hull's half-spaces (mesh_bounds.MeshParts). */
struct Mesh {
    std::vector<Part> nodes;      /* depth first, the root (the mesh's hull) first */
    std::vector<int> children;    /* 2 per node; -1: a leaf */
    std::vector<coal::Vec3s> V;
    std::vector<int> T;           /* 3 per triangle */
    std::vector<double> hull;     /* 4 per half-space: n . x + c <= 0 inside */
    bool closed = false;
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
    double shift = 0.0, margin = 0.0;
    int split_hit = -1;             /* the pair that last refused a split's midpoint */
    long long split_pairs = 0;      /* the splits' pair distances at midpoints */
    /* per body: a ball holding it, centre in its own frame and radius (4 numbers); a point
     * of it (3 numbers: a primitive's centre, a mesh's vertex); its mesh or -1 */
    std::vector<double> balls, inner;
    std::vector<int> mesh_of;
    std::vector<Mesh> meshes;
    std::vector<int> ptype;         /* a primitive body's type, and its parameters (3) */
    std::vector<double> prim;
    /* per pair: coal's functor, its request (a fresh GJK start at every call: a warm start
     * carried from an earlier query changes no answer) and result */
    std::vector<coal::ComputeDistance> functors;
    std::vector<coal::DistanceRequest> requests;
    std::vector<coal::DistanceResult> results;
    std::vector<char> meshy;        /* the pair has a mesh */
    /* and for a pair with a mesh, coal's collision test, started afresh */
    std::vector<coal::ComputeCollision> colliders;
    std::vector<coal::CollisionRequest> contact_requests;
    std::vector<coal::CollisionResult> contact_results;
    std::vector<std::vector<Part>> lone; /* a primitive body as its own single part */

    void place(const double *config) {
        const double *arg[1] = {config};
        double *res[1] = {placed.data()};
        fk(arg, res, iw.data(), w.data(), 0);
        for (size_t g = 0; g < slot.size(); ++g)
            if (slot[g] >= 0) set_placement(tf[g], &placed[12 * slot[g]]);
    }

    double raw(int k) { /* coal's signed distance [m] of the pair (a mesh: its surface) */
        coal::DistanceResult &result = results[k];
        result.clear();
        functors[k](tf[first[k]], tf[second[k]], requests[k], result);
        return result.min_distance;
    }

    /* The surface distance of a pair with a mesh, coal's BVH distance, no lower than the
     * deepest the two balls allow (coal returns -DBL_MAX for a capsule lying in a face). */
    double surface(int k) {
        const double d = raw(k);
        const double deepest = -(balls[4 * first[k] + 3] + balls[4 * second[k] + 3]);
        return std::isnan(d) || d < deepest ? deepest : d;
    }

    /* Whether the point x (world) lies inside mesh m placed at t: inside its hull's
     * half-spaces, and a winding number of magnitude > 1/2 over its triangles. */
    bool contains(int m, const coal::Transform3s &t, const coal::Vec3s &x) const {
        const Mesh &mesh = meshes[m];
        const coal::Vec3s p = t.inverseTransform(x);
        for (size_t f = 0; f < mesh.hull.size(); f += 4)
            if (mesh.hull[f] * p[0] + mesh.hull[f + 1] * p[1] + mesh.hull[f + 2] * p[2]
                + mesh.hull[f + 3] > 1e-12) return false;
        double total = 0.0;
        for (size_t i = 0; i < mesh.T.size(); i += 3) {
            const coal::Vec3s a = mesh.V[mesh.T[i]] - p, b = mesh.V[mesh.T[i + 1]] - p,
                              c = mesh.V[mesh.T[i + 2]] - p;
            const double la = a.norm(), lb = b.norm(), lc = c.norm();
            const double num = a.dot(b.cross(c));
            const double den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
            total += 2.0 * std::atan2(num, den);
        }
        return std::abs(total / (4.0 * 3.14159265358979323846)) > 0.5;
    }

    /* Whether one body of the pair lies wholly inside the other, a closed mesh (a body
     * with no point on its surface: one point of it tells). */
    bool inside(int k) const {
        const int a = first[k], b = second[k];
        for (int r = 0; r < 2; ++r) {
            const int outer = r ? a : b, body = r ? b : a;
            const int m = mesh_of[outer];
            if (m < 0 || !meshes[m].closed) continue;
            const double *x = &inner[3 * body];
            if (contains(m, tf[outer], tf[body].transform(coal::Vec3s(x[0], x[1], x[2]))))
                return true;
        }
        return false;
    }

    /* Whether the pair's meshes intersect: coal's collision test (its BVH, stopping at the
     * first pair of triangles that meet). Trusted when it says yes only: it can miss. */
    bool meet(int k) {
        coal::CollisionResult &result = contact_results[k];
        result.clear();
        colliders[k](tf[first[k]], tf[second[k]], contact_requests[k], result);
        return result.isCollision();
    }

    /* The pair's signed distance [m], as reported (CollisionChecker.distances): coal's;
     * with a mesh, its surface distance, 0 where it is positive but coal's collision test
     * finds the surfaces meeting (meet()), and negated when one body lies inside a closed
     * mesh (it is then at least that deep). */
    double exact(int k) {
        if (!meshy[k]) return raw(k);
        const double d = surface(k);
        if (d > 0 && meet(k)) return 0.0;
        return d > 0 && inside(k) ? -d : d;
    }

    /* Node i of body g's tree (a primitive: its one node, itself); its children. */
    const Part &node(int g, int i) const {
        return mesh_of[g] >= 0 ? meshes[mesh_of[g]].nodes[i] : lone[g][0];
    }
    bool leaf(int g, int i) const {
        return mesh_of[g] < 0 || meshes[mesh_of[g]].children[2 * i] < 0;
    }
    int child(int g, int i, int c) const { return meshes[mesh_of[g]].children[2 * i + c]; }

    /* A lower bound [m] on the convex distance of node i of body a and node j of body b:
     * coal's GJK without EPA (overlapping hulls give about 0: the callers take it as
     * "they may meet" and go on to exact tests), stopping early once its separating plane
     * proves the distance above `upper` (then that plane's distance, a lower bound: coal's
     * GJK, check B). To GJK's tolerance, as SLACK allows, from any start: it starts warm
     * (the UR5's table-and-box calls 16 % faster, benchmarks/bench_plan.py). */
    double nodes_apart(int a, int i, int b, int j, double upper) {
        gjk.distance_upper_bound = upper;
        coal::Vec3s p1, p2, normal;
        const Part &x = node(a, i), &y = node(b, j);
        const auto &sa = static_cast<const coal::ShapeBase &>(*x.shape);
        const auto &sb = static_cast<const coal::ShapeBase &>(*y.shape);
        /* GJK's start: the ray between the two balls' centres (in a's frame, as coal's
         * BoundingVolumeGuess), and each hull's walk from its last support vertex */
        const coal::Vec3s ray = tf[a].getRotation().transpose() *
            (tf[a].transform(coal::Vec3s(x.ball[0], x.ball[1], x.ball[2])) -
             tf[b].transform(coal::Vec3s(y.ball[0], y.ball[1], y.ball[2])));
        gjk.cached_guess = ray.squaredNorm() > 0 ? ray : coal::Vec3s(1, 0, 0);
        int &ha = hint(a, i), &hb = hint(b, j);
        gjk.support_func_cached_guess << ha, hb;
        const double d = gjk.shapeDistance(sa, tf[a], sb, tf[b], false, p1, p2, normal);
        ha = gjk.support_func_cached_guess[0];
        hb = gjk.support_func_cached_guess[1];
        return d;
    }

    /* The vertex where node i of body g's last support search ended (its next one's start). */
    int &hint(int g, int i) {
        std::vector<int> &h = hints[g];
        if (h.empty()) h.assign(mesh_of[g] >= 0 ? meshes[mesh_of[g]].nodes.size() : 1, 0);
        return h[i];
    }

    /* A lower bound [m] on the pair's surface distance, by branch and bound down the two
     * trees of hulls (mesh_bounds): a pair of nodes' hull distance bounds every pair of
     * their triangles from below. Best first: the pair of nodes with the least bound is
     * split (the one of larger ball; its children get their parent's bound, or their
     * balls' distance where larger, until measured). It stops with the least bound of the
     * open node pairs when that is a pair of leaves (their exact convex distance: the
     * least over the whole surface's cover), above HULL_NEAR beyond the shift (far enough
     * for any proof), or above `enough`. Less SLACK: GJK's distance of two hulls is exact
     * to its tolerance, 1e-6 m (it came out 6e-8 m above coal's BVH distance). */
    double lower(int k, double enough = std::numeric_limits<double>::infinity()) {
        const int a = first[k], b = second[k];
        const double far = HULL_NEAR + shift;
        auto later = [](const OpenPair &x, const OpenPair &y) { return x.bound > y.bound; };
        heap.clear();
        const double upper = std::min(far, enough);
        const double root = nodes_apart(a, 0, b, 0, upper);
        hulls_meet = root <= SLACK;
        heap.push_back({root, 0, 0, true});
        for (;;) {
            std::pop_heap(heap.begin(), heap.end(), later);
            const OpenPair top = heap.back();
            heap.pop_back();
            if (!top.measured) {
                heap.push_back({std::max(top.bound, nodes_apart(a, top.i, b, top.j, upper)), top.i,
                                top.j, true});
                std::push_heap(heap.begin(), heap.end(), later);
                continue;
            }
            const bool la = leaf(a, top.i), lb = leaf(b, top.j);
            if ((la && lb) || top.bound > far || top.bound > enough) return top.bound - SLACK;
            const bool split_a = !la && (lb || node(a, top.i).ball[3] >= node(b, top.j).ball[3]);
            for (int c = 0; c < 2; ++c) {
                const int i = split_a ? child(a, top.i, c) : top.i;
                const int j = split_a ? top.j : child(b, top.j, c);
                const Part &x = node(a, i), &y = node(b, j);
                const coal::Vec3s cx = tf[a].transform(coal::Vec3s(x.ball[0], x.ball[1], x.ball[2]));
                const coal::Vec3s cy = tf[b].transform(coal::Vec3s(y.ball[0], y.ball[1], y.ball[2]));
                const double balls_gap = (cx - cy).norm() - x.ball[3] - y.ball[3];
                heap.push_back({std::max(top.bound, balls_gap), i, j, false});
                std::push_heap(heap.begin(), heap.end(), later);
            }
        }
    }

    /* What a proof takes as the pair's distance [m] (a lower bound on it, outside a
     * solid): coal's distance; with a mesh, lower() where it is above the shift, the
     * deepest the holding balls allow where the surfaces meet, else the exact surface
     * distance. */
    double bound(int k, double enough = std::numeric_limits<double>::infinity()) {
        if (!meshy[k]) return raw(k);
        const double lb = lower(k, enough);
        if (lb > shift) return lb;
        if (lb <= 0 && meet(k)) /* in contact: no deeper than the two balls allow */
            return -(balls[4 * first[k] + 3] + balls[4 * second[k] + 3]);
        return surface(k);
    }

    /* bound() less the shift; with `need`, a mesh pair's search stops at a bound above it
     * (all a proof asks to drop the pair: any lower bound on the distance is as sound). */
    double distance(int k, double need = std::numeric_limits<double>::infinity()) {
        return bound(k, need + shift + SLACK) - shift;
    }

    /* What a proof takes at a configuration it starts from (a state, a first sample):
     * bound(), and a contact (-1 m) where a body lies inside a closed mesh. */
    double at_rest(int k) {
        const double d = bound(k);
        return meshy[k] && hulls_meet && inside(k) ? std::min(d, 0.0) - 1.0 : d;
    }

    /* A lower bound [m] on the pair's distance at the placed configuration: the distance
     * of the two balls holding its bodies (no coal call). */
    double balls_apart(int k) const {
        const double *ba = &balls[4 * first[k]], *bb = &balls[4 * second[k]];
        const coal::Transform3s &ta = tf[first[k]], &tb = tf[second[k]];
        const coal::Vec3s wa = ta.transform(coal::Vec3s(ba[0], ba[1], ba[2]));
        const coal::Vec3s wb = tb.transform(coal::Vec3s(bb[0], bb[1], bb[2]));
        return (wa - wb).norm() - ba[3] - bb[3];
    }

    bool within(double d) const { return margin > 0 ? d < margin : d <= 0; }

    /* Whether the pair is in contact at the placed configuration: closer than the margin
     * (with none: a signed distance <= 0), decided by exact() itself, in two stages that
     * collides() takes over all pairs in turn: quick() finds a contact by coal's own
     * tests (a primitive pair's distance; meshes that meet), rest() settles the others
     * (a mesh's hull bound farther than the margin, else its surface distance; and no
     * body inside a closed mesh). A pair whose holding balls are farther apart than the
     * margin is free, nor inside one another. */
    bool touching(int k) {
        if (balls_apart(k) > margin) return false;
        return quick(k) || (meshy[k] && rest(k));
    }

    bool quick(int k) { return meshy[k] ? meet(k) : within(raw(k)); }

    bool rest(int k) {
        if (lower(k, margin) > margin) return hulls_meet && inside(k);
        const double d = surface(k);
        return within(d) || (d > 0 && inside(k));
    }

    std::vector<OpenPair> heap;     /* lower()'s open pairs of nodes */
    bool hulls_meet = true;         /* the last lower()'s: the two hulls overlap (only then
                                     * can one body lie inside the other) */
    coal::DistanceRequest part_request;
    coal::GJKSolver gjk;            /* nodes_apart()'s, set from part_request */
    std::vector<std::vector<int>> hints; /* hint(): per body, per node */
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

/* The ball holding a shape, in its own frame: centre (3) and radius (4 numbers). */
void holding_ball(int type, const double *p, double *out) {
    out[0] = out[1] = out[2] = 0.0;
    switch (type) {
    case 0: out[3] = p[0]; break;
    case 1: out[3] = 0.5 * std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]); break;
    case 2: out[3] = p[0] + 0.5 * p[1]; break;
    default: out[3] = std::sqrt(p[0] * p[0] + 0.25 * p[1] * p[1]); break;
    }
}

/* A kernel for nbodies bodies (types, params 3 each, fixed world placements 12 each for
 * slot -1); type 4 a mesh, given by edge_kernel_add_mesh before edge_kernel_pairs. fk: the
 * casadi entry, its work sizes; shift: margin + tol for the proofs, margin: the clearance
 * a contact test asks for [m]. */
void *edge_kernel_new(int nq, void *fk, int sz_iw, int sz_w, int nmoving, int nbodies,
                      const int *types, const double *params, const double *fixed,
                      const int *slot, double shift, double margin) {
    auto *k = new Kernel();
    k->nq = nq;
    k->nmoving = nmoving;
    k->fk = (casadi_function)fk;
    k->iw.assign(sz_iw > 0 ? sz_iw : 1, 0);
    k->w.assign(sz_w > 0 ? sz_w : 1, 0.0);
    k->placed.assign(12 * (nmoving > 0 ? nmoving : 1), 0.0);
    k->q.assign(nq, 0.0);
    k->shift = shift;
    k->margin = margin;
    k->balls.assign(4 * (size_t)nbodies, 0.0);
    k->inner.assign(3 * (size_t)nbodies, 0.0);
    k->mesh_of.assign(nbodies, -1);
    k->lone.resize(nbodies);
    k->ptype.assign(types, types + nbodies);
    k->prim.assign(params, params + 3 * (size_t)nbodies);
    k->part_request.gjk_initial_guess = coal::GJKInitialGuess::CachedGuess;
    k->gjk = coal::GJKSolver(k->part_request);
    k->hints.resize(nbodies);
    for (int g = 0; g < nbodies; ++g) {
        auto s = shape(types[g], params + 3 * g);
        if (!s && types[g] != 4) { delete k; return nullptr; }
        if (s) {
            holding_ball(types[g], params + 3 * g, &k->balls[4 * (size_t)g]);
            k->lone[g].push_back({s, {0.0, 0.0, 0.0, k->balls[4 * (size_t)g + 3]}});
        }
        k->shapes.push_back(s);
        k->slot.push_back(slot[g]);
        k->tf.emplace_back();
        set_placement(k->tf.back(), fixed + 12 * g);
    }
    return k;
}

/* Body g's mesh (mesh_bounds.MeshParts): nv vertices V (3 each), nt triangles T (3 each),
 * nn nodes of its tree of hulls (counts[2 i], counts[2 i + 1]: a node's points and
 * triangles, taken in turn from points (3 each) and tris (3 each, into its own points);
 * children: 2 per node, -1 for a leaf), balls (4 per node), the mesh's ball (4), nh
 * half-spaces of its hull (4 each), closed, a point of it (3). Returns 0 on success. */
int edge_kernel_add_mesh(void *kernel, int g, int nv, const double *V, int nt, const int *T,
                         int nn, const int *counts, const double *points, const int *tris,
                         const int *children, const double *balls, const double *ball, int nh,
                         const double *hull, int closed, const double *point) {
    auto *k = (Kernel *)kernel;
    auto bvh = std::make_shared<coal::BVHModel<coal::OBBRSS>>();
    std::vector<coal::Vec3s> vs(nv);
    for (int i = 0; i < nv; ++i) vs[i] = coal::Vec3s(V[3 * i], V[3 * i + 1], V[3 * i + 2]);
    std::vector<coal::Triangle> ts(nt);
    for (int i = 0; i < nt; ++i)
        ts[i] = coal::Triangle((coal::Triangle::index_type)T[3 * i],
                               (coal::Triangle::index_type)T[3 * i + 1],
                               (coal::Triangle::index_type)T[3 * i + 2]);
    if (bvh->beginModel(nt, nv) != 0 || bvh->addSubModel(vs, ts) != 0 || bvh->endModel() != 0)
        return 1;
    Mesh mesh;
    mesh.V = vs;
    mesh.T.assign(T, T + 3 * (size_t)nt);
    mesh.hull.assign(hull, hull + 4 * (size_t)nh);
    mesh.children.assign(children, children + 2 * (size_t)nn);
    mesh.closed = closed != 0;
    for (int i = 0; i < nn; ++i) {
        const int n_pts = counts[2 * i], n_tri = counts[2 * i + 1];
        auto pts = std::make_shared<std::vector<coal::Vec3s>>(n_pts);
        for (int j = 0; j < n_pts; ++j)
            (*pts)[j] = coal::Vec3s(points[3 * j], points[3 * j + 1], points[3 * j + 2]);
        auto polys = std::make_shared<std::vector<coal::Triangle>>(n_tri);
        for (int j = 0; j < n_tri; ++j)
            (*polys)[j] = coal::Triangle((coal::Triangle::index_type)tris[3 * j],
                                         (coal::Triangle::index_type)tris[3 * j + 1],
                                         (coal::Triangle::index_type)tris[3 * j + 2]);
        Part part;
        part.shape = std::make_shared<coal::Convex<coal::Triangle>>(pts, n_pts, polys, n_tri);
        std::copy(balls + 4 * i, balls + 4 * i + 4, part.ball);
        mesh.nodes.push_back(part);
        points += 3 * (size_t)n_pts;
        tris += 3 * (size_t)n_tri;
    }
    k->shapes[g] = bvh;
    k->mesh_of[g] = (int)k->meshes.size();
    k->meshes.push_back(std::move(mesh));
    std::copy(ball, ball + 4, &k->balls[4 * (size_t)g]);
    std::copy(point, point + 3, &k->inner[3 * (size_t)g]);
    return 0;
}

/* The kernel's npairs pairs (2 bodies each), every body's shape given. */
void edge_kernel_pairs(void *kernel, int npairs, const int *pairs) {
    auto *k = (Kernel *)kernel;
    for (int p = 0; p < npairs; ++p) {
        const int a = pairs[2 * p], b = pairs[2 * p + 1];
        k->first.push_back(a);
        k->second.push_back(b);
        k->functors.emplace_back(k->shapes[a].get(), k->shapes[b].get());
        coal::DistanceRequest request(true);
        request.gjk_initial_guess = coal::GJKInitialGuess::DefaultGuess;
        k->requests.push_back(request);
        k->results.emplace_back();
        k->meshy.push_back(k->mesh_of[a] >= 0 || k->mesh_of[b] >= 0);
        k->colliders.emplace_back(k->shapes[a].get(), k->shapes[b].get());
        coal::CollisionRequest contact(coal::NO_REQUEST, 1);
        contact.gjk_initial_guess = coal::GJKInitialGuess::DefaultGuess;
        k->contact_requests.push_back(contact);
        k->contact_results.emplace_back();
    }
}

void edge_kernel_free(void *kernel) { delete (Kernel *)kernel; }

/* Signed distances [m] of the pairs cols (ncols; NULL: all) at each of the n rows of Q
 * (n, nq): out (n, ncols); kind 1: as reported (Kernel::exact), 0: what a proof takes
 * inside a motion (Kernel::bound), 2: at its start (Kernel::at_rest); all three the same
 * for primitives. */
void edge_kernel_batch(void *kernel, const double *Q, int n, const int *cols, int ncols,
                       int kind, double *out) {
    auto *k = (Kernel *)kernel;
    for (int i = 0; i < n; ++i) {
        k->place(Q + (size_t)i * k->nq);
        for (int c = 0; c < ncols; ++c) {
            const int p = cols ? cols[c] : c;
            out[(size_t)i * ncols + c] = kind == 1 ? k->exact(p)
                                         : kind == 2 ? k->at_rest(p) : k->bound(p);
        }
    }
}

/* Whether any pair is in contact at each of the n rows of Q (n, nq): out (n,), 0 or 1,
 * as CollisionChecker.collides (Kernel::touching, stopping at the first). */
void edge_kernel_collides(void *kernel, const double *Q, int n, unsigned char *out) {
    auto *k = (Kernel *)kernel;
    const int np = (int)k->first.size();
    std::vector<int> near;
    for (int i = 0; i < n; ++i) {
        k->place(Q + (size_t)i * k->nq);
        unsigned char hit = 0;
        near.clear();
        for (int p = 0; p < np && !hit; ++p) {  /* Kernel::touching, quick stage first */
            if (k->balls_apart(p) > k->margin) continue;
            hit = k->quick(p);
            if (k->meshy[p]) near.push_back(p);
        }
        for (size_t r = 0; r < near.size() && !hit; ++r) hit = k->rest(near[r]);
        out[i] = hit;
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
        /* whether the interval's pair i is apart at the midpoint (above h M, the pair
         * leaves both halves: no closer bound is needed); one in contact is remembered */
        auto apart_at = [&](size_t i) {
            dm[i] = k->distance(open[iv.pairs[i]], h * M[iv.pairs[i]]);
            ++k->split_pairs;
            if (dm[i] <= 0) k->split_hit = open[iv.pairs[i]];
            return dm[i] > 0;
        };
        /* the pair that last refused a midpoint first: a midpoint in contact is refused
         * whichever of its pairs is found in contact, so the verdict is the same */
        size_t lead = m;
        for (size_t i = 0; i < m && k->split_hit >= 0; ++i)
            if (open[iv.pairs[i]] == k->split_hit) { lead = i; break; }
        if (lead < m && !apart_at(lead)) return 0;
        for (size_t i = 0; i < m; ++i)
            if (i != lead && !apart_at(i)) return 0;
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

/* continuous.check_path (locate=False) of a piecewise polynomial path q(u): m pieces on
 * breakpoints x (m + 1), coefficients c (order + 1, m, nq) highest power first (scipy's
 * PPoly), V (m, nq) bounds on |q'| per piece, W (npairs, nq) the pairs' weights, A
 * (npairs, nq) with a, b (npairs) a SCARA's height gaps (or NULL), resolution [m],
 * budget (configurations). The same levels, in the same order, as continuous.prove.
 * out: [spare, at, distance, pair, touching, evaluations, pair distances at middles];
 * returns 1 when clear. */
int edge_kernel_prove_path(void *kernel, int m, int order, const double *x, const double *c,
                           const double *V, const double *W, const double *A, const double *ga,
                           const double *gb, double resolution, long long budget,
                           double *out) {
    auto *k = (Kernel *)kernel;
    const int nq = k->nq, np = (int)k->first.size();
    const double inf = std::numeric_limits<double>::infinity();
    auto eval = [&](int piece, double u, double *q) { /* scipy's evaluate_poly1 */
        const double s = u - x[piece];
        for (int j = 0; j < nq; ++j) {
            double res = 0.0, z = 1.0;
            for (int kp = 0; kp <= order; ++kp) {
                res = res + c[((size_t)(order - kp) * m + piece) * nq + j] * z;
                if (kp < order) z *= s;
            }
            q[j] = res;
        }
    };
    long long computed = 0; /* pair distances at middles */
    auto contact = [&](double at, const double *d, int touching, long long evals) {
        int best = 0;
        for (int p = 1; p < np; ++p) if (d[p] < d[best]) best = p;
        out[0] = -inf; out[1] = at; out[2] = d[best] + k->shift; out[3] = best;
        out[4] = touching; out[5] = (double)evals; out[6] = (double)computed;
        return 0;
    };
    /* the first samples: the breakpoints (the last on the last piece) */
    std::vector<double> lo, hi, Dlo, Dhi, Qlo, Qhi, Q(nq * (m + 1)), D(np * (m + 1));
    std::vector<int> piece;
    for (int i = 0; i <= m; ++i) {
        eval(i < m ? i : m - 1, x[i], &Q[(size_t)i * nq]);
        k->place(&Q[(size_t)i * nq]);
        for (int p = 0; p < np; ++p) D[(size_t)i * np + p] = k->at_rest(p) - k->shift;
    }
    for (int i = 0; i <= m; ++i)
        for (int p = 0; p < np; ++p)
            if (D[(size_t)i * np + p] <= 0) return contact(x[i], &D[(size_t)i * np], 1, 0);
    for (int i = 0; i < m; ++i) {
        lo.push_back(x[i]); hi.push_back(x[i + 1]); piece.push_back(i);
        Dlo.insert(Dlo.end(), &D[(size_t)i * np], &D[(size_t)(i + 1) * np]);
        Dhi.insert(Dhi.end(), &D[(size_t)(i + 1) * np], &D[(size_t)(i + 2) * np]);
        Qlo.insert(Qlo.end(), &Q[(size_t)i * nq], &Q[(size_t)(i + 1) * nq]);
        Qhi.insert(Qhi.end(), &Q[(size_t)(i + 1) * nq], &Q[(size_t)(i + 2) * nq]);
    }
    double spare = inf;
    long long evals = 0;
    std::vector<double> M, fine, half(nq), box_lo(nq), box_hi(nq), Dm;
    std::vector<char> passed;
    std::vector<int> rest;
    while (!lo.empty()) {
        const size_t n = lo.size();
        M.assign(n * np, 0.0);
        fine.assign(n * np, 0.0);
        passed.assign(n * np, 0);
        rest.clear();
        for (size_t r = 0; r < n; ++r) {
            const double *v = V + (size_t)piece[r] * nq;
            const double w = hi[r] - lo[r];
            if (A) {
                for (int j = 0; j < nq; ++j) {
                    half[j] = v[j] * (w / 2);
                    const double mid = (Qlo[r * nq + j] + Qhi[r * nq + j]) / 2;
                    box_lo[j] = mid - half[j];
                    box_hi[j] = mid + half[j];
                }
            }
            bool ok = true;
            for (int p = 0; p < np; ++p) {
                double speed = 0.0;
                for (int j = 0; j < nq; ++j) speed += v[j] * W[(size_t)p * nq + j];
                const double bound = w * speed;
                const double d0 = Dlo[r * np + p], d1 = Dhi[r * np + p];
                double f = (d0 > 0 && d1 > 0) ? (d0 + d1 - bound) / 2 : -inf;
                if (A) {
                    double low = 0.0, high = 0.0;
                    for (int j = 0; j < nq; ++j) {
                        const double a = A[(size_t)p * nq + j];
                        low += a > 0 ? a * box_lo[j] : a * box_hi[j];
                        high += a > 0 ? a * box_hi[j] : a * box_lo[j];
                    }
                    const double g = std::max(low + ga[p], gb[p] - high) - k->shift;
                    f = std::max(f, g);
                }
                M[r * np + p] = bound;
                fine[r * np + p] = f;
                passed[r * np + p] = f > 0;
                ok = ok && f > 0;
                if (f > 0) spare = std::min(spare, f);
            }
            if (!ok) rest.push_back((int)r);
        }
        if (rest.empty()) break;
        int graze = -1;
        for (int r : rest) {
            double most = 0.0;
            for (int p = 0; p < np; ++p)
                if (!passed[r * np + p]) most = std::max(most, M[r * np + p]);
            if (most < resolution && (graze < 0 || lo[r] < lo[graze])) graze = r;
        }
        if (graze >= 0 || evals + (long long)rest.size() > budget) {
            const int r = graze >= 0 ? graze : rest[0];
            std::vector<double> d(np);
            for (int p = 0; p < np; ++p) d[p] = std::min(Dlo[r * np + p], Dhi[r * np + p]);
            return contact(lo[r], d.data(), 0, evals);
        }
        const size_t nr = rest.size();
        std::vector<double> mids(nr), Qm(nr * nq);
        Dm.assign(nr * np, inf);
        int hit = -1;
        for (size_t i = 0; i < nr; ++i) {
            const int r = rest[i];
            mids[i] = (lo[r] + hi[r]) / 2;
            eval(piece[r], mids[i], &Qm[i * nq]);
            k->place(&Qm[i * nq]);
            for (int p = 0; p < np; ++p) {
                if (passed[r * np + p]) continue;  /* proven on the interval: inf */
                Dm[i * np + p] = k->bound(p) - k->shift;
                ++computed;
                if (Dm[i * np + p] <= 0 && (hit < 0 || mids[i] < mids[hit])) hit = (int)i;
            }
        }
        evals += (long long)nr;
        if (hit >= 0) return contact(mids[hit], &Dm[(size_t)hit * np], 1, evals);
        std::vector<double> lo2, hi2, Dlo2, Dhi2, Qlo2, Qhi2;
        std::vector<int> piece2;
        for (int half_ = 0; half_ < 2; ++half_)
            for (size_t i = 0; i < nr; ++i) {
                const int r = rest[i];
                piece2.push_back(piece[r]);
                lo2.push_back(half_ ? mids[i] : lo[r]);
                hi2.push_back(half_ ? hi[r] : mids[i]);
                const double *dl = half_ ? &Dm[i * np] : &Dlo[r * np];
                const double *dh = half_ ? &Dhi[r * np] : &Dm[i * np];
                Dlo2.insert(Dlo2.end(), dl, dl + np);
                Dhi2.insert(Dhi2.end(), dh, dh + np);
                const double *ql = half_ ? &Qm[i * nq] : &Qlo[r * nq];
                const double *qh = half_ ? &Qhi[r * nq] : &Qm[i * nq];
                Qlo2.insert(Qlo2.end(), ql, ql + nq);
                Qhi2.insert(Qhi2.end(), qh, qh + nq);
            }
        lo.swap(lo2); hi.swap(hi2); Dlo.swap(Dlo2); Dhi.swap(Dhi2);
        Qlo.swap(Qlo2); Qhi.swap(Qhi2); piece.swap(piece2);
    }
    out[0] = spare + k->shift; out[1] = 0; out[2] = 0; out[3] = -1; out[4] = 0;
    out[5] = (double)evals;
    out[6] = (double)computed;
    return 1;
}

} // extern "C"

/* ------------------------------------------------------------------ EdgeProver.edge
 * One planning query's prover on a kernel: the states' distances (less the shift) and a
 * SCARA's gaps above and below each pair along its axis, cached per configuration, and
 * EdgeProver.edge's rule from the two ends before the split. */
namespace {

struct State {
    std::vector<double> d, up, down;
    std::vector<char> known;        /* the pairs whose distance d holds */
    double least;
};

struct Prover {
    Kernel *k;
    int nq, np;
    std::vector<double> W, A, a, b; /* weights; gaps (A empty: none), a and b less the shift */
    std::map<std::vector<double>, State> cache;
    long long states = 0, midpoints = 0, pairs = 0; /* pairs: the states' pair distances */
    std::vector<int> order;         /* the pairs in the order a state computes them: the
                                     * last one found in contact first */

    /* The state's distances as the proofs take them (and no body inside a solid), pair by
     * pair in `order`; unless `all`, it stops at the first pair in contact: the state is
     * then refused whatever the others' distances (its `least` is <= 0 either way). */
    void fill(State &s, const double *q, bool all) {
        k->place(q);
        for (int i = 0; i < np; ++i) {
            const int p = order[i];
            if (s.known[p]) continue;
            s.d[p] = k->at_rest(p) - k->shift;
            s.known[p] = 1;
            ++pairs;
            s.least = std::min(s.least, s.d[p]);
            if (s.d[p] <= 0 && !all) {
                std::rotate(order.begin(), order.begin() + i, order.begin() + i + 1);
                return;
            }
        }
    }

    const State &state(const double *q, bool all = false) {
        std::vector<double> key(q, q + nq);
        auto it = cache.find(key);
        if (it != cache.end()) {
            const std::vector<char> &known = it->second.known;
            if (all && std::find(known.begin(), known.end(), 0) != known.end())
                fill(it->second, q, true);  /* a refused state completed */
            return it->second;
        }
        State s;
        s.d.assign(np, std::numeric_limits<double>::quiet_NaN());
        s.known.assign(np, 0);
        s.least = std::numeric_limits<double>::infinity();
        fill(s, q, all);
        if (!A.empty()) {
            s.up.resize(np);
            s.down.resize(np);
            for (int p = 0; p < np; ++p) {
                double h = 0.0;
                for (int j = 0; j < nq; ++j) h += A[(size_t)p * nq + j] * q[j];
                s.up[p] = h + a[p];
                s.down[p] = b[p] - h;
            }
        }
        ++states;
        return cache.emplace(std::move(key), std::move(s)).first->second;
    }
};

/* the open span of s where (1 - s) ga + s gb > 0 (inf, -inf: none): ompl_backend._positive */
inline void positive(double ga, double gb, double *lo, double *hi) {
    const double inf = std::numeric_limits<double>::infinity();
    if (ga > 0 && gb > 0) { *lo = -inf; *hi = inf; }
    else if (ga > 0) { *lo = -inf; *hi = ga / (ga - gb); }
    else if (gb > 0) { *lo = ga / (ga - gb); *hi = inf; }
    else { *lo = inf; *hi = -inf; }
}

} // namespace

extern "C" {

/* A prover on the kernel: W (npairs, nq) the pairs' weights, A (npairs, nq) with a, b
 * (npairs) a SCARA's height gaps less the shift (A NULL: none). */
void *edge_prover_new(void *kernel, const double *W, const double *A, const double *a,
                      const double *b) {
    auto *k = (Kernel *)kernel;
    auto *p = new Prover();
    p->k = k;
    p->nq = k->nq;
    p->np = (int)k->first.size();
    p->order.resize(p->np);
    for (int i = 0; i < p->np; ++i) p->order[i] = i;
    p->W.assign(W, W + (size_t)p->np * p->nq);
    if (A) {
        p->A.assign(A, A + (size_t)p->np * p->nq);
        p->a.assign(a, a + p->np);
        p->b.assign(b, b + p->np);
    }
    return p;
}

void edge_prover_free(void *prover) { delete (Prover *)prover; }

/* The state's distances less the shift into out (npairs,; or NULL: a state in contact
 * may stop at its first pair in contact); returns whether all are > 0. counts: [states,
 * midpoints, pair distances of states, of the kernel's midpoints] so far. */
int edge_prover_state(void *prover, const double *q, double *out, long long *counts) {
    auto *p = (Prover *)prover;
    const State &s = p->state(q, out != nullptr);
    if (out) std::copy(s.d.begin(), s.d.end(), out);
    counts[0] = p->states;
    counts[1] = p->midpoints;
    counts[2] = p->pairs;
    counts[3] = p->k->split_pairs;
    return s.least > 0 || p->np == 0;
}

/* EdgeProver.edge (without its memory of proven edges): 1 proven clear, 0 not; a start
 * in contact refuses it before its end is computed. counts: as edge_prover_state's. */
int edge_prover_edge(void *prover, const double *qa, const double *qb, double resolution,
                     long long *counts) {
    auto *p = (Prover *)prover;
    const int nq = p->nq, np = p->np;
    const State &sa = p->state(qa);
    int ok = !np || sa.least > 0;
    const State &sb = ok ? p->state(qb) : sa; /* (a refused start: the end is not needed) */
    if (np && sb.least <= 0) ok = 0;
    if (ok && np) {
        std::vector<int> open;
        std::vector<double> M(np), Ms, da, db, spans;
        for (int k = 0; k < np; ++k) {
            double m = 0.0;
            for (int j = 0; j < nq; ++j) m += p->W[(size_t)k * nq + j] * std::abs(qb[j] - qa[j]);
            M[k] = m;
            if (m < sa.d[k] + sb.d[k]) continue;
            if (!p->A.empty() && ((sa.up[k] > 0 && sb.up[k] > 0) ||
                                  (sa.down[k] > 0 && sb.down[k] > 0)))
                continue; /* apart along the axis at both ends: all along (affine) */
            open.push_back(k);
        }
        if (!open.empty()) {
            const int n = (int)open.size();
            for (int k : open) {
                Ms.push_back(M[k]);
                da.push_back(sa.d[k]);
                db.push_back(sb.d[k]);
                if (!p->A.empty()) {
                    double s[4];
                    positive(sa.up[k], sb.up[k], &s[0], &s[1]);
                    positive(sa.down[k], sb.down[k], &s[2], &s[3]);
                    spans.insert(spans.end(), s, s + 4);
                }
            }
            long long mids = 0;
            ok = edge_kernel_split(p->k, qa, qb, n, open.data(), Ms.data(), da.data(), db.data(),
                                   p->A.empty() ? nullptr : spans.data(), resolution, &mids);
            p->midpoints += mids;
        }
    }
    counts[0] = p->states;
    counts[1] = p->midpoints;
    counts[2] = p->pairs;
    counts[3] = p->k->split_pairs;
    return ok;
}

} // extern "C"
