#include "usdksl/narrow_phase/shared_vertex_clearance.hpp"

#include "usdksl/narrow_phase/pair_clearance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace usdksl {
namespace {

/// Box diagonal (scene units) of both triangles at both ends of a linear
/// step: no larger than the pair's at any time during it.
double swept_diagonal(const std::array<Vec3, 3>& a0, const std::array<Vec3, 3>& a1, const std::array<Vec3, 3>& b0,
                      const std::array<Vec3, 3>& b1) {
    Vec3 lo = a0[0], hi = a0[0];
    for (const std::array<Vec3, 3>* t : {&a0, &a1, &b0, &b1}) {
        for (const Vec3& p : *t) {
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        }
    }
    return (hi - lo).norm();
}

bool holds_vertex(const Triangle& ids, int32_t v) { return ids[0] == v || ids[1] == v || ids[2] == v; }

/// Every point of `y` lies more than `reach` beyond every point of `x` along
/// the direction from x's centroid to y's (taken halfway through the step),
/// at both ends of the step: their convex hulls then stay that far apart
/// throughout, the heights' differences being linear over a linear step.
/// `x0`, `x1`: the x points at the step's ends (`count_x` of them), likewise y.
bool centroids_apart(const Vec3* x0, const Vec3* x1, int count_x, const Vec3* y0, const Vec3* y1, int count_y,
                     double reach) {
    Vec3 direction = Vec3::Zero();
    for (int i = 0; i < count_y; ++i) direction += (y0[i] + y1[i]) / count_y;
    for (int i = 0; i < count_x; ++i) direction -= (x0[i] + x1[i]) / count_x;
    const double least = reach * direction.norm();
    if (!(least > 0.0) || !std::isfinite(least)) return false;
    for (int end = 0; end < 2; ++end) {
        const Vec3* x = end == 0 ? x0 : x1;
        const Vec3* y = end == 0 ? y0 : y1;
        double highest_x = -std::numeric_limits<double>::infinity();
        double lowest_y = std::numeric_limits<double>::infinity();
        for (int i = 0; i < count_x; ++i) highest_x = std::max(highest_x, direction.dot(x[i]));
        for (int i = 0; i < count_y; ++i) lowest_y = std::min(lowest_y, direction.dot(y[i]));
        // Negated: a NaN never holds.
        if (!(lowest_y - highest_x > least)) return false;
    }
    return true;
}

} // namespace

void SharedVertexClearance::start(const Triangle& ids_a, const std::array<Vec3, 3>& a, const Triangle& ids_b,
                                  const std::array<Vec3, 3>& b) {
    drift_limit_ = -1.0;
    normal_[0] = normal_[1] = normal_[2] = 0.0f;
    plane_possible_ = false;
    shared_a_ = shared_b_ = -1;
    int shared = 0;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (ids_a[i] != ids_b[j]) continue;
            ++shared;
            if (shared_a_ < 0) {
                shared_a_ = static_cast<int8_t>(i);
                shared_b_ = static_cast<int8_t>(j);
            }
        }
    }
    if (shared_a_ < 0) return;  // not a vertex-sharing pair: the proof never holds
    plane_possible_ = shared == 1;
    const Vec3& reference = a[shared_a_];
    offsets_ = {a[(shared_a_ + 1) % 3] - reference, a[(shared_a_ + 2) % 3] - reference,
                b[(shared_b_ + 1) % 3] - reference, b[(shared_b_ + 2) % 3] - reference};
    drift_limit_ = std::numeric_limits<double>::quiet_NaN();
}

bool SharedVertexClearance::plane_holds(const Vec3& normal, const std::array<Vec3, 3>& a0,
                                        const std::array<Vec3, 3>& a1, const std::array<Vec3, 3>& b0,
                                        const std::array<Vec3, 3>& b1, double reach) const {
    // Heights are normal . (p - shared vertex); the distance is the height over |normal|.
    const double least = reach * normal.norm();
    if (!(least > 0.0) || !std::isfinite(least)) return false;
    for (int end = 0; end < 2; ++end) {
        const std::array<Vec3, 3>& a = end == 0 ? a0 : a1;
        const std::array<Vec3, 3>& b = end == 0 ? b0 : b1;
        const Vec3& shared = a[shared_a_];
        // Negated comparisons: a NaN never holds.
        if (!(normal.dot(a[(shared_a_ + 1) % 3] - shared) < -least) ||
            !(normal.dot(a[(shared_a_ + 2) % 3] - shared) < -least) ||
            !(normal.dot(b[(shared_b_ + 1) % 3] - shared) > least) ||
            !(normal.dot(b[(shared_b_ + 2) % 3] - shared) > least))
            return false;
    }
    return true;
}

Vec3 SharedVertexClearance::fitted_normal(const std::array<Vec3, 3>& a0, const std::array<Vec3, 3>& a1,
                                          const std::array<Vec3, 3>& b0, const std::array<Vec3, 3>& b1) const {
    // Across the two triangles' corners at the shared vertex, halfway through
    // the step: from the mean direction of A's edges out of it to B's.
    const auto direction = [](const Vec3& v) {
        const double length = v.norm();
        return length > 0.0 ? Vec3(v / length) : Vec3(Vec3::Zero());
    };
    const auto middle = [&](const std::array<Vec3, 3>& t0, const std::array<Vec3, 3>& t1, int shared, int i) {
        return direction((t0[(shared + i) % 3] - t0[shared]) + (t1[(shared + i) % 3] - t1[shared]));
    };
    return direction(middle(b0, b1, shared_b_, 1) + middle(b0, b1, shared_b_, 2)) -
           direction(middle(a0, a1, shared_a_, 1) + middle(a0, a1, shared_a_, 2));
}

bool SharedVertexClearance::primitives_apart(const Triangle& ids_a, const std::array<Vec3, 3>& a0,
                                             const std::array<Vec3, 3>& a1, const Triangle& ids_b,
                                             const std::array<Vec3, 3>& b0, const std::array<Vec3, 3>& b1,
                                             double reach) {
    // The primitive pairs the narrow phase tests for two triangles of one mesh, as triangle_pair_ccd takes them.
    for (int i = 0; i < 3; ++i) {
        if (!holds_vertex(ids_b, ids_a[i]) && !centroids_apart(&a0[i], &a1[i], 1, b0.data(), b1.data(), 3, reach))
            return false;
        if (!holds_vertex(ids_a, ids_b[i]) && !centroids_apart(&b0[i], &b1[i], 1, a0.data(), a1.data(), 3, reach))
            return false;
    }
    for (int i = 0; i < 3; ++i) {
        const int i1 = (i + 1) % 3;
        for (int j = 0; j < 3; ++j) {
            const int j1 = (j + 1) % 3;
            const int32_t ends_b[2] = {ids_b[j], ids_b[j1]};
            if (ends_b[0] == ids_a[i] || ends_b[0] == ids_a[i1] || ends_b[1] == ids_a[i] || ends_b[1] == ids_a[i1])
                continue;
            const Vec3 edge_a0[2] = {a0[i], a0[i1]}, edge_a1[2] = {a1[i], a1[i1]};
            const Vec3 edge_b0[2] = {b0[j], b0[j1]}, edge_b1[2] = {b1[j], b1[j1]};
            if (!centroids_apart(edge_a0, edge_a1, 2, edge_b0, edge_b1, 2, reach)) return false;
        }
    }
    return true;
}

double SharedVertexClearance::drift(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) const {
    // The shared vertex is one point of both triangles: its position in b is the same as in a.
    const Vec3& reference = a[shared_a_];
    const double squared_a = std::max((a[(shared_a_ + 1) % 3] - reference - offsets_[0]).squaredNorm(),
                                      (a[(shared_a_ + 2) % 3] - reference - offsets_[1]).squaredNorm());
    const double squared_b = std::max((b[(shared_b_ + 1) % 3] - reference - offsets_[2]).squaredNorm(),
                                      (b[(shared_b_ + 2) % 3] - reference - offsets_[3]).squaredNorm());
    return std::sqrt(squared_a) + std::sqrt(squared_b);
}

void SharedVertexClearance::measure_drift_limit(const Triangle& ids_a, const Triangle& ids_b,
                                                const SharedVertexReach& reach) {
    // The start positions less the shared vertex's: distances do not change with a translation.
    std::array<Vec3, 3> a, b;
    a[shared_a_] = Vec3::Zero();
    a[(shared_a_ + 1) % 3] = offsets_[0];
    a[(shared_a_ + 2) % 3] = offsets_[1];
    b[shared_b_] = Vec3::Zero();
    b[(shared_b_ + 1) % 3] = offsets_[2];
    b[(shared_b_ + 2) % 3] = offsets_[3];
    // PairClearance's drift proof holds while distance - drift > reach(drift),
    // reach growing by the size fraction times the drift growth: solved for the drift.
    const double size_fraction = clearance_size_fraction(reach.tolerance);
    const double at_start =
        clearance_reach(reach.contact_distance, size_fraction, pair_box_diagonal(a, b), 0.0, reach.magnitude);
    const double distance = tested_primitive_distance(ids_a, a, ids_b, b, true);
    drift_limit_ = (distance - at_start) / (1.0 + PAIR_CLEARANCE_DRIFT_GROWTH * size_fraction);
}

bool SharedVertexClearance::holds_over(const Triangle& ids_a, const std::array<Vec3, 3>& a0,
                                       const std::array<Vec3, 3>& a1, const Triangle& ids_b,
                                       const std::array<Vec3, 3>& b0, const std::array<Vec3, 3>& b1,
                                       const SharedVertexReach& reach) {
    if (shared_a_ < 0) return false;
    const double step_reach = clearance_reach(reach.contact_distance, clearance_size_fraction(reach.tolerance),
                                              swept_diagonal(a0, a1, b0, b1), 0.0, reach.magnitude);
    if (plane_possible_) {
        const Vec3 last(normal_[0], normal_[1], normal_[2]);
        if (plane_holds(last, a0, a1, b0, b1, step_reach)) return true;
        const Vec3 fitted = fitted_normal(a0, a1, b0, b1).cast<float>().cast<double>();
        if (plane_holds(fitted, a0, a1, b0, b1, step_reach)) {
            for (int k = 0; k < 3; ++k) normal_[k] = static_cast<float>(fitted[k]);
            return true;
        }
    }
    if (primitives_apart(ids_a, a0, a1, ids_b, b0, b1, step_reach)) return true;
    if (std::isnan(drift_limit_)) measure_drift_limit(ids_a, ids_b, reach);
    if (!(drift_limit_ > 0.0)) return false;
    return drift(a0, b0) < drift_limit_ && drift(a1, b1) < drift_limit_;
}

} // namespace usdksl
