#pragma once
/// @file triangle_separating_axis.hpp
/// @brief A floating-point proof that two triangles are disjoint: a direction
///        along which one lies wholly beyond the other by more than the
///        rounding of the projections. It needs no exact arithmetic, so it
///        spares the exact incidence tests the many nearly coplanar pairs of
///        flat cloth that lie side by side.

#include "usdksl/types.hpp"

#include <array>

namespace usdksl {

/// @brief Bound, in units of the double unit roundoff, on the error of one
///        projection d . p computed in floating point, relative to
///        |d|_1 times the largest absolute coordinate (three products and two
///        sums make it at most 3 units; the rest is headroom).
constexpr double SEPARATING_AXIS_ERROR_UNITS = 8.0;

/// @brief True when some tried direction (either triangle's normal, or the
///        normal of one of its edges within its plane) has the projections of
///        B's corners all beyond those of A's, or all before them, by more
///        than twice the projection error bound: the closed triangles are then
///        disjoint. False says nothing (they may still be disjoint); never
///        true for triangles that touch. `magnitude`: at least the largest
///        absolute coordinate of the six corners (scene units).
bool triangles_apart_along_an_axis(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b, double magnitude);

} // namespace usdksl
