#pragma once
/// @file rounding.hpp
/// @brief Floating-point rounding bounds of the geometry floor (the CCD error
///        bounds in ccd/ccd_constants.hpp build on them).

namespace usdksl {

/// @brief Unit roundoff of IEEE double (2^-53), dimensionless.
constexpr double DOUBLE_UNIT_ROUNDOFF = 1.1102230246251565e-16;

/// @brief Relative slack (to the largest absolute coordinate) added to
///        thickness in the static distance tests, covering the rounding of
///        closest-point computations; errs toward reporting contact.
constexpr double STATIC_DISTANCE_RELATIVE_SLACK = 1e-12;

} // namespace usdksl
