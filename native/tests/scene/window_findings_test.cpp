/// @file window_findings_test.cpp
/// @brief Time windows checked at once pass on the pairs they found: a window
///        takes only what windows beginning earlier found, each key once, and
///        its tester then leaves those pairs untested.

#include "usdksl/scene/triangle_pair_tester.hpp"
#include "usdksl/scene/window_findings.hpp"
#include "animations.hpp"

#include <gtest/gtest.h>

#include <vector>

using namespace usdksl;

namespace {

std::vector<uint64_t> collected(const WindowFindings& findings, int32_t slot, std::vector<size_t>& cursors) {
    std::vector<uint64_t> keys;
    findings.collect_earlier(slot, cursors, [&](uint64_t key) { keys.push_back(key); });
    return keys;
}

} // namespace

TEST(WindowFindings, AWindowTakesWhatWindowsBeginningEarlierFoundOnce) {
    WindowFindings findings;
    const int32_t late = findings.join(50.0);  // joins first, begins later
    const int32_t early = findings.join(0.0);
    findings.publish(early, {7, 9});
    findings.publish(late, {11});
    std::vector<size_t> late_cursors, early_cursors;
    EXPECT_EQ(collected(findings, late, late_cursors), (std::vector<uint64_t>{7, 9}));
    EXPECT_TRUE(collected(findings, late, late_cursors).empty()) << "each key is taken once";
    findings.publish(early, {13});
    EXPECT_EQ(collected(findings, late, late_cursors), (std::vector<uint64_t>{13}));
    EXPECT_TRUE(collected(findings, early, early_cursors).empty())
        << "a later window's finding may come after the pair's first contact in an earlier one";
    // A window cut from a running one joins last and takes everything earlier windows found so far.
    const int32_t cut = findings.join(25.0);
    std::vector<size_t> cut_cursors;
    EXPECT_EQ(collected(findings, cut, cut_cursors), (std::vector<uint64_t>{7, 9, 13}));
}

TEST(TrianglePairTester, LeavesThePairsAnEarlierWindowFoundUntested) {
    // The triangle falls through the floor between time codes 0 and 2; both windows see it touch.
    const std::vector<MeshAnimation> meshes{animations::floor_triangle(3), animations::falling_triangle({1.0, 0.0, -1.0})};
    const Scene scene(meshes, false);
    CCDSettings settings;
    Counters early_counters, late_counters;
    WindowFindings findings;
    TrianglePairTester early(scene, settings, early_counters);
    TrianglePairTester late(scene, settings, late_counters);
    early.share_findings(findings, findings.join(0.0));
    late.share_findings(findings, findings.join(0.5));

    late.exchange_findings();
    EXPECT_FALSE(late.settled(0, 0, 1, 0)) << "nothing found yet";
    ASSERT_TRUE(early.test_steps(0, 0, 1, 0, 0.0, 2.0, false).hit);
    EXPECT_FALSE(late.settled(0, 0, 1, 0)) << "published only by exchange_findings";
    early.exchange_findings();
    late.exchange_findings();
    EXPECT_TRUE(late.settled(1, 0, 0, 0)) << "either order names the pair";

    const int64_t tests_before = late_counters.narrow_phase_tests;
    const StepRun run = late.test_steps(0, 0, 1, 0, 0.5, 2.0, false);
    EXPECT_TRUE(run.hit) << "the pair needs no further test";
    EXPECT_EQ(run.tested_until, 0.5);
    EXPECT_EQ(late_counters.narrow_phase_tests, tests_before) << "and gets none";
    EXPECT_TRUE(late.contacts().empty()) << "the earlier window's candidate answers for it";
    ASSERT_EQ(early.contacts().size(), 1u);

    // The other way round nothing passes: a window that begins before both tests the pair itself.
    Counters first_counters;
    TrianglePairTester first(scene, settings, first_counters);
    first.share_findings(findings, findings.join(-1.0));
    first.exchange_findings();
    EXPECT_FALSE(first.settled(0, 0, 1, 0));
    EXPECT_TRUE(first.test_steps(0, 0, 1, 0, 0.0, 2.0, false).hit);
    EXPECT_EQ(first.contacts().size(), 1u);
}
