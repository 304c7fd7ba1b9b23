#pragma once
/// @file primitive_distance.hpp
/// @brief Floating-point squared distances between closed primitives (scene
///        units squared), for the static test with thickness > 0.

#include "usdksl/types.hpp"

namespace usdksl {

/// @brief Squared distance from point p to closed segment ab.
double point_segment_distance_squared(const Vec3& p, const Vec3& a, const Vec3& b);

/// @brief Squared distance from point p to closed triangle abc (any shape,
///        zero-area included).
double point_triangle_distance_squared(const Vec3& p, const Vec3& a, const Vec3& b,
                                       const Vec3& c);

/// @brief Squared distance between closed segments pq and rs (parallel and
///        zero-length included).
double segment_segment_distance_squared(const Vec3& p, const Vec3& q, const Vec3& r,
                                        const Vec3& s);

/// @brief The interior candidate of point_triangle_distance_squared: the
///        squared distance from p to its projection onto the plane of abc when
///        that falls inside the triangle, else +infinity. The full distance is
///        the least of this and p's distances to the three edges.
double point_triangle_interior_distance_squared(const Vec3& p, const Vec3& a, const Vec3& b,
                                                const Vec3& c);

/// @brief The interior candidate of segment_segment_distance_squared: the
///        squared distance between the closest points strictly inside both
///        segments when those exist, else +infinity. The full distance is the
///        least of this and the four endpoint-to-segment distances.
double segment_segment_interior_distance_squared(const Vec3& p, const Vec3& q, const Vec3& r,
                                                 const Vec3& s);

} // namespace usdksl
