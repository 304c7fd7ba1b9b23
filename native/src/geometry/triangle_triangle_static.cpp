/// @file triangle_triangle_static.cpp
/// @brief Two closed triangles at one instant: exact incidence, then distances.

#include "usdksl/geometry/triangle_triangle_static.hpp"

#include "usdksl/geometry/exact_geometry.hpp"
#include "usdksl/geometry/primitive_distance.hpp"
#include "usdksl/geometry/rounding.hpp"
#include "usdksl/geometry/triangle_separating_axis.hpp"

#include <algorithm>
#include <cmath>

namespace usdksl {

bool triangles_intersect_static(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b,
                                double thickness) {
    thickness = std::max(thickness, 0.0);
    Vec3 a_min = a[0], a_max = a[0], b_min = b[0], b_max = b[0];
    for (int i = 1; i < 3; ++i) {
        a_min = a_min.cwiseMin(a[i]);
        a_max = a_max.cwiseMax(a[i]);
        b_min = b_min.cwiseMin(b[i]);
        b_max = b_max.cwiseMax(b[i]);
    }
    const double magnitude = std::max({a_min.cwiseAbs().maxCoeff(), a_max.cwiseAbs().maxCoeff(),
                                       b_min.cwiseAbs().maxCoeff(), b_max.cwiseAbs().maxCoeff()});
    const double reach = thickness + STATIC_DISTANCE_RELATIVE_SLACK * magnitude;
    for (int k = 0; k < 3; ++k) {
        if (a_min[k] > b_max[k] + reach || b_min[k] > a_max[k] + reach) return false;
    }
    // Closed triangles meet iff an edge of one meets the other (the boundary of
    // the convex intersection lies on their edges). A separating axis proves
    // in floating point that no edge does: nearly coplanar neighbours would
    // otherwise fall through to exact arithmetic in every test.
    if (!triangles_apart_along_an_axis(a, b, magnitude)) {
        for (int i = 0; i < 3; ++i) {
            if (segment_intersects_triangle(a[i], a[(i + 1) % 3], b[0], b[1], b[2])) return true;
            if (segment_intersects_triangle(b[i], b[(i + 1) % 3], a[0], a[1], a[2])) return true;
        }
    }
    if (thickness <= 0.0) return false;
    const double reach_squared = reach * reach;
    for (int i = 0; i < 3; ++i) {
        if (point_triangle_distance_squared(a[i], b[0], b[1], b[2]) <= reach_squared) return true;
        if (point_triangle_distance_squared(b[i], a[0], a[1], a[2]) <= reach_squared) return true;
        for (int j = 0; j < 3; ++j) {
            if (segment_segment_distance_squared(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]) <=
                reach_squared)
                return true;
        }
    }
    return false;
}

} // namespace usdksl
