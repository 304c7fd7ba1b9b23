/// @file tested_primitive_distance_test.cpp
/// @brief tested_primitive_distance, which measures each vertex-to-edge
///        distance once for all the pairs it serves, equals bit for bit the
///        least distance of every tested vertex-face and edge-edge pair
///        measured on its own.

#include "usdksl/geometry/primitive_distance.hpp"
#include "usdksl/narrow_phase/pair_clearance.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

using namespace usdksl;

namespace {

using Positions = std::array<Vec3, 3>;

bool holds(const Triangle& ids, int32_t v) { return ids[0] == v || ids[1] == v || ids[2] == v; }

/// Each tested pair on its own, as the narrow phase sees them.
double each_pair_on_its_own(const Triangle& ids_a, const Positions& a, const Triangle& ids_b, const Positions& b,
                            bool same_mesh) {
    double squared = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) {
        if (!(same_mesh && holds(ids_b, ids_a[i])))
            squared = std::min(squared, point_triangle_distance_squared(a[i], b[0], b[1], b[2]));
        if (!(same_mesh && holds(ids_a, ids_b[i])))
            squared = std::min(squared, point_triangle_distance_squared(b[i], a[0], a[1], a[2]));
    }
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            const int32_t e0 = ids_a[i], e1 = ids_a[(i + 1) % 3], f0 = ids_b[j], f1 = ids_b[(j + 1) % 3];
            if (same_mesh && (e0 == f0 || e0 == f1 || e1 == f0 || e1 == f1)) continue;
            squared = std::min(squared, segment_segment_distance_squared(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]));
        }
    }
    return std::sqrt(squared);
}

/// A point uniform in the cube [-1, 1]^3.
Vec3 random_point(std::mt19937& random) {
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const double x = unit(random), y = unit(random), z = unit(random);
    return Vec3(x, y, z);
}

} // namespace

TEST(TestedPrimitiveDistance, EqualsEveryTestedPairMeasuredOnItsOwn) {
    std::mt19937 random(20261123);
    const auto point = [&]() { return random_point(random); };
    // No shared vertex, one shared vertex (at each corner), a shared edge;
    // and degenerate shapes: a repeated point, collinear corners.
    const std::array<Triangle, 5> ids_b_cases = {Triangle{3, 4, 5}, Triangle{4, 0, 5}, Triangle{3, 5, 2},
                                                 Triangle{1, 0, 5}, Triangle{2, 5, 1}};
    int cases = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const Triangle ids_a{0, 1, 2};
        const Triangle& ids_b = ids_b_cases[trial % ids_b_cases.size()];
        Positions a{point(), point(), point()};
        if (trial % 7 == 0) a[2] = a[1];                              // zero area: a repeated corner
        if (trial % 11 == 0) a[2] = 0.5 * (a[0] + a[1]);              // zero area: collinear corners
        Positions b{point(), point(), point()};
        for (int j = 0; j < 3; ++j) {
            for (int i = 0; i < 3; ++i) {
                if (ids_b[j] == ids_a[i]) b[j] = a[i];  // a shared vertex sits where it is in A
            }
        }
        for (bool same_mesh : {true, false}) {
            EXPECT_EQ(tested_primitive_distance(ids_a, a, ids_b, b, same_mesh),
                      each_pair_on_its_own(ids_a, a, ids_b, b, same_mesh))
                << "trial " << trial << " same mesh " << same_mesh;
            ++cases;
        }
    }
    EXPECT_EQ(cases, 4000);
}

TEST(TestedPrimitiveDistance, StopsEarlyOnlyWithinTheDistanceAsked) {
    std::mt19937 random(20261124);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const auto point = [&]() { return random_point(random); };
    const Triangle ids_a{0, 1, 2}, ids_b{3, 4, 5};
    int stopped = 0, measured = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const Positions a{point(), point(), point()};
        const Vec3 offset = 1.5 * point();
        const Positions b{point() + offset, point() + offset, point() + offset};
        const double smallest = tested_primitive_distance(ids_a, a, ids_b, b, false);
        const double within = 0.5 * (unit(random) + 1.0);
        const double answer = tested_primitive_distance(ids_a, a, ids_b, b, false, within);
        EXPECT_EQ(answer <= within, smallest <= within) << "trial " << trial;
        EXPECT_GE(answer, smallest) << "trial " << trial;
        if (smallest > within) {
            EXPECT_EQ(answer, smallest) << "trial " << trial;
            ++measured;
        } else {
            stopped += answer > smallest;
        }
    }
    // Both outcomes occur, and stopping early does happen.
    EXPECT_GT(measured, 200);
    EXPECT_GT(stopped, 50);
}

TEST(InPlaneGap, NeverExceedsTheDistanceOfTheTriangles) {
    std::mt19937 random(20261125);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const Triangle ids_a{0, 1, 2}, ids_b{3, 4, 5};
    int separated = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        // Mostly two triangles of one plane (a flat sheet), some tilted out of it.
        const double tilt = trial % 4 == 0 ? 0.3 : 0.0;
        const auto point = [&]() -> Vec3 {
            const double x = 2.0 * unit(random), y = 2.0 * unit(random);
            return Vec3(x, y, tilt * unit(random));
        };
        const Positions a{point(), point(), point()};
        const Positions b{point(), point(), point()};
        // Untouched by the narrow phase's exclusions (no shared vertex), this
        // is the distance between the two triangles (when they do not cross).
        const double distance = tested_primitive_distance(ids_a, a, ids_b, b, false);
        const double gap = in_plane_gap(a, b);
        EXPECT_LE(gap, distance * (1.0 + 1e-12) + 1e-12) << "trial " << trial;
        separated += gap > 0.0;
    }
    EXPECT_GT(separated, 200);
}
