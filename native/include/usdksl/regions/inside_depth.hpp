#pragma once
/// @file inside_depth.hpp
/// @brief How deep a set of triangles goes into a closed mesh: the largest
///        distance to the closed surface of any point of the triangles that
///        lies inside it, found by branch and bound over each triangle.
///
/// The function f(p) = max(0, signed distance from p to the surface, positive
/// inside) is 1-Lipschitz, so on a sub-triangle with centroid c and corners
/// v_i it is at most f(c) + max_i |c - v_i|. It is also at most the distance
/// from p to any one triangle s of the surface, a convex function of p, whose
/// largest value on the sub-triangle is at a corner: at most max_i |v_i - s|.
/// A sub-triangle is split at its edge midpoints into four while the smaller
/// of the two bounds exceeds the best depth found so far by more than the
/// accuracy; one that meets no surface triangle (exact test) lies wholly on
/// one side, and is dropped when its centroid is outside. The search is
/// best-first over all the triangles at once, so a deep point found on one
/// triangle prunes the others.

#include "usdksl/regions/closed_surface.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief Accuracy of the depth, as a fraction of the longest edge of the
///        triangle (of the penetrating side) on which the deepest point lies
///        (dimensionless): the reported depth d satisfies d <= true depth <=
///        d + DEPTH_RELATIVE_ACCURACY * that edge, plus the rounding of the
///        distance arithmetic (a few units in the last place of the
///        coordinates), given a correct inside test (closed_surface.hpp).
///        1% of an edge is well inside the faceting of any cloth or collider
///        mesh, and costs a few dozen distance queries along a crossing.
constexpr double DEPTH_RELATIVE_ACCURACY = 0.01;

/// @brief Midpoint splits a sub-triangle may go through (a backstop: the
///        accuracy stops the splitting after about log2(1 /
///        DEPTH_RELATIVE_ACCURACY) = 7 levels; this bounds the work on
///        inputs with non-finite coordinates).
constexpr int32_t DEPTH_MAX_SPLITS = 30;

/// @brief The deepest point found and the box of the points found inside.
struct InsideDepth {
    /// @brief Largest depth found (scene units), 0 when no point is inside.
    double depth = 0.0;
    /// @brief Where it is (meaningful when any_inside).
    Vec3 deepest = Vec3::Zero();
    /// @brief True when some evaluated point (a corner or a sub-triangle's
    ///        centroid) lies inside.
    bool any_inside = false;
    /// @brief World-space box of the evaluated points found inside.
    Vec3 inside_min = Vec3::Zero();
    Vec3 inside_max = Vec3::Zero();
    /// @brief Signed distances evaluated (the search's work).
    int64_t evaluations = 0;
};

/// @brief The largest depth inside `surface` of any point of `triangles`
///        (within DEPTH_RELATIVE_ACCURACY, see there). Deterministic: the
///        same triangles in the same order give the same answer.
InsideDepth deepest_inside(const ClosedSurface& surface, const std::vector<std::array<Vec3, 3>>& triangles);

} // namespace usdksl
