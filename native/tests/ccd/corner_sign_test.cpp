/// @file corner_sign_test.cpp
/// @brief The float filter in front of the exact corner sign never gives a
///        sign the expansions would not, on corners built to sit at or near
///        zero, where a filter with too small an error bound goes wrong.

#include "usdksl/ccd/corner_sign.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

using namespace usdksl;

namespace {

/// Vertex-face point order of the root finder: W = p - a, E1 = b - a, E2 = c - a.
CornerAxis vertex_face_axis(double thickness) {
    CornerAxis axis{};
    axis.pairs = PairIndices{0, 1, 2, 1, 3, 1};
    axis.thickness = thickness;
    return axis;
}

/// A parameter the root finder may ask at: an end, a dyadic split point or a
/// clipped (arbitrary) value.
double parameter(std::mt19937_64& random) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    switch (random() % 4) {
    case 0: return static_cast<double>(random() % 2);
    case 1: return std::ldexp(static_cast<double>(random() % 1024), -10);
    default: return unit(random);
    }
}

/// Coordinates of a magnitude-`scale` point nearly shared by all four
/// points: offsets of a few units in the last place, or far below them, so
/// that F sits within rounding of zero.
double near(double base, std::mt19937_64& random) {
    const int64_t ulps = static_cast<int64_t>(random() % 9) - 4;
    double value = base;
    for (int64_t i = 0; i < std::llabs(ulps); ++i) value = std::nextafter(value, ulps > 0 ? INFINITY : -INFINITY);
    return value;
}

struct Tally {
    int64_t decided = 0;
    int64_t undecided = 0;
};

void expect_agreement(const CornerAxis& axis, double t, double u, double v, Tally& tally) {
    for (const double offset_sign : {-1.0, 1.0}) {
        const int exact = expanded_corner_sign(axis, t, u, v, offset_sign);
        const int filtered = filtered_corner_sign(axis, t, u, v, offset_sign);
        if (filtered == CORNER_SIGN_UNDECIDED) {
            ++tally.undecided;
        } else {
            ++tally.decided;
            ASSERT_EQ(filtered, exact) << "t=" << t << " u=" << u << " v=" << v << " offset " << offset_sign;
        }
        ASSERT_EQ(exact_corner_sign(axis, t, u, v, offset_sign), exact);
    }
}

} // namespace

TEST(CornerSign, FilterAgreesWithExpansionsOnNearlySharedCoordinates) {
    std::mt19937_64 random(20261123);
    std::uniform_real_distribution<double> magnitude(-3.0, 3.0);
    Tally tally;
    for (int trial = 0; trial < 200000; ++trial) {
        const double scale = std::pow(10.0, magnitude(random));
        const double start_base = scale * (0.5 + 0.5 * std::generate_canonical<double, 53>(random));
        const double end_base = random() % 3 == 0 ? start_base : start_base * (1.0 + 1e-3 * (random() % 7));
        CornerAxis axis = vertex_face_axis(random() % 2 ? 0.0 : std::ldexp(scale, -60));
        for (int i = 0; i < 4; ++i) {
            axis.start[i] = near(start_base, random);
            axis.end[i] = random() % 4 == 0 ? axis.start[i] : near(end_base, random);
        }
        expect_agreement(axis, parameter(random), parameter(random), parameter(random), tally);
        if (HasFatalFailure()) return;
    }
    // Both sides ran: the filter decided most corners and left some to the expansions.
    EXPECT_GT(tally.decided, 10 * tally.undecided);
    EXPECT_GT(tally.undecided, 100);
}

TEST(CornerSign, FilterAgreesWhereThePointCrossesThePlaneAtTheCorner) {
    // The vertex passes through the face's plane (all face corners share the
    // coordinate) at time t_cross; a corner at or right next to t_cross has F
    // at or within rounding of zero, with either sign.
    std::mt19937_64 random(7);
    Tally tally;
    for (int trial = 0; trial < 100000; ++trial) {
        const double plane = std::ldexp(static_cast<double>(random() % 4096 + 1), -11) * (random() % 2 ? 1.0 : -1.0);
        const double depth = std::ldexp(1.0, -static_cast<int>(random() % 40));
        CornerAxis axis = vertex_face_axis(0.0);
        for (int i = 1; i < 4; ++i) {
            axis.start[i] = plane;
            axis.end[i] = random() % 2 ? plane : near(plane, random);
        }
        axis.start[0] = plane + depth * std::generate_canonical<double, 53>(random);
        axis.end[0] = plane - depth * std::generate_canonical<double, 53>(random);
        const double ds = axis.start[0] - plane, de = axis.end[0] - plane;
        const double crossing = ds / (ds - de);
        for (const double t : {crossing, std::nextafter(crossing, 0.0), std::nextafter(crossing, 1.0)}) {
            expect_agreement(axis, t, parameter(random), parameter(random), tally);
            if (HasFatalFailure()) return;
        }
    }
    EXPECT_GT(tally.undecided, 100);
}

TEST(CornerSign, ExactlyZeroDifferencesGiveTheOffsetsSign) {
    // Every point shares its coordinate at both ends: F is zero, and a touch
    // at distance exactly the thickness counts, so neither side is beyond it.
    CornerAxis axis = vertex_face_axis(0.0);
    for (int i = 0; i < 4; ++i) axis.start[i] = axis.end[i] = 0.3;
    EXPECT_EQ(filtered_corner_sign(axis, 0.37, 0.2, 0.1, -1.0), -1);
    EXPECT_EQ(filtered_corner_sign(axis, 0.37, 0.2, 0.1, 1.0), 1);
    // W is zero at the start only: zero at t = 0, not at t > 0.
    axis.end[0] = 0.5;
    EXPECT_EQ(filtered_corner_sign(axis, 0.0, 0.2, 0.1, -1.0), -1);
    EXPECT_EQ(expanded_corner_sign(axis, 0.25, 0.2, 0.1, -1.0), 1);
    EXPECT_EQ(filtered_corner_sign(axis, 0.25, 0.2, 0.1, -1.0), 1);
}
