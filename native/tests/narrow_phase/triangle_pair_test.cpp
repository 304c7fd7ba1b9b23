/// @file triangle_pair_test.cpp
/// @brief Triangle pairs: shared vertices are never contacts; a crossing is.

#include "usdksl/narrow_phase/triangle_pair.hpp"

#include <gtest/gtest.h>

using namespace usdksl;

namespace {

MovingTriangle still(Triangle ids, Vec3 a, Vec3 b, Vec3 c) { return {ids, {a, b, c}, {a, b, c}}; }

} // namespace

TEST(TrianglePair, NeighboursSharingAnEdgeNeverTouchThroughIt) {
    CCDSettings settings;
    const MovingTriangle left = still({0, 1, 2}, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0));
    const MovingTriangle right = still({1, 3, 2}, Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0));
    EXPECT_FALSE(triangle_pair_ccd(left, right, true, settings).hit);
    // Other meshes with the same coordinates do touch.
    EXPECT_TRUE(triangle_pair_ccd(left, right, false, settings).hit);
}

TEST(TrianglePair, TunnellingTriangleIsFoundAtTheCrossing) {
    CCDSettings settings;
    const MovingTriangle plane = still({0, 1, 2}, Vec3(-2, -2, 0), Vec3(4, -2, 0), Vec3(-2, 4, 0));
    const MovingTriangle bullet{{0, 1, 2},
                                {Vec3(0.1, 0.1, 1), Vec3(0.2, 0.1, 1), Vec3(0.1, 0.2, 1)},
                                {Vec3(0.1, 0.1, -1), Vec3(0.2, 0.1, -1), Vec3(0.1, 0.2, -1)}};
    const TrianglePairContact hit = triangle_pair_ccd(plane, bullet, false, settings);
    ASSERT_TRUE(hit.hit);
    EXPECT_LE(hit.toi, 0.5);
    EXPECT_GE(hit.toi, 0.5 - settings.tolerance);
    EXPECT_FALSE(hit.undecided);
}

TEST(TrianglePair, StaticTestSeesTouchingAndApartTriangles) {
    const std::array<Vec3, 3> a{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    const std::array<Vec3, 3> crossing{Vec3(0.2, 0.2, -1), Vec3(0.2, 0.2, 1), Vec3(0.3, 0.25, 0)};
    const std::array<Vec3, 3> apart{Vec3(0.2, 0.2, 0.5), Vec3(0.3, 0.2, 0.5), Vec3(0.2, 0.3, 0.5)};
    EXPECT_TRUE(triangle_pair_intersect_static({0, 1, 2}, a, {3, 4, 5}, crossing, false, 0.0));
    EXPECT_FALSE(triangle_pair_intersect_static({0, 1, 2}, a, {3, 4, 5}, apart, false, 0.0));
    EXPECT_TRUE(triangle_pair_intersect_static({0, 1, 2}, a, {3, 4, 5}, apart, false, 0.51));
}
