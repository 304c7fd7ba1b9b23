/// @file node_plane_test.cpp
/// @brief A plane found between two tree nodes keeps their vertices apart by
///        more than the reach throughout the step, and only then.

#include "animations.hpp"
#include "usdksl/constants.hpp"
#include "usdksl/kinetic/node_plane.hpp"
#include "usdksl/narrow_phase/pair_clearance.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

using namespace usdksl;

namespace {

/// A 4 x 4 quad card (unit square, tilted), `height` above the plane through
/// the origin along the tilted normal, at two samples: the second lowered by
/// `sink` along the normal.
MeshAnimation card(double height, double sink) {
    const Eigen::Matrix3d r = animations::tilt();
    return animations::sheet(4, 2, [&](double x, double z, int k) {
        return Vec3(r * Vec3(x, height - sink * k, z));
    });
}

/// The gap a plane through the two cards' tree roots keeps, found or not.
bool finds_plane(const MeshAnimation& lower, const MeshAnimation& upper, double reach, Vec3& normal) {
    const Flightplans plans_a(lower, false), plans_b(upper, false);
    StepBoxTree tree_a(plans_a, lower.triangles, 0.0), tree_b(plans_b, upper.triangles, 0.0);
    tree_a.index_triangles_under();
    tree_b.index_triangles_under();
    tree_a.fit(0.0, 1.0);
    tree_b.fit(0.0, 1.0);
    return find_node_plane(tree_a, 0, tree_b, 0, reach, Vec3::Zero(), normal);
}

} // namespace

TEST(NodePlane, FindsTheCardsPlaneOnlyWhenTheGapExceedsTheReachThroughoutTheStep) {
    const double reach = 0.01;
    Vec3 normal;
    // 0.02 apart throughout: the tilted normal, pointing from the lower card up.
    ASSERT_TRUE(finds_plane(card(0.0, 0.0), card(0.02, 0.0), reach, normal));
    EXPECT_NEAR(normal.dot(animations::tilt() * Vec3::UnitY()), 1.0, 1e-12);
    // The other way round, the normal flips.
    ASSERT_TRUE(finds_plane(card(0.02, 0.0), card(0.0, 0.0), reach, normal));
    EXPECT_NEAR(normal.dot(animations::tilt() * Vec3::UnitY()), -1.0, 1e-12);
    // 0.0099 apart: within the reach.
    EXPECT_FALSE(finds_plane(card(0.0, 0.0), card(0.0099, 0.0), reach, normal));
    // Apart at the step's begin, sinking to within the reach by its end.
    EXPECT_FALSE(finds_plane(card(0.0, 0.0), card(0.02, 0.011), reach, normal));
    EXPECT_TRUE(finds_plane(card(0.0, 0.0), card(0.02, 0.009), reach, normal));
}

TEST(NodePlane, TheReachCoversBothNodesBoxesOverTheStep) {
    const MeshAnimation lower = card(0.0, 0.0), upper = card(0.02, 0.0);
    const Flightplans plans_a(lower, false), plans_b(upper, false);
    StepBoxTree tree_a(plans_a, lower.triangles, 0.0), tree_b(plans_b, upper.triangles, 0.0);
    tree_a.fit(0.0, 1.0);
    tree_b.fit(0.0, 1.0);
    // The contact distance times the narrow phase's reach, plus the size
    // fraction of the pair's box diagonal (about sqrt(2) for two unit cards,
    // tilted).
    const double contact_distance = 0.001;
    const double reach = node_pair_reach(tree_a, 0, tree_b, 0, contact_distance, DEFAULT_CCD_TOLERANCE);
    const double narrow_phase_reach = PAIR_CLEARANCE_CONTACT_REACH * contact_distance;
    EXPECT_GT(reach, narrow_phase_reach + clearance_size_fraction(DEFAULT_CCD_TOLERANCE) * 1.4);
    EXPECT_LT(reach, narrow_phase_reach + clearance_size_fraction(DEFAULT_CCD_TOLERANCE) * 2.0);
}
