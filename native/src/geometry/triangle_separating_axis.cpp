#include "usdksl/geometry/triangle_separating_axis.hpp"

#include "usdksl/geometry/rounding.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace usdksl {
namespace {

/// True when the corners of a and b, projected on d in floating point, are
/// apart by more than the projections' rounding can close.
bool apart_along(const Vec3& d, const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b, double magnitude) {
    // The absolute term covers products that underflow, where rounding is not relative.
    const double error = SEPARATING_AXIS_ERROR_UNITS * (DOUBLE_UNIT_ROUNDOFF * d.lpNorm<1>() * magnitude +
                                                        std::numeric_limits<double>::denorm_min());
    // NaN anywhere fails every comparison below: not proven apart.
    if (!(error > 0.0) || !std::isfinite(error)) return false;
    double low_a = d.dot(a[0]), high_a = low_a, low_b = d.dot(b[0]), high_b = low_b;
    for (int i = 1; i < 3; ++i) {
        const double pa = d.dot(a[i]), pb = d.dot(b[i]);
        low_a = std::min(low_a, pa);
        high_a = std::max(high_a, pa);
        low_b = std::min(low_b, pb);
        high_b = std::max(high_b, pb);
    }
    // Each side's true extreme lies within `error` of its float one; the
    // subtraction rounds by far less than the spare `error`.
    return low_b - high_a > 3.0 * error || low_a - high_b > 3.0 * error;
}

/// True when a direction from triangle t (its normal, or one of its edges'
/// normals within its plane) separates it from the other triangle.
bool apart_along_axes_of(const std::array<Vec3, 3>& t, const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b,
                         double magnitude) {
    const Vec3 normal = (t[1] - t[0]).cross(t[2] - t[0]);
    if (apart_along(normal, a, b, magnitude)) return true;
    for (int i = 0; i < 3; ++i) {
        if (apart_along(normal.cross(t[(i + 1) % 3] - t[i]), a, b, magnitude)) return true;
    }
    return false;
}

} // namespace

bool triangles_apart_along_an_axis(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b, double magnitude) {
    return apart_along_axes_of(a, a, b, magnitude) || apart_along_axes_of(b, a, b, magnitude);
}

} // namespace usdksl
