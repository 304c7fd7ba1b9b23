/// @file geometry_test.cpp
/// @brief Exact predicates decide signs a naive double determinant gets
///        wrong; distances and the static triangle test match hand-computed cases.

#include "usdksl/geometry/exact_geometry.hpp"
#include "usdksl/geometry/exact_predicates.hpp"
#include "usdksl/geometry/primitive_distance.hpp"
#include "usdksl/geometry/triangle_triangle_static.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>

using namespace usdksl;

TEST(ExactPredicates, Orient3dSignsAndPermutations) {
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    const int above = orient3d(a, b, c, Vec3(0, 0, 1));
    const int below = orient3d(a, b, c, Vec3(0, 0, -1));
    EXPECT_NE(above, 0);
    EXPECT_EQ(below, -above);
    EXPECT_EQ(orient3d(b, a, c, Vec3(0, 0, 1)), -above) << "swapping two points flips the sign";
    EXPECT_EQ(orient3d(a, b, c, Vec3(0.25, 0.5, 0)), 0);
}

TEST(ExactPredicates, Orient2dOnSharedCoordinatesMatchesIntegerDeterminants) {
    // Small integer coordinates, many shared: integer arithmetic gives the
    // exact sign. The zeros where points share an x or a y are the cases the
    // shortcut on equal coordinates decides (a case where only one product
    // vanishes never reaches it: the float filter decides that one).
    std::mt19937_64 random(11);
    int zeros = 0, signs = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        int64_t v[6];
        for (int64_t& x : v) x = static_cast<int64_t>(random() % 3);
        const Point2 a{static_cast<double>(v[0]), static_cast<double>(v[1])};
        const Point2 b{static_cast<double>(v[2]), static_cast<double>(v[3])};
        const Point2 c{static_cast<double>(v[4]), static_cast<double>(v[5])};
        const int64_t det = (v[0] - v[4]) * (v[3] - v[5]) - (v[1] - v[5]) * (v[2] - v[4]);
        const int expected = det > 0 ? 1 : det < 0 ? -1 : 0;
        ASSERT_EQ(orient2d(a, b, c), expected) << "trial " << trial;
        (expected == 0 ? zeros : signs) += 1;
    }
    EXPECT_GT(zeros, 1000);
    EXPECT_GT(signs, 1000);
}

TEST(ExactPredicates, Orient3dDecidesOneUlpOffThePlane) {
    // Plane x + y + z = 1 through three points; d_up and d_down lie one ulp either side of the rounded z.
    const Vec3 a(1, 0, 0), b(0, 1, 0), c(0, 0, 1);
    const double x = 0.1, y = 0.3;  // not representable exactly: z = 1 - x - y is what rounding gives
    const double z = 1.0 - x - y;
    const Vec3 d_up(x, y, std::nextafter(z, 2.0));
    const Vec3 d_down(x, y, std::nextafter(z, -2.0));
    const int up = orient3d(a, b, c, d_up);
    const int down = orient3d(a, b, c, d_down);
    EXPECT_NE(up, 0);
    EXPECT_NE(down, 0);
    EXPECT_EQ(up, -down) << "points one ulp on either side of the plane lie on opposite sides";
    EXPECT_EQ(orient3d(a, b, c, Vec3(0.25, 0.25, 0.5)), 0) << "an exactly coplanar point is on the plane";
}

TEST(ExactGeometry, DegenerateAndTouchingCases) {
    EXPECT_TRUE(triangle_is_degenerate(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2)));
    EXPECT_FALSE(triangle_is_degenerate(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)));
    // Segments that touch at an end point intersect (closed); parallel disjoint ones do not.
    EXPECT_TRUE(segments_intersect(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0)));
    EXPECT_FALSE(segments_intersect(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)));
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    EXPECT_TRUE(point_in_triangle(Vec3(0.5, 0.5, 0), a, b, c)) << "on the hypotenuse";
    EXPECT_FALSE(point_in_triangle(Vec3(0.5, 0.5, 1e-300), a, b, c)) << "off the plane by a subnormal step";
    EXPECT_TRUE(segment_intersects_triangle(Vec3(0.2, 0.2, -1), Vec3(0.2, 0.2, 1), a, b, c));
    EXPECT_FALSE(segment_intersects_triangle(Vec3(0.6, 0.6, -1), Vec3(0.6, 0.6, 1), a, b, c));
}

TEST(PrimitiveDistance, HandComputedSquaredDistances) {
    EXPECT_DOUBLE_EQ(point_segment_distance_squared(Vec3(0.5, 2, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)), 4.0);
    EXPECT_DOUBLE_EQ(point_segment_distance_squared(Vec3(3, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)), 4.0)
        << "beyond the end: distance to the end point";
    EXPECT_DOUBLE_EQ(point_triangle_distance_squared(Vec3(0.2, 0.2, 3), Vec3(0, 0, 0), Vec3(1, 0, 0),
                                                     Vec3(0, 1, 0)), 9.0);
    EXPECT_DOUBLE_EQ(segment_segment_distance_squared(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, -1, 2),
                                                      Vec3(0.5, 1, 2)), 4.0);
}

TEST(TriangleTriangleStatic, PiercingTouchingAndThickness) {
    const std::array<Vec3, 3> floor{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0)};
    const std::array<Vec3, 3> piercing{Vec3(0.5, 0.5, -1), Vec3(0.5, 0.5, 1), Vec3(0.6, 0.5, 1)};
    const std::array<Vec3, 3> above{Vec3(0.5, 0.5, 0.5), Vec3(0.6, 0.5, 0.5), Vec3(0.5, 0.6, 0.5)};
    const std::array<Vec3, 3> resting{Vec3(0.5, 0.5, 0), Vec3(0.6, 0.5, 1), Vec3(0.5, 0.6, 1)};
    EXPECT_TRUE(triangles_intersect_static(floor, piercing, 0.0));
    EXPECT_TRUE(triangles_intersect_static(floor, resting, 0.0)) << "a vertex on the face touches";
    EXPECT_FALSE(triangles_intersect_static(floor, above, 0.0));
    EXPECT_FALSE(triangles_intersect_static(floor, above, 0.49));
    EXPECT_TRUE(triangles_intersect_static(floor, above, 0.51));
}
