#pragma once
/// @file rounding_bounds.hpp
/// @brief The bounds a float corner value of the distance function F must
///        clear to exclude the thickness, shared by the root search and the
///        whole-step filter in front of it: the filter may exclude only what
///        the search would, so both take them from here.

#include "usdksl/ccd/ccd_constants.hpp"
#include "usdksl/types.hpp"

#include <algorithm>
#include <cmath>

namespace usdksl {

/// @brief Rounding bound (scene units) of one float corner value of F along
///        a world axis whose input coordinates are at most `max_abs` in size.
inline double corner_error(double max_abs) {
    return std::max(CCD_CORNER_ERROR_FACTOR * max_abs, CCD_MIN_ABSOLUTE_ERROR);
}

/// @brief What a float corner value along a world axis must exceed (in
///        size) to exclude |F_k| <= thickness: the thickness, the corner's
///        rounding `error` (corner_error) and inflation for this sum's own.
inline double axis_bound(double thickness, double error) { return (thickness + error) * CCD_BOUND_INFLATION; }

/// @brief What the float value n.F, n = `unit_ish` (largest component 1),
///        must exceed (in size) to exclude F from a region whose extent
///        along n is at most thickness * `length` (length already inflated:
///        |n|_2 for the thickness ball, |n|_1 for the cube): per axis the
///        corner's `error` and the dot product's rounding, with |F_k| <=
///        6 max_abs[k] (the corner magnitude bound) and gamma_3 < 4u.
inline double direction_bound(const Vec3& unit_ish, double length, double thickness, const double error[3],
                              const double max_abs[3]) {
    double error_bound = 0.0;
    for (int k = 0; k < 3; ++k) {
        error_bound += std::abs(unit_ish[k]) *
                       (error[k] + 4.0 * DOUBLE_UNIT_ROUNDOFF * (6.0 * max_abs[k] + error[k]));
    }
    return (thickness * length + error_bound) * CCD_BOUND_INFLATION;
}

} // namespace usdksl
