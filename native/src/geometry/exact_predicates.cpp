/// @file exact_predicates.cpp
/// @brief Orientation predicates: a static floating-point filter, and an exact
///        expansion sum of the determinant's monomials when the filter fails.

#include "usdksl/geometry/exact_predicates.hpp"

#include "usdksl/geometry/expansion_arithmetic.hpp"

#include "usdksl/geometry/rounding.hpp"

#include <cmath>

namespace usdksl {
namespace {

/// Relative error bounds of the filtered determinants (Shewchuk 1997,
/// "Adaptive Precision Floating-Point Arithmetic", bounds A of orient2d/3d).
constexpr double ORIENT2D_FILTER_BOUND = (3.0 + 16.0 * DOUBLE_UNIT_ROUNDOFF) * DOUBLE_UNIT_ROUNDOFF;
constexpr double ORIENT3D_FILTER_BOUND = (7.0 + 56.0 * DOUBLE_UNIT_ROUNDOFF) * DOUBLE_UNIT_ROUNDOFF;

/// Adds sign * det2(x, y) = sign * (x0 y1 - x1 y0) exactly.
void add_det2(expansion::ExactSum& sum, const Point2& x, const Point2& y, double sign) {
    sum.add_product(x.x, y.y, sign);
    sum.add_product(x.y, y.x, -sign);
}

/// Adds sign * x . (y cross z) exactly.
void add_det3(expansion::ExactSum& sum, const Vec3& x, const Vec3& y, const Vec3& z, double sign) {
    sum.add_triple_product(x[0], y[1], z[2], sign);
    sum.add_triple_product(x[0], y[2], z[1], -sign);
    sum.add_triple_product(x[1], y[2], z[0], sign);
    sum.add_triple_product(x[1], y[0], z[2], -sign);
    sum.add_triple_product(x[2], y[0], z[1], sign);
    sum.add_triple_product(x[2], y[1], z[0], -sign);
}

int sign_of(double value) { return value > 0.0 ? 1 : (value < 0.0 ? -1 : 0); }

} // namespace

int orient2d(const Point2& a, const Point2& b, const Point2& c) {
    const double left = (a.x - c.x) * (b.y - c.y);
    const double right = (a.y - c.y) * (b.x - c.x);
    const double det = left - right;
    const double bound = ORIENT2D_FILTER_BOUND * (std::abs(left) + std::abs(right));
    if (det > bound || -det > bound) return sign_of(det);
    // A product with a zero factor is exactly zero (a difference of doubles
    // is zero only for equal ones): points on an axis-parallel line, such as
    // a flat cloth seen along an axis of its plane, need no expansions.
    if ((a.x == c.x || b.y == c.y) && (a.y == c.y || b.x == c.x)) return 0;
    // det2(a-c, b-c) = det2(a,b) - det2(c,b) - det2(a,c): exact in the raw coordinates.
    expansion::ExactSum sum;
    add_det2(sum, a, b, 1.0);
    add_det2(sum, c, b, -1.0);
    add_det2(sum, a, c, -1.0);
    return sum.sign();
}

int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const double adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2];
    const double bdx = b[0] - d[0], bdy = b[1] - d[1], bdz = b[2] - d[2];
    const double cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
    const double bdycdz = bdy * cdz, bdzcdy = bdz * cdy;
    const double cdyadz = cdy * adz, cdzady = cdz * ady;
    const double adybdz = ady * bdz, adzbdy = adz * bdy;
    const double det = adx * (bdycdz - bdzcdy) + bdx * (cdyadz - cdzady) + cdx * (adybdz - adzbdy);
    const double permanent = (std::abs(bdycdz) + std::abs(bdzcdy)) * std::abs(adx) +
                             (std::abs(cdyadz) + std::abs(cdzady)) * std::abs(bdx) +
                             (std::abs(adybdz) + std::abs(adzbdy)) * std::abs(cdx);
    const double bound = ORIENT3D_FILTER_BOUND * permanent;
    if (det > bound || -det > bound) return sign_of(det);
    // Four points sharing one coordinate lie in an axis plane: the determinant
    // is exactly zero (flat cloth at rest hits this for every pair).
    for (int k = 0; k < 3; ++k) {
        if (a[k] == d[k] && b[k] == d[k] && c[k] == d[k]) return 0;
    }
    // det3(a-d, b-d, c-d) = [a,b,c] - [d,b,c] - [a,d,c] - [a,b,d] (multilinearity).
    expansion::ExactSum sum;
    add_det3(sum, a, b, c, 1.0);
    add_det3(sum, d, b, c, -1.0);
    add_det3(sum, a, d, c, -1.0);
    add_det3(sum, a, b, d, -1.0);
    return sum.sign();
}

} // namespace usdksl
