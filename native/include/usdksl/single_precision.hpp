#pragma once
/// @file single_precision.hpp
/// @brief Bounds kept in single precision, rounded the safe way: a float
///        rounds to nearest, so a bound would otherwise shrink or grow by up
///        to half a unit in the last place.

#include <cmath>

namespace usdksl {

/// @brief The least float at or above `value` (scene units or any; NaN stays NaN).
inline float float_at_least(double value) {
    float rounded = static_cast<float>(value);
    if (static_cast<double>(rounded) < value) rounded = std::nextafter(rounded, INFINITY);
    return rounded;
}

/// @brief The greatest float at or below `value` (NaN stays NaN).
inline float float_at_most(double value) {
    float rounded = static_cast<float>(value);
    if (static_cast<double>(rounded) > value) rounded = std::nextafter(rounded, -INFINITY);
    return rounded;
}

} // namespace usdksl
