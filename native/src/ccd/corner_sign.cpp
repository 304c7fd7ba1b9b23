/// @file corner_sign.cpp
/// @brief The exact corner sign: a float filter with a running error bound,
///        expansion arithmetic behind it.

#include "usdksl/ccd/corner_sign.hpp"

#include "usdksl/ccd/ccd_constants.hpp"
#include "usdksl/geometry/expansion_arithmetic.hpp"

#include <cmath>

namespace usdksl {
namespace {

struct Difference {
    double coefficient;
    int plus, minus;
};

void differences_of(const CornerAxis& axis, double u, double v, Difference out[3]) {
    out[0] = {1.0, axis.pairs.w_plus, axis.pairs.w_minus};
    out[1] = {-u, axis.pairs.e1_plus, axis.pairs.e1_minus};
    out[2] = {-v, axis.pairs.e2_plus, axis.pairs.e2_minus};
}

} // namespace

int exact_corner_sign(const CornerAxis& axis, double t, double u, double v, double offset_sign) {
    const int filtered = filtered_corner_sign(axis, t, u, v, offset_sign);
    return filtered != CORNER_SIGN_UNDECIDED ? filtered : expanded_corner_sign(axis, t, u, v, offset_sign);
}

/// F = sum over the three differences of coefficient x D(t), with D(t) =
/// (1 - t) ds + t de and ds, de the differences of the two points' start
/// and end coordinates. A D that is exactly zero (ds = de = 0, ds = 0 at
/// t = 0, de = 0 at t = 1; a difference of doubles is zero exactly when they
/// are equal) drops out; when all drop out the sign is offset_sign's
/// (thickness + guard > 0). Otherwise F + offset_sign x thickness is
/// evaluated in floating point with a running bound on its rounding error:
/// the rounded result r of each operation is off by at most
/// DOUBLE_UNIT_ROUNDOFF x |r| (plus an underflow far below
/// FILTERED_SIGN_MIN_MARGIN), and the operands' errors are carried along.
/// Differences are taken first, so the bound follows the size of the
/// differences, not of the coordinates (the root finder's float corners are
/// bounded by the coordinates' size; this is where it cannot tell). The sign
/// is taken only when the value clears the bound, inflated for its own
/// rounding, by FILTERED_SIGN_MIN_MARGIN: the exact value is then that far
/// from zero, beyond the guard CCD_MIN_ABSOLUTE_ERROR and any underflow of
/// the expansions, which give the same sign.
int filtered_corner_sign(const CornerAxis& axis, double t, double u, double v, double offset_sign) {
    constexpr double unit = DOUBLE_UNIT_ROUNDOFF;
    Difference differences[3];
    differences_of(axis, u, v, differences);
    double sum = 0.0, error = 0.0;
    bool all_zero = true;
    for (const Difference& difference : differences) {
        if (difference.coefficient == 0.0) continue;
        const double ds = axis.start[difference.plus] - axis.start[difference.minus];
        const double de = axis.end[difference.plus] - axis.end[difference.minus];
        if ((ds == 0.0 && (de == 0.0 || t == 0.0)) || (de == 0.0 && t == 1.0)) continue;
        all_zero = false;
        const double ds_error = unit * std::abs(ds);
        const double change = de - ds;
        const double change_error = ds_error + unit * std::abs(de) + unit * std::abs(change);
        const double moved = t * change;
        const double moved_error = t * change_error + unit * std::abs(moved);
        const double at = ds + moved;
        const double at_error = ds_error + moved_error + unit * std::abs(at);
        const double term = difference.coefficient * at;
        sum = sum + term;
        error += std::abs(difference.coefficient) * at_error + unit * std::abs(term) + unit * std::abs(sum);
    }
    if (all_zero) return offset_sign > 0.0 ? 1 : -1;
    sum = sum + offset_sign * axis.thickness;
    error += unit * std::abs(sum);
    const double margin = error * FILTERED_SIGN_BOUND_INFLATION + FILTERED_SIGN_MIN_MARGIN;
    if (sum > margin) return 1;
    if (sum < -margin) return -1;
    return CORNER_SIGN_UNDECIDED;
}

/// Every product an error-free transform. The guard CCD_MIN_ABSOLUTE_ERROR
/// covers products that underflow. Terms whose exact value is known without
/// products are simplified exactly (the sum, hence the sign, is unchanged):
/// a difference of two points with equal start and end coordinates is zero,
/// and a position is s at t = 0 or when the point holds still on this axis
/// (s = e), and e at t = 1.
int expanded_corner_sign(const CornerAxis& axis, double t, double u, double v, double offset_sign) {
    expansion::ExactSum sum;
    Difference differences[3];
    differences_of(axis, u, v, differences);
    for (const Difference& difference : differences) {
        if (difference.coefficient == 0.0) continue;
        if (axis.start[difference.plus] == axis.start[difference.minus] &&
            axis.end[difference.plus] == axis.end[difference.minus])
            continue;
        for (const int point : {difference.plus, difference.minus}) {
            const double c = point == difference.plus ? difference.coefficient : -difference.coefficient;
            const double s = axis.start[point], e = axis.end[point];
            if (t == 0.0 || s == e) {
                sum.add_product(c, s);
            } else if (t == 1.0) {
                sum.add_product(c, e);
            } else {
                sum.add_product(c, s);
                sum.add_triple_product(c, t, e);
                sum.add_triple_product(c, t, s, -1.0);
            }
        }
    }
    sum.add(offset_sign * axis.thickness);
    sum.add(offset_sign * CCD_MIN_ABSOLUTE_ERROR);
    return sum.sign();
}

} // namespace usdksl
