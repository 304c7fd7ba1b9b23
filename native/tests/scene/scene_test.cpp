/// @file scene_test.cpp
/// @brief The scene interpolates sampled positions, and the triangle-pair
///        tester records a pair's first contact once, at its true time.

#include "usdksl/scene/scene.hpp"
#include "usdksl/scene/triangle_pair_tester.hpp"
#include "animations.hpp"

#include <gtest/gtest.h>

#include <vector>

using namespace usdksl;

using animations::falling_triangle;
using animations::floor_triangle;

TEST(Scene, RawScenePositionsInterpolateLinearlyWithoutSlack) {
    const std::vector<MeshAnimation> meshes{floor_triangle(3), falling_triangle({1.0, 0.0, -1.0})};
    const Scene scene(meshes, false);
    EXPECT_FALSE(scene.merged(1));
    EXPECT_EQ(scene.merge_deviation(1), 0.0);
    EXPECT_EQ(scene.contact_distance(0, 1, 0.25), 0.25) << "raw samples add no slack to the thickness";
    const auto at = scene.triangle_at(1, 0, 0.25);
    for (const Vec3& p : at) EXPECT_DOUBLE_EQ(p[1], 0.75);
    EXPECT_DOUBLE_EQ(at[1][0], 0.5);
}

TEST(TrianglePairTester, RecordsTheFirstContactOnceAtItsTime) {
    const std::vector<MeshAnimation> meshes{floor_triangle(3), falling_triangle({1.0, 0.0, -1.0})};
    const Scene scene(meshes, false);
    CCDSettings settings;
    Counters counters;
    TrianglePairTester tester(scene, settings, counters);
    EXPECT_FALSE(tester.settled(0, 0, 1, 0));
    const StepRun run = tester.test_steps(1, 0, 0, 0, 0.0, 2.0, false);
    ASSERT_TRUE(run.hit);
    ASSERT_EQ(tester.contacts().size(), 1u);
    const Contact& contact = tester.contacts().front();
    EXPECT_EQ(contact.mesh_a, 0) << "stored in canonical order whatever order it was asked in";
    EXPECT_EQ(contact.mesh_b, 1);
    EXPECT_LE(contact.time, 1.0) << "never late";
    EXPECT_GE(contact.time, 1.0 - 4.0 * settings.tolerance) << "early by at most about the tolerance";
    EXPECT_TRUE(tester.settled(1, 0, 0, 0));
    EXPECT_GT(counters.narrow_phase_tests, 0);
    // The pair is settled: a second run records nothing new.
    tester.test_step(0, 0, 1, 0, tester.step_containing(0, 0, 1, 0, 1.5));
    EXPECT_EQ(tester.contacts().size(), 1u);
}

TEST(TrianglePairTester, StepByStepAndRunAgreeBitForBit) {
    const std::vector<MeshAnimation> meshes{floor_triangle(4), falling_triangle({1.0, 0.6, 0.2, -0.2})};
    const Scene scene(meshes, false);
    CCDSettings settings;
    Counters run_counters, step_counters;
    TrianglePairTester by_run(scene, settings, run_counters);
    TrianglePairTester by_step(scene, settings, step_counters);
    ASSERT_TRUE(by_run.test_steps(0, 0, 1, 0, 0.0, 3.0, false).hit);
    bool hit = false;
    for (double t = 0.0; !hit && t < 3.0; t += 1.0) hit = by_step.test_step(0, 0, 1, 0, by_step.step_containing(0, 0, 1, 0, t));
    ASSERT_TRUE(hit);
    EXPECT_EQ(by_run.contacts().front().time, by_step.contacts().front().time);
    EXPECT_GT(by_run.contacts().front().time, 2.0);
    EXPECT_LE(by_run.contacts().front().time, 2.5);
}

TEST(TrianglePairTester, MissesNothingAndReportsNothingWhenApart) {
    const std::vector<MeshAnimation> meshes{floor_triangle(3), falling_triangle({1.0, 0.5, 0.01})};
    const Scene scene(meshes, false);
    CCDSettings settings;
    Counters counters;
    TrianglePairTester tester(scene, settings, counters);
    const StepRun run = tester.test_steps(0, 0, 1, 0, 0.0, 2.0, false);
    EXPECT_FALSE(run.hit);
    EXPECT_GE(run.tested_until, 2.0);
    EXPECT_TRUE(tester.contacts().empty());
    EXPECT_FALSE(tester.test_static(0, 0, 1, 0, 2.0));
    settings.thickness = 0.02;
    TrianglePairTester thick(scene, settings, counters);
    EXPECT_TRUE(thick.test_static(0, 0, 1, 0, 2.0)) << "0.01 apart is within a thickness of 0.02";
    ASSERT_EQ(thick.contacts().size(), 1u);
    EXPECT_EQ(thick.contacts().front().feature, ContactFeature::Initial) << "found by a test at one instant";
    EXPECT_EQ(static_cast<int>(ContactFeature::Initial), 3) << "the code usdksl.contacts.table reads as initial";
}
