#pragma once
/// @file exact_geometry.hpp
/// @brief Exact (thickness 0) incidence tests between closed points, segments
///        and triangles in 3-D, built only on exact orientation predicates, so
///        coplanar, touching and degenerate (zero-length, zero-area) inputs are
///        decided correctly.

#include "usdksl/types.hpp"

namespace usdksl {

/// @brief True when a, b, c are exactly collinear (zero-area triangle).
bool triangle_is_degenerate(const Vec3& a, const Vec3& b, const Vec3& c);

/// @brief True when closed segments pq and rs share a point.
bool segments_intersect(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s);

/// @brief True when point p lies on closed triangle abc.
bool point_in_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// @brief True when closed segment pq shares a point with closed triangle abc.
bool segment_intersects_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                                 const Vec3& c);

} // namespace usdksl
