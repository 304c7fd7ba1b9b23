/// @file time_windows_test.cpp
/// @brief Time windows for threads: contiguous cover of the range, cut at
///        sample times, equal sizes (windows that can be cut) or sizes
///        falling from the first window to the last (windows that cannot),
///        the smallest spanning about MIN_SAMPLE_STEPS_PER_WINDOW sample steps.

#include "../../src/collision/time_windows.hpp"
#include "animations.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace usdksl;

namespace {

std::vector<TimeWindow> windows_of(int samples, int32_t count, WindowSizes sizes = WindowSizes::Falling) {
    const std::vector<MeshAnimation> meshes{animations::folding_cloth(4, samples)};
    const Scene scene(meshes, false);
    return split_into_windows(WindowCuts(scene, {{0, 0}}, 0.0, samples - 1.0), count, sizes);
}

} // namespace

TEST(TimeWindows, ShortShotsStayOneWindow) {
    // 10 sample steps hold one window of MIN_SAMPLE_STEPS_PER_WINDOW steps.
    EXPECT_EQ(windows_of(11, 8).size(), 1u);
}

TEST(TimeWindows, LongShotsGetAsManyWindowsAsTheSmallestOneAllows) {
    const int samples = 33;   // 32 steps: weights 2 + 1 hold 3 minimum spans (24 steps), 3 + 2 + 1 would need 48
    const auto windows = windows_of(samples, 64);
    EXPECT_EQ(windows.size(), 2u);
    EXPECT_EQ(windows.front().begin, 0.0);
    EXPECT_EQ(windows.back().end, samples - 1.0);
    for (size_t w = 0; w < windows.size(); ++w) {
        EXPECT_LT(windows[w].begin, windows[w].end);
        EXPECT_EQ(windows[w].begin, std::floor(windows[w].begin)) << "cut at a sample time";
        if (w > 0) {
            EXPECT_EQ(windows[w].begin, windows[w - 1].end) << "contiguous";
        }
    }
}

TEST(TimeWindows, SizesFallSoTheLastWindowHandedOutIsTheSmallest) {
    const int samples = 201;  // 200 steps: 6 windows need 21 minimum spans (168 steps), 7 would need 224
    const auto windows = windows_of(samples, 8);
    ASSERT_EQ(windows.size(), 6u);
    for (size_t w = 1; w < windows.size(); ++w) {
        EXPECT_LT(windows[w].end - windows[w].begin, windows[w - 1].end - windows[w - 1].begin) << "window " << w;
    }
    // Linear weights 6..1 of 21: the last window spans a 21st of the range.
    EXPECT_NEAR(windows.back().end - windows.back().begin, 200.0 / 21.0, 1.0);
    EXPECT_GE(windows.back().end - windows.back().begin, static_cast<double>(MIN_SAMPLE_STEPS_PER_WINDOW));
}

TEST(TimeWindows, FewerRequestedThanTheMinimumAllowsGivesTheRequestedCount) {
    EXPECT_EQ(windows_of(101, 3).size(), 3u);
    EXPECT_EQ(windows_of(101, 1).size(), 1u);
}

TEST(TimeWindows, EqualSizesSplitTheRangeEvenlyAndKeepTheMinimumSpan) {
    const int samples = 201;  // 200 steps
    const auto two = windows_of(samples, 2, WindowSizes::Equal);
    ASSERT_EQ(two.size(), 2u);
    EXPECT_EQ(two.front().begin, 0.0);
    EXPECT_EQ(two.front().end, two.back().begin) << "contiguous";
    EXPECT_EQ(two.back().end, samples - 1.0);
    // The cut lies within a quarter of a window of the middle, at a sample time.
    EXPECT_NEAR(two.front().end, 100.0, 25.0);
    EXPECT_EQ(two.front().end, std::floor(two.front().end));
    // Falling sizes would put that cut two thirds of the way.
    EXPECT_NEAR(windows_of(samples, 2).front().end, 200.0 * 2.0 / 3.0, 200.0 / 12.0);
    // 25 equal windows of 8 steps fill 200 steps; 26 would not.
    EXPECT_EQ(windows_of(samples, 64, WindowSizes::Equal).size(), 25u);
    for (const TimeWindow& w : windows_of(samples, 25, WindowSizes::Equal)) {
        EXPECT_GE(w.end - w.begin, 4.0) << "no window shrinks below half a share";
    }
}

TEST(TimeWindows, CutsFallOnTheSampleTimeWhereMostBreakpointsFall) {
    // A sheet that zigzags up and down, turning every 10 samples: merged
    // flightplans keep breakpoints at the turns (time codes 0, 10, 20, ...) only.
    const int samples = 101;
    const std::vector<MeshAnimation> meshes{animations::zigzag_sheet()};
    const Scene scene(meshes, true);
    ASSERT_TRUE(scene.merged(0));
    const WindowCuts cuts(scene, {{0, 0}}, 0.0, samples - 1.0);
    EXPECT_EQ(cuts.best_cut(47, 6, 1, 99), 50) << "the turn within reach";
    EXPECT_EQ(cuts.best_cut(47, 2, 1, 99), 47) << "none within reach: the ideal place";
    EXPECT_EQ(cuts.best_cut(47, 6, 1, 49), 47) << "a turn beyond the bound does not count";
    EXPECT_EQ(cuts.best_cut(47, 6, 60, 99), -1) << "an empty range";
    // Equal windows of the 100 steps cut at the turn nearest each ideal place.
    const auto windows = split_into_windows(cuts, 4, WindowSizes::Equal);
    ASSERT_EQ(windows.size(), 4u);
    EXPECT_EQ(windows[0].end, 20.0);  // ideal 25: 20 and 30 are as near; the first found stays
    EXPECT_EQ(windows[1].end, 50.0);
    EXPECT_EQ(windows[2].end, 70.0);
}

TEST(TimeWindows, FlightplanStepsEndWhereMergedFlightplansBreak) {
    const std::vector<MeshAnimation> meshes{animations::zigzag_sheet()};
    const Scene merged(meshes, true);
    const WindowCuts cuts(merged, {{0, 0}}, 0.0, 100.0);
    // before a cut: the breaks at 10 and 20; after it: the break at 90 and the range's end
    EXPECT_EQ(cuts.keeping_flightplan_steps(0, 100, 2), std::make_pair(int64_t{20}, int64_t{89}));
    EXPECT_EQ(cuts.keeping_flightplan_steps(5, 95, 1), std::make_pair(int64_t{10}, int64_t{94}))
        << "the range's end counts whatever breaks there";
    const auto [lo, hi] = cuts.keeping_flightplan_steps(0, 100, 6);
    EXPECT_GT(lo, hi) << "ten steps cannot leave six on either side";
    // every sample breaks in flightplans of every sample: a step per sample
    const Scene raw(meshes, false);
    const WindowCuts raw_cuts(raw, {{0, 0}}, 0.0, 100.0);
    EXPECT_EQ(raw_cuts.keeping_flightplan_steps(0, 100, 4), std::make_pair(int64_t{4}, int64_t{96}));
}
