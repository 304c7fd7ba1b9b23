#include "usdksl/kinetic/node_plane.hpp"

#include "usdksl/narrow_phase/pair_clearance.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace usdksl {
namespace {

/// Least and most height along a direction of the corners under a node, at
/// both ends of the fitted step.
struct Heights {
    double low[2], high[2];
};

Heights heights_under(const StepBoxTree& tree, int32_t node, const Vec3& direction) {
    Heights h{{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()},
              {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}};
    const auto [first, last] = tree.triangles_under(node);
    const std::vector<Triangle>& triangles = tree.triangles();
    for (int end = 0; end < 2; ++end) {
        const double* points = end == 0 ? tree.begin_points() : tree.end_points();
        double low = h.low[end], high = h.high[end];
        for (const int32_t* t = first; t != last; ++t) {
            for (int32_t v : triangles[static_cast<size_t>(*t)]) {
                const double* p = points + 3 * static_cast<size_t>(v);
                const double height = direction[0] * p[0] + direction[1] * p[1] + direction[2] * p[2];
                low = std::min(low, height);
                high = std::max(high, height);
            }
        }
        h.low[end] = low;
        h.high[end] = high;
    }
    return h;
}

/// Area-weighted mean normal of the triangles under a node at the step's
/// end, unit; zero when they cancel out.
Vec3 mean_normal(const StepBoxTree& tree, int32_t node) {
    const auto [first, last] = tree.triangles_under(node);
    const std::vector<Triangle>& triangles = tree.triangles();
    const double* points = tree.end_points();
    const auto at = [&](int32_t v) { return Eigen::Map<const Vec3>(points + 3 * static_cast<size_t>(v)); };
    Vec3 sum = Vec3::Zero();
    for (const int32_t* t = first; t != last; ++t) {
        const Triangle& ids = triangles[static_cast<size_t>(*t)];
        sum += (at(ids[1]) - at(ids[0])).cross(at(ids[2]) - at(ids[0]));
    }
    const double length = sum.norm();
    return length > 0.0 ? Vec3(sum / length) : Vec3::Zero();
}

/// True, orienting `normal`, when the vertices under b lie above those under
/// a along `direction` (or along its opposite) by more than `reach` at both
/// ends of the step.
bool separates(const StepBoxTree& tree_a, int32_t a, const StepBoxTree& tree_b, int32_t b, double reach,
               const Vec3& direction, Vec3& normal) {
    if (!(direction.squaredNorm() > 0.0)) return false;
    const Heights ha = heights_under(tree_a, a, direction);
    const Heights hb = heights_under(tree_b, b, direction);
    const double b_above = std::min(hb.low[0] - ha.high[0], hb.low[1] - ha.high[1]);
    const double a_above = std::min(ha.low[0] - hb.high[0], ha.low[1] - hb.high[1]);
    if (b_above > reach) {
        normal = direction;
        return true;
    }
    if (a_above > reach) {
        normal = -direction;
        return true;
    }
    return false;
}

} // namespace

double node_pair_reach(const StepBoxTree& tree_a, int32_t a, const StepBoxTree& tree_b, int32_t b,
                       double contact_distance, double tolerance) {
    // Boxes (grown by their rounding margins) over both ends of the step:
    // every vertex beneath lies in their union throughout it.
    const StepBox& ba = tree_a.box(a);
    const StepBox& bb = tree_b.box(b);
    Vec3 low, high;
    double magnitude = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        low[axis] = std::min({ba.lo[0][axis], ba.lo[1][axis], bb.lo[0][axis], bb.lo[1][axis]});
        high[axis] = std::max({ba.hi[0][axis], ba.hi[1][axis], bb.hi[0][axis], bb.hi[1][axis]});
        magnitude = std::max({magnitude, std::abs(low[axis]), std::abs(high[axis])});
    }
    return clearance_reach(contact_distance, clearance_size_fraction(tolerance), (high - low).norm(), 0.0, magnitude);
}

bool find_node_plane(const StepBoxTree& tree_a, int32_t a, const StepBoxTree& tree_b, int32_t b, double reach,
                     const Vec3& previous, Vec3& normal) {
    if (separates(tree_a, a, tree_b, b, reach, previous, normal)) return true;
    const Vec3 along_a = mean_normal(tree_a, a);
    if (separates(tree_a, a, tree_b, b, reach, along_a, normal)) return true;
    const Vec3 along_b = mean_normal(tree_b, b);
    return along_b.cross(along_a).squaredNorm() > 0.0 && separates(tree_a, a, tree_b, b, reach, along_b, normal);
}

} // namespace usdksl
