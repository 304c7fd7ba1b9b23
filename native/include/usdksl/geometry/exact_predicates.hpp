#pragma once
/// @file exact_predicates.hpp
/// @brief Adaptive exact orientation predicates: a floating-point filter first,
///        exact expansion arithmetic only when the filter cannot decide.

#include "usdksl/types.hpp"

namespace usdksl {

/// @brief A point of a coordinate plane (a 3-D point with one axis dropped).
struct Point2 {
    double x;
    double y;
};

/// @brief Exact sign of det[a-c, b-c]: +1 when a, b, c turn counter-clockwise,
///        -1 clockwise, 0 exactly collinear.
int orient2d(const Point2& a, const Point2& b, const Point2& c);

/// @brief Exact sign of det[a-d, b-d, c-d]: 0 exactly when the four points are
///        coplanar; the sign flips when d crosses the plane of a, b, c.
int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// @brief The point with coordinate axis `dropped_axis` (0, 1 or 2) removed.
inline Point2 project_dropping_axis(const Vec3& p, int dropped_axis) {
    const int i = dropped_axis == 0 ? 1 : 0;
    const int j = dropped_axis == 2 ? 1 : 2;
    return Point2{p[i], p[j]};
}

} // namespace usdksl
