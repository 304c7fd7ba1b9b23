#pragma once
/// @file closest_feature.hpp
/// @brief The point of a triangle closest to a point, and which feature
///        (interior, edge or corner) it lies on: the inside test of a closed
///        mesh takes the normal of that feature.

#include "usdksl/types.hpp"

#include <cstdint>

namespace usdksl {

/// @brief Where on triangle (a, b, c) a closest point lies.
enum class TriangleFeature : int8_t {
    Interior = 0,
    Corner0 = 1,  ///< @brief vertex a
    Corner1 = 2,  ///< @brief vertex b
    Corner2 = 3,  ///< @brief vertex c
    Edge01 = 4,   ///< @brief edge a-b (open)
    Edge12 = 5,   ///< @brief edge b-c (open)
    Edge20 = 6,   ///< @brief edge c-a (open)
};

/// @brief A closest point and its feature; distance_squared in scene units squared.
struct ClosestOnTriangle {
    Vec3 point = Vec3::Zero();
    double distance_squared = 0.0;
    TriangleFeature feature = TriangleFeature::Interior;
};

/// @brief The point of closed triangle abc closest to p (Ericson, Real-Time
///        Collision Detection 5.1.5: Voronoi regions by barycentric signs),
///        floating point. A zero-area triangle yields a corner or an edge.
ClosestOnTriangle closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

} // namespace usdksl
