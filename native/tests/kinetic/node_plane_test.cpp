/// @file node_plane_test.cpp
/// @brief A plane found between two tree nodes keeps their vertices apart by
///        more than the reach throughout the step, and only then; the heights
///        it is judged on are those of every triangle corner beneath; and a
///        pair it keeps apart sleeps no longer than the plane keeps holding.

#include "animations.hpp"
#include "usdksl/constants.hpp"
#include "usdksl/kinetic/node_plane.hpp"
#include "usdksl/narrow_phase/pair_clearance.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

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

namespace {

/// The heights of a node walked over every corner of every triangle under it.
NodeHeights corner_walk_heights(const StepBoxTree& tree, int32_t node, const Vec3& direction) {
    NodeHeights h{{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()},
                  {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}};
    const auto [first, last] = tree.triangles_under(node);
    for (int end = 0; end < 2; ++end) {
        const double* points = end == 0 ? tree.begin_points() : tree.end_points();
        for (const int32_t* t = first; t != last; ++t) {
            for (int32_t v : tree.triangles()[static_cast<size_t>(*t)]) {
                const double* p = points + 3 * static_cast<size_t>(v);
                const double height = direction[0] * p[0] + direction[1] * p[1] + direction[2] * p[2];
                h.low[end] = std::min(h.low[end], height);
                h.high[end] = std::max(h.high[end], height);
            }
        }
    }
    return h;
}

/// Samples of the two sheets the sleep tests use.
constexpr int kApproachSamples = 40;
/// The upper sheet starts this far (scene units) above the lower along
/// their normal and sinks by kApproachSpeed per time code (one step).
constexpr double kApproachStart = 0.71;
constexpr double kApproachSpeed = 0.02;

/// A tilted unit sheet of 4 x 4 quads, `height` above the plane through the
/// origin along the tilted normal at time code k, shifted within its plane
/// by (dx, dz).
MeshAnimation tilted_sheet(double height0, double speed, double dx, double dz) {
    const Eigen::Matrix3d r = animations::tilt();
    return animations::sheet(4, kApproachSamples, [&](double x, double z, int k) {
        return Vec3(r * Vec3(x + dx, height0 - speed * k, z + dz));
    });
}

/// The gap along the normal between the resting and the sinking sheet at time code t.
double approach_gap(double t) { return kApproachStart - kApproachSpeed * t; }

/// node_pair_reach of the two root nodes over step s ([s, s + 1]), from the
/// sheets' corners (their boxes' rounding margins left out: far below the
/// margins the test's numbers leave).
double analytic_reach(int64_t s, double contact_distance) {
    const Eigen::Matrix3d r = animations::tilt();
    Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity()), high = -low;
    for (double t : {static_cast<double>(s), static_cast<double>(s + 1)}) {
        for (double x : {0.0, 1.0}) {
            for (double z : {0.0, 1.0}) {
                for (const Vec3& p : {Vec3(r * Vec3(x, 0.0, z)), Vec3(r * Vec3(x + 0.03, approach_gap(t), z + 0.05))}) {
                    low = low.cwiseMin(p);
                    high = high.cwiseMax(p);
                }
            }
        }
    }
    const double magnitude = std::max(low.cwiseAbs().maxCoeff(), high.cwiseAbs().maxCoeff());
    return clearance_reach(contact_distance, clearance_size_fraction(DEFAULT_CCD_TOLERANCE), (high - low).norm(), 0.0,
                           magnitude);
}

/// The last step the plane keeps the sheets apart on, judged from step
/// `from` on: the gap at both of its ends exceeds its reach.
int64_t last_step_kept(int64_t from, int64_t steps, double contact_distance) {
    int64_t s = from;
    while (s + 1 < steps) {
        const double reach = analytic_reach(s + 1, contact_distance);
        if (!(approach_gap(static_cast<double>(s + 1)) > reach && approach_gap(static_cast<double>(s + 2)) > reach)) {
            break;
        }
        ++s;
    }
    return s;
}

/// The resting sheet and the sinking one, with their trees (their vertices
/// listed for planes). Flightplans of every sample read their meshes in
/// place, so the members stay where they are: use it where it is made.
struct ApproachingSheets {
    const MeshAnimation lower = tilted_sheet(0.0, 0.0, 0.0, 0.0);
    const MeshAnimation upper = tilted_sheet(kApproachStart, kApproachSpeed, 0.03, 0.05);
    const Flightplans plans_a{lower, false}, plans_b{upper, false};
    StepBoxTree tree_a{plans_a, lower.triangles, 0.0}, tree_b{plans_b, upper.triangles, 0.0};

    ApproachingSheets() {
        tree_a.index_triangles_under();
        tree_b.index_triangles_under();
    }
    ApproachingSheets(const ApproachingSheets&) = delete;
    ApproachingSheets& operator=(const ApproachingSheets&) = delete;
};

/// node_plane_quiet_until() for the sheets' root nodes, their trees fitted
/// to step `step` and recording the steps after it as the lists do, the
/// meshes' travel given as the lists measure it (or not at all).
int64_t approach_quiet_until(int64_t step, double contact_distance, bool with_travel, Vec3& normal, double& gap) {
    ApproachingSheets sheets;
    StepBoxTree& tree_a = sheets.tree_a;
    StepBoxTree& tree_b = sheets.tree_b;
    const int64_t steps = kApproachSamples - 1;
    tree_a.fit(static_cast<double>(step), static_cast<double>(step + 1));
    tree_b.fit(static_cast<double>(step), static_cast<double>(step + 1));
    for (int64_t s = step + 1; s < std::min(steps, step + 1 + NODE_TRAVEL_AHEAD_STEPS); ++s) {
        tree_a.record_travel(s, static_cast<double>(s), static_cast<double>(s + 1));
        tree_b.record_travel(s, static_cast<double>(s), static_cast<double>(s + 1));
    }
    const double reach = node_pair_reach(tree_a, 0, tree_b, 0, contact_distance, DEFAULT_CCD_TOLERANCE);
    if (!find_node_plane(tree_a, 0, tree_b, 0, reach, Vec3::Zero(), normal, &gap)) return -1;
    // Along any axis the sinking sheet's vertices move kApproachSpeed times
    // the normal's largest component per step (widened for rounding).
    const Vec3 along = animations::tilt() * Vec3::UnitY();
    const double per_step = kApproachSpeed * along.cwiseAbs().maxCoeff() * (1.0 + 1e-9);
    std::vector<double> still(static_cast<size_t>(steps) + 1, 0.0), sinking(static_cast<size_t>(steps) + 1, 0.0);
    for (size_t s = 0; s + 1 < sinking.size(); ++s) sinking[s + 1] = sinking[s] + per_step;
    return node_plane_quiet_until(tree_a, 0, tree_b, 0, normal, gap, contact_distance, DEFAULT_CCD_TOLERANCE, step,
                                  steps, with_travel ? still.data() : nullptr,
                                  with_travel ? sinking.data() : nullptr);
}

} // namespace

TEST(NodePlane, HeightsOverTheListedVerticesEqualTheWalkOverEveryCorner) {
    // 12 x 12 quads folding: nodes small enough to be listed and larger
    // ones (walked over their corners), heights at both ends of a step.
    const MeshAnimation cloth = animations::folding_cloth(12, 6);
    const Flightplans plans(cloth, false);
    StepBoxTree tree(plans, cloth.triangles, 0.0);
    tree.index_triangles_under();
    tree.fit(2.0, 3.0);
    const Vec3 directions[] = {Vec3::UnitY(), Vec3(0.3, -0.8, 0.52).normalized(), animations::tilt() * Vec3::UnitX()};
    int listed = 0;
    for (int32_t node = 0; node < tree.topology().node_count(); ++node) {
        const auto [first, last] = tree.vertices_under(node);
        listed += first != last;
        for (const Vec3& direction : directions) {
            const NodeHeights fast = node_heights(tree, node, direction);
            const NodeHeights walked = corner_walk_heights(tree, node, direction);
            for (int end = 0; end < 2; ++end) {
                // Least and most of the same values: equal to the bit.
                EXPECT_EQ(fast.low[end], walked.low[end]) << "node " << node;
                EXPECT_EQ(fast.high[end], walked.high[end]) << "node " << node;
            }
        }
    }
    EXPECT_GT(listed, 0);
    EXPECT_LT(listed, tree.topology().node_count());
}

TEST(NodePlane, AKeptPairSleepsExactlyUntilThePlaneFailsWithinTheRecordedSteps) {
    // The sheets stay apart along their normal by approach_gap(t); the
    // plane must be looked at again on the first step it may fail on, and
    // a rigid approach leaves the recorded shifts no slack to wake earlier.
    const double contact_distance = 0.001;
    const int64_t step = 27;
    const int64_t last = last_step_kept(step, kApproachSamples - 1, contact_distance);
    ASSERT_GT(last, step + 1);
    ASSERT_LT(last + 1, step + 1 + NODE_TRAVEL_AHEAD_STEPS) << "the plane must fail within the recorded steps";
    Vec3 normal;
    double gap;
    const int64_t quiet = approach_quiet_until(step, contact_distance, true, normal, gap);
    EXPECT_NEAR(normal.dot(animations::tilt() * Vec3::UnitY()), 1.0, 1e-12);
    EXPECT_NEAR(gap, approach_gap(static_cast<double>(step + 1)), 1e-12);
    EXPECT_EQ(quiet, last + 1);
}

TEST(NodePlane, AKeptPairSleepsPastTheRecordedStepsNoLongerThanThePlaneHolds) {
    // Beyond the recorded steps the meshes' fastest vertex bounds the
    // approach (per axis, so along a tilted normal more than it is): the
    // pair wakes early, but not before the recorded steps run out.
    const double contact_distance = 0.001;
    const int64_t step = 2;
    const int64_t last = last_step_kept(step, kApproachSamples - 1, contact_distance);
    Vec3 normal;
    double gap;
    ASSERT_GT(last, step + NODE_TRAVEL_AHEAD_STEPS);
    const int64_t quiet = approach_quiet_until(step, contact_distance, true, normal, gap);
    EXPECT_GT(quiet, step + NODE_TRAVEL_AHEAD_STEPS);
    EXPECT_LE(quiet, last + 1);
    // Without the meshes' travel it wakes when the recorded steps run out.
    EXPECT_EQ(approach_quiet_until(step, contact_distance, false, normal, gap), step + 1 + NODE_TRAVEL_AHEAD_STEPS);
}

TEST(NodePlane, APlaneCarriedFromTheStepBeforeGetsTheSameAnswerMeasuringOnlyTheEnd) {
    // Step after step as the sinking sheet closes in: the previous step's
    // end gap stands in for this step's begin, until the plane fails.
    ApproachingSheets sheets;
    StepBoxTree& tree_a = sheets.tree_a;
    StepBoxTree& tree_b = sheets.tree_b;
    Vec3 previous = Vec3::Zero();
    double previous_gap = 0.0;
    int kept = 0, failed = 0;
    for (int step = 20; step < kApproachSamples - 1; ++step) {
        tree_a.fit(step, step + 1.0);
        tree_b.fit(step, step + 1.0);
        const double reach = node_pair_reach(tree_a, 0, tree_b, 0, 0.001, DEFAULT_CCD_TOLERANCE);
        Vec3 normal = Vec3::Zero(), carried_normal = Vec3::Zero();
        double gap = 0.0, carried_gap = 0.0;
        const bool found = find_node_plane(tree_a, 0, tree_b, 0, reach, previous, normal, &gap);
        if (previous.squaredNorm() > 0.0) {
            const bool carried = find_node_plane(tree_a, 0, tree_b, 0, reach, previous, carried_normal, &carried_gap,
                                                 &previous_gap);
            ASSERT_EQ(carried, found) << "step " << step;
            if (found) {
                EXPECT_EQ(carried_normal, normal) << "step " << step;
                EXPECT_EQ(carried_gap, gap) << "step " << step;
            }
            kept += carried;
            failed += !carried;
        }
        if (!found) break;
        previous = normal;
        previous_gap = gap;
    }
    EXPECT_GT(kept, 5);
    EXPECT_EQ(failed, 1) << "the plane must fail as the sheets meet";
}
