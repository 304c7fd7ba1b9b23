#include "usdksl/kinetic/node_plane.hpp"

#include "usdksl/narrow_phase/pair_clearance.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace usdksl {
namespace {

/// Folds the heights of vertices [first, last) at the step's ends from
/// `first_end` on (0: both, 1: its end) into `h`.
void fold_heights(const StepBoxTree& tree, const int32_t* first, const int32_t* last, const Vec3& direction,
                  int first_end, NodeHeights& h) {
    for (int end = first_end; end < 2; ++end) {
        const double* points = end == 0 ? tree.begin_points() : tree.end_points();
        double low = h.low[end], high = h.high[end];
        for (const int32_t* v = first; v != last; ++v) {
            const double* p = points + 3 * static_cast<size_t>(*v);
            const double height = direction[0] * p[0] + direction[1] * p[1] + direction[2] * p[2];
            low = std::min(low, height);
            high = std::max(high, height);
        }
        h.low[end] = low;
        h.high[end] = high;
    }
}

/// node_heights() at the step's ends from `first_end` on (the others left infinite).
NodeHeights heights_from(const StepBoxTree& tree, int32_t node, const Vec3& direction, int first_end) {
    NodeHeights h{{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()},
                  {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}};
    const auto [first, last] = tree.vertices_under(node);
    if (first != last) {
        fold_heights(tree, first, last, direction, first_end, h);
        return h;
    }
    // A node too large for the tree to list its vertices: its triangles' corners.
    const auto [first_triangle, last_triangle] = tree.triangles_under(node);
    const std::vector<Triangle>& triangles = tree.triangles();
    for (const int32_t* t = first_triangle; t != last_triangle; ++t) {
        const Triangle& corners = triangles[static_cast<size_t>(*t)];
        fold_heights(tree, corners.data(), corners.data() + 3, direction, first_end, h);
    }
    return h;
}

/// True, orienting `normal`, when the vertices under b lie above those under
/// a along `direction` (or along its opposite) by more than `reach` at both
/// ends of the step. Given `begin_gap`, b's least height minus a's most along
/// `direction` at the step's begin, only the end is measured.
bool separates(const StepBoxTree& tree_a, int32_t a, const StepBoxTree& tree_b, int32_t b, double reach,
               const Vec3& direction, Vec3& normal, double* end_gap, const double* begin_gap = nullptr) {
    if (!(direction.squaredNorm() > 0.0)) return false;
    if (begin_gap && *begin_gap > 0.0) {
        // a above b by more than the reach would need a's least height above
        // b's most at the begin, where it lies below by at least the gap.
        const NodeHeights ha = heights_from(tree_a, a, direction, 1);
        const NodeHeights hb = heights_from(tree_b, b, direction, 1);
        if (!(std::min(*begin_gap, hb.low[1] - ha.high[1]) > reach)) return false;
        normal = direction;
        if (end_gap) *end_gap = hb.low[1] - ha.high[1];
        return true;
    }
    const NodeHeights ha = node_heights(tree_a, a, direction);
    const NodeHeights hb = node_heights(tree_b, b, direction);
    const double b_above = std::min(hb.low[0] - ha.high[0], hb.low[1] - ha.high[1]);
    const double a_above = std::min(ha.low[0] - hb.high[0], ha.low[1] - hb.high[1]);
    if (b_above > reach) {
        normal = direction;
        if (end_gap) *end_gap = hb.low[1] - ha.high[1];
        return true;
    }
    if (a_above > reach) {
        normal = -direction;
        if (end_gap) *end_gap = ha.low[1] - hb.high[1];
        return true;
    }
    return false;
}

} // namespace

NodeHeights node_heights(const StepBoxTree& tree, int32_t node, const Vec3& direction) {
    return heights_from(tree, node, direction, 0);
}

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
                     const Vec3& previous, Vec3& normal, double* end_gap, const double* previous_begin_gap) {
    if (separates(tree_a, a, tree_b, b, reach, previous, normal, end_gap, previous_begin_gap)) return true;
    const Vec3& along_a = tree_a.end_mean_normal(a);
    if (separates(tree_a, a, tree_b, b, reach, along_a, normal, end_gap)) return true;
    const Vec3& along_b = tree_b.end_mean_normal(b);
    return along_b.cross(along_a).squaredNorm() > 0.0 &&
           separates(tree_a, a, tree_b, b, reach, along_b, normal, end_gap);
}

int64_t node_plane_quiet_until(const StepBoxTree& tree_a, int32_t a, const StepBoxTree& tree_b, int32_t b,
                               const Vec3& normal, double end_gap, double contact_distance, double tolerance,
                               int64_t step, int64_t steps, const double* travel_a, const double* travel_b) {
    int64_t next = step + 1;
    if (next >= steps) return next;
    const StepBox& ba = tree_a.box(a);
    const StepBox& bb = tree_b.box(b);
    const double size_fraction = clearance_size_fraction(tolerance);
    const double slope = std::abs(normal[0]) + std::abs(normal[1]) + std::abs(normal[2]);
    // Bounds, per axis, of every displacement since the fitted step's end of
    // a vertex under a (b): [low, high], at the end of the last step judged.
    double low_a[3] = {0.0, 0.0, 0.0}, high_a[3] = {0.0, 0.0, 0.0};
    double low_b[3] = {0.0, 0.0, 0.0}, high_b[3] = {0.0, 0.0, 0.0};
    double gap = end_gap;
    // node_pair_reach over a step, bounded from above: its boxes lie in the
    // boxes at the fitted step's end grown by displacements within [low, high]
    // (each side's bounds at both of the step's ends). Sets the magnitude.
    const auto reach_over = [&](const double* la, const double* ha, const double* lb, const double* hb,
                                double& magnitude) {
        Vec3 low, high;
        magnitude = 0.0;
        for (int axis = 0; axis < 3; ++axis) {
            low[axis] = std::min(ba.lo[1][axis] + la[axis], bb.lo[1][axis] + lb[axis]);
            high[axis] = std::max(ba.hi[1][axis] + ha[axis], bb.hi[1][axis] + hb[axis]);
            magnitude = std::max({magnitude, std::abs(low[axis]), std::abs(high[axis])});
        }
        return clearance_reach(contact_distance, size_fraction, (high - low).norm(), 0.0, magnitude);
    };
    const int64_t recorded_end = std::min(steps, next + NODE_TRAVEL_AHEAD_STEPS);
    for (; next < recorded_end; ++next) {
        const NodeShift& sa = tree_a.shift(a, next);
        const NodeShift& sb = tree_b.shift(b, next);
        double rise = slope * (static_cast<double>(sa.radius) + sb.radius);  // of a's heights against b's
        for (int axis = 0; axis < 3; ++axis) {
            rise += normal[axis] * (static_cast<double>(sa.center[axis]) - sb.center[axis]);
        }
        // Every reach is at least the contact reach: most pairs fail here,
        // before their grown boxes are measured.
        if (!(gap - rise > PAIR_CLEARANCE_CONTACT_REACH * contact_distance)) return next;
        double step_low_a[3], step_high_a[3], step_low_b[3], step_high_b[3];
        for (int axis = 0; axis < 3; ++axis) {
            const double ca = sa.center[axis], cb = sb.center[axis];
            const double la = low_a[axis] + (ca - sa.radius), ha = high_a[axis] + (ca + sa.radius);
            const double lb = low_b[axis] + (cb - sb.radius), hb = high_b[axis] + (cb + sb.radius);
            step_low_a[axis] = std::min(low_a[axis], la);
            step_high_a[axis] = std::max(high_a[axis], ha);
            step_low_b[axis] = std::min(low_b[axis], lb);
            step_high_b[axis] = std::max(high_b[axis], hb);
            low_a[axis] = la;
            high_a[axis] = ha;
            low_b[axis] = lb;
            high_b[axis] = hb;
        }
        double magnitude;
        const double reach = reach_over(step_low_a, step_high_a, step_low_b, step_high_b, magnitude);
        const double after = gap - rise - NODE_PLANE_ROUNDING * magnitude;
        // The step's begin is the last one's end, but its reach may be larger.
        if (!(std::min(gap, after) > reach)) return next;
        gap = after;
    }
    if (next >= steps || !travel_a || !travel_b) return next;
    // Beyond, every vertex moves along each axis by at most its mesh's travel:
    // the gap bound only shrinks and the reach only grows, step after step.
    const int64_t first = next;
    const auto holds = [&](int64_t s) {  // through step s, s >= first
        const double ta = travel_a[s + 1] - travel_a[first], tb = travel_b[s + 1] - travel_b[first];
        double la[3], ha[3], lb[3], hb[3];
        for (int axis = 0; axis < 3; ++axis) {
            la[axis] = low_a[axis] - ta;
            ha[axis] = high_a[axis] + ta;
            lb[axis] = low_b[axis] - tb;
            hb[axis] = high_b[axis] + tb;
        }
        double magnitude;
        const double reach = reach_over(la, ha, lb, hb, magnitude);
        return gap - slope * (ta + tb) - static_cast<double>(s - first + 1) * NODE_PLANE_ROUNDING * magnitude > reach;
    };
    if (holds(steps - 1)) return steps;
    int64_t kept = first - 1, fails = steps - 1;  // steps through `kept` hold; step `fails` may not
    while (kept + 1 < fails) {
        const int64_t middle = kept + (fails - kept) / 2;
        if (holds(middle)) kept = middle;
        else fails = middle;
    }
    return fails;
}

} // namespace usdksl
