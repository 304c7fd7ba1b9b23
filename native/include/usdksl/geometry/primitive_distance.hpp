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

} // namespace usdksl
