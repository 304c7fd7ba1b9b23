#pragma once
/// @file triangle_triangle_static.hpp
/// @brief Static (single instant) triangle-triangle intersection.

#include "usdksl/types.hpp"

#include <array>

namespace usdksl {

/// @brief True when closed triangles A and B intersect or come within
///        `thickness` (scene units) of each other. Exact for thickness 0 on
///        coplanar and touching configurations (robust orientation predicates).
bool triangles_intersect_static(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b,
                                double thickness);

} // namespace usdksl
