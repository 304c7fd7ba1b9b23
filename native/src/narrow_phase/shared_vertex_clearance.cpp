#include "usdksl/narrow_phase/shared_vertex_clearance.hpp"

#include "usdksl/narrow_phase/pair_clearance.hpp"
#include "usdksl/narrow_phase/vertex_sharing.hpp"
#include "usdksl/single_precision.hpp"

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

/// An allowance (scene units) kept in single precision: never more than `value`, and 0 for a value not
/// above 0 or NaN.
float allowance_of(double value) { return value > 0.0 ? float_at_most(value) : 0.0f; }

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
                                  const std::array<Vec3, 3>& b, double magnitude) {
    drift_limit_ = -1.0;
    drift_held_ = plane_held_ = last_fell_short_ = false;
    allowance_ = 0.0f;
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
    magnitude_ = float_at_least(magnitude);
    set_drift_reference(a, b);
}

void SharedVertexClearance::set_drift_reference(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
    const FreeCorners corners = free_corners(a, b);
    for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 3; ++k) offsets_[i][k] = static_cast<float>(corners.offset[i][k]);
    drift_limit_ = std::numeric_limits<double>::quiet_NaN();
    drift_held_ = false;
    drift_fresh_ = true;
}

SharedVertexClearance::FreeCorners SharedVertexClearance::free_corners(const std::array<Vec3, 3>& a,
                                                                       const std::array<Vec3, 3>& b) const {
    const Vec3& shared = a[shared_a_];
    FreeCorners corners;
    corners.offset[0] = a[(shared_a_ + 1) % 3] - shared;
    corners.offset[1] = a[(shared_a_ + 2) % 3] - shared;
    corners.offset[2] = b[(shared_b_ + 1) % 3] - shared;
    corners.offset[3] = b[(shared_b_ + 2) % 3] - shared;
    corners.radius_squared = 0.0;
    for (const Vec3& offset : corners.offset)
        corners.radius_squared = std::max(corners.radius_squared, offset.squaredNorm());
    return corners;
}

double SharedVertexClearance::plane_margin(const Vec3& normal, const FreeCorners& corners) {
    // Negated comparisons: a NaN never counts.
    double margin = -normal.dot(corners.offset[0]);
    for (const double height : {-normal.dot(corners.offset[1]), normal.dot(corners.offset[2]),
                                normal.dot(corners.offset[3])})
        margin = height < margin || std::isnan(height) ? height : margin;
    return margin;
}

float SharedVertexClearance::plane_least(const Vec3& normal, float radius, double contact_distance,
                                         double tolerance) const {
    // Heights are normal . offset: the reach is scaled by |normal| instead of dividing each height by it.
    return float_at_least(clearance_reach(contact_distance, clearance_size_fraction(tolerance),
                                          SHARED_VERTEX_BOX_DIAGONAL_PER_RADIUS * radius, 0.0, magnitude_) *
                          normal.norm());
}

bool SharedVertexClearance::plane_holds(const Vec3& normal, const FreeCorners& begin, const FreeCorners& end,
                                        float least) {
    if (!(least > 0.0f) || !std::isfinite(least)) return false;
    return plane_margin(normal, begin) > least && plane_margin(normal, end) > least;
}

Vec3 SharedVertexClearance::fitted_normal(const FreeCorners& begin, const FreeCorners& end) {
    // Across the two triangles' corners at the shared vertex, halfway through
    // the step: from the mean direction of A's edges out of it to B's.
    const auto direction = [](const Vec3& v) {
        const double length = v.norm();
        return length > 0.0 ? Vec3(v / length) : Vec3(Vec3::Zero());
    };
    const auto middle = [&](int i) { return direction(begin.offset[i] + end.offset[i]); };
    // In single precision, as normal_ keeps it: the plane proven is the plane kept.
    return (direction(middle(2) + middle(3)) - direction(middle(0) + middle(1))).cast<float>().cast<double>();
}

bool SharedVertexClearance::primitives_apart(const Triangle& ids_a, const std::array<Vec3, 3>& a0,
                                             const std::array<Vec3, 3>& a1, const Triangle& ids_b,
                                             const std::array<Vec3, 3>& b0, const std::array<Vec3, 3>& b1,
                                             double reach) {
    // The primitive pairs the narrow phase tests for two triangles of one mesh, as triangle_pair_ccd takes them.
    for (int i = 0; i < 3; ++i) {
        if (!triangle_holds_vertex(ids_b, ids_a[i]) && !centroids_apart(&a0[i], &a1[i], 1, b0.data(), b1.data(), 3, reach))
            return false;
        if (!triangle_holds_vertex(ids_a, ids_b[i]) && !centroids_apart(&b0[i], &b1[i], 1, a0.data(), a1.data(), 3, reach))
            return false;
    }
    for (int i = 0; i < 3; ++i) {
        const int i1 = (i + 1) % 3;
        for (int j = 0; j < 3; ++j) {
            const int j1 = (j + 1) % 3;
            if (edges_share_vertex(ids_a[i], ids_a[i1], ids_b[j], ids_b[j1])) continue;
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
    const double squared_a = std::max((a[(shared_a_ + 1) % 3] - reference - offset(0)).squaredNorm(),
                                      (a[(shared_a_ + 2) % 3] - reference - offset(1)).squaredNorm());
    const double squared_b = std::max((b[(shared_b_ + 1) % 3] - reference - offset(2)).squaredNorm(),
                                      (b[(shared_b_ + 2) % 3] - reference - offset(3)).squaredNorm());
    return std::sqrt(squared_a) + std::sqrt(squared_b);
}

void SharedVertexClearance::measure_drift_limit(const Triangle& ids_a, const Triangle& ids_b,
                                                double contact_distance, double tolerance) {
    // The reference positions, the shared vertex at the origin: distances do not change with a translation.
    std::array<Vec3, 3> a, b;
    a[shared_a_] = Vec3::Zero();
    a[(shared_a_ + 1) % 3] = offset(0);
    a[(shared_a_ + 2) % 3] = offset(1);
    b[shared_b_] = Vec3::Zero();
    b[(shared_b_ + 1) % 3] = offset(2);
    b[(shared_b_ + 2) % 3] = offset(3);
    // PairClearance's drift proof holds while distance - drift > reach(drift),
    // reach growing by the size fraction times the drift growth: solved for the drift.
    const double size_fraction = clearance_size_fraction(tolerance);
    const double at_start = clearance_reach(contact_distance, size_fraction, pair_box_diagonal(a, b), 0.0, magnitude_);
    const double distance = tested_primitive_distance(ids_a, a, ids_b, b, true);
    drift_limit_ = (distance - at_start) / (1.0 + PAIR_CLEARANCE_DRIFT_GROWTH * size_fraction);
}

bool SharedVertexClearance::drift_proof(const Triangle& ids_a, const std::array<Vec3, 3>& a0,
                                        const std::array<Vec3, 3>& a1, const Triangle& ids_b,
                                        const std::array<Vec3, 3>& b0, const std::array<Vec3, 3>& b1,
                                        double contact_distance, double tolerance) {
    if (std::isnan(drift_limit_)) measure_drift_limit(ids_a, ids_b, contact_distance, tolerance);
    const double at_end = drift(a1, b1);
    drift_held_ = drift_limit_ > 0.0 && at_end < drift_limit_;
    if (!drift_held_ || !(drift(a0, b0) < drift_limit_)) return false;
    keep_drift_allowance(at_end);
    return true;
}

void SharedVertexClearance::keep_drift_allowance(double drift_at_end) {
    // A corner moving by d relative to the shared vertex moves its triangle's drift by at most d, and
    // the two triangles' corners may both move.
    allowance_ = allowance_of(0.5 * (drift_limit_ - drift_at_end));
}

void SharedVertexClearance::keep_plane_allowance(double margin_at_end, double radius_at_end) {
    // A corner moving by d relative to the shared vertex moves its height by at most |normal| d and its
    // distance from the shared vertex by at most d.
    allowance_ = allowance_of(
        std::min((margin_at_end - static_cast<double>(plane_least_)) / last_normal().norm(),
                 static_cast<double>(proven_radius_) - radius_at_end));
}

bool SharedVertexClearance::holds_at_end(const std::array<Vec3, 3>& a1, const std::array<Vec3, 3>& b1) {
    allowance_ = 0.0f;
    if (drift_held_) {
        const double at_end = drift(a1, b1);
        if (at_end < drift_limit_) {
            keep_drift_allowance(at_end);
            return true;
        }
        drift_held_ = false;
    }
    if (plane_held_) {
        plane_held_ = false;
        // The begin cleared plane_least_, the reach within proven_radius_; the end must too, within it.
        const FreeCorners end = free_corners(a1, b1);
        // Exact: a product of two floats fits a double.
        const double radius = proven_radius_;
        if (end.radius_squared <= radius * radius) {
            const double margin = plane_margin(last_normal(), end);
            if (margin > plane_least_) {
                plane_held_ = true;
                keep_plane_allowance(margin, std::sqrt(end.radius_squared));
                return true;
            }
            last_fell_short_ = true;
        }
    }
    return false;
}

bool SharedVertexClearance::holds_over(const Triangle& ids_a, const std::array<Vec3, 3>& a0,
                                       const std::array<Vec3, 3>& a1, const Triangle& ids_b,
                                       const std::array<Vec3, 3>& b0, const std::array<Vec3, 3>& b1,
                                       double contact_distance, double tolerance) {
    if (shared_a_ < 0) return false;
    if (holds_at_end(a1, b1)) return true;
    const bool drift_fresh = drift_fresh_;
    drift_fresh_ = false;
    if (!plane_possible_) {
        // A hinged pair: the drift proof first, as cheap as it gets on a cloth at rest, then from this
        // step's begin (a cloth turning a little at a time keeps it for the steps that follow).
        if (drift_proof(ids_a, a0, a1, ids_b, b0, b1, contact_distance, tolerance)) return true;
        if (!drift_fresh) {
            set_drift_reference(a0, b0);
            if (drift_proof(ids_a, a0, a1, ids_b, b0, b1, contact_distance, tolerance)) return true;
        }
        return primitives_apart(ids_a, a0, a1, ids_b, b0, b1, swept_reach(a0, a1, b0, b1, contact_distance, tolerance));
    }
    const FreeCorners begin = free_corners(a0, b0), end = free_corners(a1, b1);
    // Proven with headroom, a plane stays on the end-only path while the pair stretches a little; the
    // radius and the reach are rounded up to single precision as they are kept.
    const float radius =
        float_at_least(SHARED_VERTEX_RADIUS_HEADROOM * std::sqrt(std::max(begin.radius_squared, end.radius_squared)));
    // The last normal, unless its end fell short; then one fitted to the step.
    const bool ask_last = !last_fell_short_;
    last_fell_short_ = false;
    const Vec3 normals[2] = {last_normal(), fitted_normal(begin, end)};
    for (int i = ask_last ? 0 : 1; i < 2; ++i) {
        const float least = plane_least(normals[i], radius, contact_distance, tolerance);
        if (plane_holds(normals[i], begin, end, least)) {
            keep_plane(normals[i], radius, least);
            keep_plane_allowance(plane_margin(normals[i], end), std::sqrt(end.radius_squared));
            return true;
        }
    }
    if (primitives_apart(ids_a, a0, a1, ids_b, b0, b1, swept_reach(a0, a1, b0, b1, contact_distance, tolerance)))
        return true;
    return drift_proof(ids_a, a0, a1, ids_b, b0, b1, contact_distance, tolerance);
}

Vec3 SharedVertexClearance::last_normal() const { return Vec3(normal_[0], normal_[1], normal_[2]); }

void SharedVertexClearance::keep_plane(const Vec3& normal, float radius, float least) {
    for (int k = 0; k < 3; ++k) normal_[k] = static_cast<float>(normal[k]);  // exact: a normal in single precision
    plane_held_ = true;
    proven_radius_ = radius;
    plane_least_ = least;
}

double SharedVertexClearance::swept_reach(const std::array<Vec3, 3>& a0, const std::array<Vec3, 3>& a1,
                                          const std::array<Vec3, 3>& b0, const std::array<Vec3, 3>& b1,
                                          double contact_distance, double tolerance) const {
    return clearance_reach(contact_distance, clearance_size_fraction(tolerance), swept_diagonal(a0, a1, b0, b1), 0.0,
                           magnitude_);
}

} // namespace usdksl
