/// @file whole_step_exclusion.cpp
/// @brief Corner differences of a primitive pair at both ends of its step,
///        tested per world axis and along the pair's normals.

#include "whole_step_exclusion.hpp"

#include "rounding_bounds.hpp"

#include "usdksl/ccd/ccd_constants.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace usdksl {
namespace {

/// Differences whose extremes bound F over the domain at one end of the
/// step: p - a, p - b, p - c (vertex-face); ea_i - eb_j (edge-edge).
constexpr int MAX_CORNERS = 4;

struct StepEnd {
    Vec3 corner[MAX_CORNERS];
    /// Normal of the face, or common normal of the two edges.
    Vec3 normal;
    /// Edge-edge: the offset between the lines of the two edges, across edge A.
    Vec3 offset;
    bool has_offset = false;
};

struct Bounds {
    double thickness;
    /// Per world axis: rounding bound of one corner value (scene units).
    double error[3];
    /// Per world axis: largest absolute input coordinate (scene units).
    double max_abs[3];
};

StepEnd step_end(const std::array<Vec3, 4>& p, PrimitivePairKind kind) {
    StepEnd end;
    if (kind == PrimitivePairKind::VertexFace) {
        for (int i = 0; i < 3; ++i) end.corner[i] = p[0] - p[1 + i];
        end.normal = (p[2] - p[1]).cross(p[3] - p[1]);
        return end;
    }
    end.corner[0] = p[0] - p[2];
    end.corner[1] = p[0] - p[3];
    end.corner[2] = p[1] - p[2];
    end.corner[3] = p[1] - p[3];
    const Vec3 edge_a = p[1] - p[0];
    end.normal = edge_a.cross(p[3] - p[2]);
    // The search's offset direction for (nearly) parallel edges: W without its part along edge A.
    const double length_squared = edge_a.squaredNorm();
    if (length_squared > 0.0) {
        const Vec3& w = end.corner[0];
        end.offset = w - (w.dot(edge_a) / length_squared) * edge_a;
        end.has_offset = true;
    }
    return end;
}

/// All corner values at both ends beyond +bound, or all beyond -bound
/// (negated comparisons: a NaN never excludes).
bool all_beyond(const double* values, int count, double bound) {
    bool above = true, below = true;
    for (int i = 0; i < count; ++i) {
        above = above && values[i] > bound;
        below = below && values[i] < -bound;
    }
    return above || below;
}

/// The projections on direction n exclude the thickness ball, by the root
/// search's bound for a fixed direction.
bool excluded_along(const Vec3& n, const StepEnd ends[2], int corners, const Bounds& bounds) {
    // Values beyond a bound of either sign share that sign; most directions
    // fail here, before the bound is worked out. (A value that clears the
    // bound below clears the unscaled one's rounding error too, which the
    // bound's corner errors exceed.)
    bool positive = true, negative = true;
    for (int e = 0; e < 2; ++e) {
        for (int c = 0; c < corners; ++c) {
            const double value = n.dot(ends[e].corner[c]);
            positive = positive && value > 0.0;
            negative = negative && value < 0.0;
        }
    }
    if (!positive && !negative) return false;
    const double scale = n.cwiseAbs().maxCoeff();
    if (!(scale > 0.0) || !std::isfinite(scale)) return false;
    const Vec3 unit_ish = n / scale;
    const double bound = direction_bound(unit_ish, unit_ish.norm() * CCD_BOUND_INFLATION, bounds.thickness,
                                         bounds.error, bounds.max_abs);
    double values[2 * MAX_CORNERS];
    int count = 0;
    for (int e = 0; e < 2; ++e) {
        for (int c = 0; c < corners; ++c) values[count++] = unit_ish.dot(ends[e].corner[c]);
    }
    return all_beyond(values, count, bound);
}

} // namespace

bool excluded_over_whole_step(const MultilinearDistance& f, double thickness) {
    Bounds bounds;
    bounds.thickness = std::max(thickness, 0.0);
    if (!std::isfinite(bounds.thickness)) return false;
    for (int k = 0; k < 3; ++k) {
        double largest = 0.0;
        for (int i = 0; i < 4; ++i) {
            largest = std::max({largest, std::abs(f.at_start[i][k]), std::abs(f.at_end[i][k])});
        }
        // Also false for NaN.
        if (!(largest <= std::numeric_limits<double>::max())) return false;
        bounds.max_abs[k] = largest;
        bounds.error[k] = corner_error(largest);
    }
    const StepEnd ends[2] = {step_end(f.at_start, f.kind), step_end(f.at_end, f.kind)};
    const int corners = f.kind == PrimitivePairKind::VertexFace ? 3 : 4;
    for (int k = 0; k < 3; ++k) {
        double values[2 * MAX_CORNERS];
        int count = 0;
        for (int e = 0; e < 2; ++e) {
            for (int c = 0; c < corners; ++c) values[count++] = ends[e].corner[c][k];
        }
        if (all_beyond(values, count, axis_bound(bounds.thickness, bounds.error[k]))) return true;
    }
    for (const StepEnd& end : ends) {
        if (excluded_along(end.normal, ends, corners, bounds)) return true;
    }
    for (const StepEnd& end : ends) {
        if (end.has_offset && excluded_along(end.offset, ends, corners, bounds)) return true;
    }
    return false;
}

} // namespace usdksl
