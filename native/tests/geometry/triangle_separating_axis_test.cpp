/// @file triangle_separating_axis_test.cpp
/// @brief The floating-point separating-axis proof never calls triangles
///        apart that the exact incidence tests find meeting, on touching and
///        nearly coplanar pairs under random rotations, and it does prove
///        side-by-side cloth triangles apart.

#include "usdksl/geometry/exact_geometry.hpp"
#include "usdksl/geometry/triangle_separating_axis.hpp"
#include "usdksl/geometry/triangle_triangle_static.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

using namespace usdksl;

namespace {

using TrianglePoints = std::array<Vec3, 3>;

bool edges_meet_exactly(const TrianglePoints& a, const TrianglePoints& b) {
    for (int i = 0; i < 3; ++i) {
        if (segment_intersects_triangle(a[i], a[(i + 1) % 3], b[0], b[1], b[2])) return true;
        if (segment_intersects_triangle(b[i], b[(i + 1) % 3], a[0], a[1], a[2])) return true;
    }
    return false;
}

double magnitude_of(const TrianglePoints& a, const TrianglePoints& b) {
    double magnitude = 0.0;
    for (const TrianglePoints* t : {&a, &b}) {
        for (const Vec3& p : *t) magnitude = std::max(magnitude, p.cwiseAbs().maxCoeff());
    }
    return magnitude;
}

/// Pairs of the kinds flat cloth and contact make, rotated and moved at random
/// so that no coordinate is exact: side by side in one plane (a gap, an
/// overlap, or a corner placed on the other's edge), a corner placed on the
/// other's face, and a corner a rounding error off either side of it.
struct PairTrials {
    std::mt19937 random{20261127};
    std::uniform_real_distribution<double> unit{-1.0, 1.0};

    Vec3 point() { return Vec3(unit(random), unit(random), unit(random)); }

    std::pair<TrianglePoints, TrianglePoints> next(int kind) {
        const TrianglePoints b{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
        TrianglePoints a;
        const double s = std::abs(unit(random)), t = std::abs(unit(random)) * (1.0 - s);
        const Vec3 on_face(s, t, 0.0);
        const Vec3 on_edge(s, 1.0 - s, 0.0);
        const double lift = std::ldexp(unit(random), -50);  // a rounding error above or below
        switch (kind) {
        case 0:  // side by side in the plane: beyond the hypotenuse by a gap, or overlapping it
            a = {on_edge + Vec3(0.3, 0.3, 0) * unit(random), on_edge + Vec3(1.0, 0.2, 0), on_edge + Vec3(0.2, 1.0, 0)};
            break;
        case 1:  // a corner on the hypotenuse, the rest beyond it, in the plane or tilted
            a = {on_edge, on_edge + Vec3(1.0, 0.2, 0.5 * unit(random)), on_edge + Vec3(0.2, 1.0, 0.5 * unit(random))};
            break;
        case 2:  // a corner on the face, or a rounding error off it, the rest above or below
            a = {on_face + Vec3(0, 0, lift), on_face + point() + Vec3(0, 0, 1.5), on_face + point() + Vec3(0, 0, 1.5)};
            if (unit(random) < 0.0) {
                for (Vec3& p : a) p[2] = -p[2];
            }
            break;
        default:  // anywhere near
            a = {point(), point(), point()};
        }
        const Eigen::Matrix3d turn = Eigen::Quaterniond(unit(random), unit(random), unit(random), unit(random))
                                         .normalized()
                                         .toRotationMatrix();
        const Vec3 move = 4.0 * point();
        const double scale = std::ldexp(1.0 + std::abs(unit(random)), static_cast<int>(8 * unit(random)));
        std::pair<TrianglePoints, TrianglePoints> pair;
        for (int i = 0; i < 3; ++i) {
            pair.first[i] = turn * (scale * a[i]) + move;
            pair.second[i] = turn * (scale * b[i]) + move;
        }
        return pair;
    }
};

} // namespace

TEST(TriangleSeparatingAxis, NeverCallsApartTrianglesThatTheExactTestsFindMeeting) {
    PairTrials trials;
    int meeting[4] = {0, 0, 0, 0}, apart[4] = {0, 0, 0, 0};
    for (int trial = 0; trial < 40000; ++trial) {
        const int kind = trial % 4;
        const auto [a, b] = trials.next(kind);
        const bool proven_apart = triangles_apart_along_an_axis(a, b, magnitude_of(a, b));
        const bool meet = edges_meet_exactly(a, b);
        ASSERT_FALSE(proven_apart && meet) << "trial " << trial << ", kind " << kind;
        meeting[kind] += meet;
        apart[kind] += proven_apart;
    }
    // Touching within a rounding error: meeting often, never provable apart.
    for (int kind : {1, 2}) {
        EXPECT_GT(meeting[kind], 500) << "kind " << kind << ": the trials do meet";
        EXPECT_EQ(apart[kind], 0) << "kind " << kind;
    }
    // Side by side in one plane: half overlap (within rounding of the plane,
    // meeting or not as it falls), half lie beyond a gap and are proven apart.
    EXPECT_GT(meeting[0], 500);
    EXPECT_GT(apart[0], 4000);
    // Anywhere near: most pairs that do not meet are proven apart.
    EXPECT_GT(meeting[3], 500);
    EXPECT_GT(apart[3], 4 * (10000 - meeting[3]) / 5) << meeting[3];
}

TEST(TriangleSeparatingAxis, ProvesSideBySideFlatClothApartAndNeverTouchingOnes) {
    // Two cloth triangles of a flat grid one cell apart, and two sharing a corner.
    const TrianglePoints cell{Vec3(0.1, 0.2, 0.3), Vec3(0.11, 0.2, 0.3), Vec3(0.1, 0.21, 0.3)};
    TrianglePoints next_but_one = cell, touching = cell;
    for (Vec3& p : next_but_one) p[0] += 0.02;
    for (Vec3& p : touching) p[0] += 0.01;  // its first corner is cell's second
    EXPECT_TRUE(triangles_apart_along_an_axis(cell, next_but_one, 0.33));
    EXPECT_FALSE(triangles_apart_along_an_axis(cell, touching, 0.33));
    EXPECT_FALSE(triangles_intersect_static(cell, next_but_one, 0.0));
    EXPECT_TRUE(triangles_intersect_static(cell, touching, 0.0));
}

TEST(TriangleSeparatingAxis, NaNAndDegenerateTrianglesAreNeverProvenApart) {
    const TrianglePoints flat{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
    const TrianglePoints point{Vec3(0.5, 0, 0), Vec3(0.5, 0, 0), Vec3(0.5, 0, 0)};
    TrianglePoints broken = flat;
    broken[1][1] = std::nan("");
    EXPECT_FALSE(triangles_apart_along_an_axis(flat, point, 2.0));
    EXPECT_FALSE(triangles_apart_along_an_axis(broken, point, 2.0));
}
