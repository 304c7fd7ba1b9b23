#include "usdksl/narrow_phase/pair_clearance.hpp"

#include "usdksl/geometry/primitive_distance.hpp"
#include "usdksl/narrow_phase/vertex_sharing.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace usdksl {
namespace {


/// Least and most height of a triangle's corners along an axis: every point
/// of the triangle lies between them.
struct Span {
    double low, high;
};

Span span_along(const Vec3& axis, const std::array<Vec3, 3>& t) {
    const double h0 = axis.dot(t[0]), h1 = axis.dot(t[1]), h2 = axis.dot(t[2]);
    return {std::min({h0, h1, h2}), std::max({h0, h1, h2})};
}

Span joined(const Span& x, const Span& y) { return {std::min(x.low, y.low), std::max(x.high, y.high)}; }

/// Gap between two spans, whichever lies above (negative when they overlap).
double gap_between(const Span& a, const Span& b) { return std::max(b.low - a.high, a.low - b.high); }

/// Smallest height of B's vertices minus the largest of A's along `normal`.
double plane_gap(const Vec3& normal, const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
    return span_along(normal, b).low - span_along(normal, a).high;
}

/// The axes across a triangle's edges in its plane (normal x edge, not unit).
std::array<Vec3, 3> in_plane_axes(const std::array<Vec3, 3>& t) {
    const Vec3 normal = (t[1] - t[0]).cross(t[2] - t[0]);
    return {normal.cross(t[1] - t[0]), normal.cross(t[2] - t[1]), normal.cross(t[0] - t[2])};
}

} // namespace

double clearance_size_fraction(double tolerance) {
    return std::max(PAIR_CLEARANCE_SIZE_FRACTION, PAIR_CLEARANCE_TOLERANCE_FACTOR * tolerance);
}

double clearance_reach(double contact_distance, double size_fraction, double diameter, double drift,
                       double magnitude) {
    return PAIR_CLEARANCE_CONTACT_REACH * contact_distance +
           size_fraction * (diameter + PAIR_CLEARANCE_DRIFT_GROWTH * drift) + PAIR_CLEARANCE_ROUNDING * magnitude;
}

double pair_box_diagonal(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
    Vec3 lo = a[0], hi = a[0];
    for (int i = 0; i < 3; ++i) {
        lo = lo.cwiseMin(a[i]).cwiseMin(b[i]);
        hi = hi.cwiseMax(a[i]).cwiseMax(b[i]);
    }
    return (hi - lo).norm();
}

double in_plane_gap(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
    // Along any unit axis, the gap between the two triangles' projections
    // bounds the distance of any point of one from any point of the other.
    double best = -std::numeric_limits<double>::infinity();
    for (const std::array<Vec3, 3>* t : {&a, &b}) {
        for (const Vec3& axis : in_plane_axes(*t)) {
            const double length = axis.norm();
            if (length > 0.0) best = std::max(best, gap_between(span_along(axis, a), span_along(axis, b)) / length);
        }
    }
    return best;
}

bool swept_apart(const std::array<Vec3, 3>& a0, const std::array<Vec3, 3>& a1, const std::array<Vec3, 3>& b0,
                 const std::array<Vec3, 3>& b1, double reach) {
    const auto apart_along = [&](const Vec3& axis) {
        const double length = axis.norm();
        return length > 0.0 && gap_between(joined(span_along(axis, a0), span_along(axis, a1)),
                                           joined(span_along(axis, b0), span_along(axis, b1))) > reach * length;
    };
    const auto normal = [](const std::array<Vec3, 3>& t) { return Vec3((t[1] - t[0]).cross(t[2] - t[0])); };
    if (apart_along(normal(a0)) || apart_along(normal(b0)) || apart_along(normal(a1)) || apart_along(normal(b1))) {
        return true;
    }
    for (const std::array<Vec3, 3>* t : {&a0, &b0}) {
        for (const Vec3& axis : in_plane_axes(*t)) {
            if (apart_along(axis)) return true;
        }
    }
    return false;
}

double tested_primitive_distance(const Triangle& ids_a, const std::array<Vec3, 3>& a, const Triangle& ids_b,
                                 const std::array<Vec3, 3>& b, bool same_mesh, double within) {
    // Every tested vertex-face and edge-edge distance is the least of some
    // vertex-to-edge distances and one interior candidate; a vertex-to-edge
    // distance serves up to three of those pairs, so it is measured once, when
    // first needed (pairs that share vertices need only some).
    // to_edge[0][i][j]: A's vertex i to B's edge (j, j+1); [1]: B's vertex i to A's edge.
    double to_edge[2][3][3];
    for (auto& side : to_edge)
        for (auto& row : side) row[0] = row[1] = row[2] = -1.0;
    const auto vertex_to_edge = [&](int side, int i, int j) {
        double& squared = to_edge[side][i][j];
        if (squared < 0.0) {
            const std::array<Vec3, 3>& vertices = side == 0 ? a : b;
            const std::array<Vec3, 3>& edges = side == 0 ? b : a;
            squared = point_segment_distance_squared(vertices[i], edges[j], edges[(j + 1) % 3]);
        }
        return squared;
    };
    double squared = std::numeric_limits<double>::infinity();
    // A pair found within `within` answers the caller's question at once.
    const double within_squared = within > 0.0 ? within * within : -1.0;
    for (int i = 0; i < 3; ++i) {
        if (!(same_mesh && triangle_holds_vertex(ids_b, ids_a[i]))) {
            squared = std::min({squared, vertex_to_edge(0, i, 0), vertex_to_edge(0, i, 1), vertex_to_edge(0, i, 2),
                                point_triangle_interior_distance_squared(a[i], b[0], b[1], b[2])});
        }
        if (!(same_mesh && triangle_holds_vertex(ids_a, ids_b[i]))) {
            squared = std::min({squared, vertex_to_edge(1, i, 0), vertex_to_edge(1, i, 1), vertex_to_edge(1, i, 2),
                                point_triangle_interior_distance_squared(b[i], a[0], a[1], a[2])});
        }
        if (squared <= within_squared) return std::sqrt(squared);
    }
    for (int i = 0; i < 3; ++i) {
        const int i1 = (i + 1) % 3;
        for (int j = 0; j < 3; ++j) {
            const int j1 = (j + 1) % 3;
            if (same_mesh && edges_share_vertex(ids_a[i], ids_a[i1], ids_b[j], ids_b[j1])) continue;
            squared = std::min({squared, vertex_to_edge(0, i, j), vertex_to_edge(0, i1, j), vertex_to_edge(1, j, i),
                                vertex_to_edge(1, j1, i),
                                segment_segment_interior_distance_squared(a[i], a[i1], b[j], b[j1])});
        }
        if (squared <= within_squared) return std::sqrt(squared);
    }
    return std::sqrt(squared);
}

void PairClearance::start(const Triangle& ids_a, const std::array<Vec3, 3>& a, const Triangle& ids_b,
                          const std::array<Vec3, 3>& b, bool same_mesh, double contact_distance, double tolerance,
                          double magnitude) {
    ids_a_ = ids_a;
    ids_b_ = ids_b;
    same_mesh_ = same_mesh;
    for (int i = 0; i < 3; ++i) {
        start_[i] = a[i];
        start_[3 + i] = b[i];
    }
    diameter_ = pair_box_diagonal(a, b);
    contact_distance_ = contact_distance;
    size_fraction_ = clearance_size_fraction(tolerance);
    magnitude_ = magnitude;
    drift_ = 0.0;
    distance_known_ = false;
    bound_known_ = false;
    plane_holds_ = false;
    start_plane_gap_ = -std::numeric_limits<double>::infinity();
    bool shared = false;
    reference_ = 0;
    for (int i = 2; i >= 0; --i) {
        if (same_mesh && triangle_holds_vertex(ids_b, ids_a[i])) {
            shared = true;
            reference_ = i;
        }
    }
    if (!shared) {  // the plane of either triangle would pass through a shared vertex
        double best = -std::numeric_limits<double>::infinity();
        for (const std::array<Vec3, 3>* t : {&a, &b}) {
            const Vec3 cross = ((*t)[1] - (*t)[0]).cross((*t)[2] - (*t)[0]);
            const double length = cross.norm();
            if (!(length > 0.0)) continue;
            for (double side : {1.0, -1.0}) {
                const Vec3 normal = cross * (side / length);
                const double gap = plane_gap(normal, a, b);
                if (gap > best) {
                    best = gap;
                    normal_ = normal;
                }
            }
        }
        start_plane_gap_ = best;
        plane_holds_ = best > plane_reach();
    }
}

double PairClearance::separating_gap() const {
    return std::max(start_plane_gap_, in_plane_gap({start_[0], start_[1], start_[2]}, {start_[3], start_[4], start_[5]}));
}

void PairClearance::measure_distance(double within) {
    distance_ = tested_primitive_distance(ids_a_, {start_[0], start_[1], start_[2]}, ids_b_,
                                          {start_[3], start_[4], start_[5]}, same_mesh_, within);
    distance_known_ = true;
}

double PairClearance::plane_reach() const {
    // Box diagonals do not change with a translation: the six vertices' box
    // now is that of their start positions moved by their displacements
    // relative to the reference vertex, none longer than the drift.
    return clearance_reach(contact_distance_, size_fraction_, diameter_ + PAIR_CLEARANCE_BOX_GROWTH * drift_, 0.0,
                           magnitude_);
}

bool PairClearance::holds_at(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
    // Displacements relative to the reference vertex, squared: one square
    // root per triangle (the largest), not one per vertex.
    const Vec3 moved_reference = a[reference_] - start_[reference_];
    double squared_a = 0.0, squared_b = 0.0;
    for (int i = 0; i < 3; ++i) {
        squared_a = std::max(squared_a, (a[i] - start_[i] - moved_reference).squaredNorm());
        squared_b = std::max(squared_b, (b[i] - start_[3 + i] - moved_reference).squaredNorm());
    }
    drift_ = std::max(drift_, std::sqrt(squared_a) + std::sqrt(squared_b));
    plane_holds_ = plane_holds_ && plane_gap(normal_, a, b) > plane_reach();
    if (plane_holds_) return true;
    // The drift proof: distance_ - drift_ > reach only weakens as drift_
    // grows, so asking it now answers for every step since the start. A
    // lower bound of the distance serves as well while it is enough.
    const double reach = clearance_reach(contact_distance_, size_fraction_, diameter_, drift_, magnitude_);
    if (!distance_known_) {
        if (!bound_known_) {
            distance_ = separating_gap();
            bound_known_ = true;
        }
        if (distance_ - drift_ > reach) return true;
        // A distance found within drift_ + reach fails the proof now, and
        // for good: drift_ and the reach only grow.
        measure_distance(drift_ + reach);
    }
    return distance_ - drift_ > reach;
}

} // namespace usdksl
