/// @file window_schedule_test.cpp
/// @brief Handing windows to threads: the planned ones in order, then the
///        later half of the running window with the most sample steps ahead,
///        and only while both halves keep MIN_SAMPLE_STEPS_PER_CUT steps.

#include "../../src/collision/window_schedule.hpp"
#include "animations.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace usdksl;

namespace {

/// A 100-step range, one sample per time code.
struct HundredSteps {
    std::vector<MeshAnimation> meshes{animations::folding_cloth(3, 101)};
    Scene scene{meshes, false};
    WindowCuts cuts{scene, {{0, 0}}, 0.0, 100.0};
};

} // namespace

TEST(WindowSchedule, HandsOutThePlannedWindowsInOrderFirst) {
    HundredSteps range;
    WindowSchedule schedule(range.cuts, {{0.0, 60.0}, {60.0, 100.0}}, true);
    ScheduledWindow* first = schedule.next();
    ScheduledWindow* second = schedule.next();
    ASSERT_NE(first, nullptr);
    ASSERT_NE(second, nullptr);
    EXPECT_EQ(first->begin, 0.0);
    EXPECT_EQ(second->begin, 60.0);
    EXPECT_TRUE(first->started && second->started);
    EXPECT_EQ(schedule.cuts_made(), 0);
}

TEST(WindowSchedule, CutsTheRunningWindowWithTheMostStepsAheadInHalf) {
    HundredSteps range;
    WindowSchedule schedule(range.cuts, {{0.0, 60.0}, {60.0, 100.0}}, true);
    ScheduledWindow* first = schedule.next();
    ScheduledWindow* second = schedule.next();
    first->stop.reach(10.0);   // 50 steps ahead
    second->stop.reach(90.0);  // 10 steps ahead
    schedule.finish(*second);
    ScheduledWindow* taken = schedule.next();
    ASSERT_NE(taken, nullptr);
    EXPECT_EQ(schedule.cuts_made(), 1);
    EXPECT_EQ(taken->end, 60.0);
    EXPECT_EQ(taken->begin, std::floor(taken->begin)) << "cut at a sample time";
    EXPECT_NEAR(taken->begin, 35.0, 50.0 / 4.0) << "about half the steps ahead";
    EXPECT_GE(taken->begin - 10.0, static_cast<double>(MIN_SAMPLE_STEPS_PER_CUT));
    EXPECT_GE(60.0 - taken->begin, static_cast<double>(MIN_SAMPLE_STEPS_PER_CUT));
    EXPECT_EQ(first->end, taken->begin) << "the cut window ends where the taken part begins";
    EXPECT_EQ(first->stop.stop_at.load(), taken->begin) << "and is told to stop there";
    EXPECT_TRUE(first->stop.stops_before(taken->begin));
    EXPECT_FALSE(first->stop.stops_before(taken->begin - 1.0));
    const std::vector<ScheduledWindow*> ordered = schedule.in_time_order();
    ASSERT_EQ(ordered.size(), 3u);
    EXPECT_EQ(ordered[0], first);
    EXPECT_EQ(ordered[1], taken);
    EXPECT_EQ(ordered[2], second);
}

TEST(WindowSchedule, LeavesAWindowWhoseHalvesWouldBeTooShort) {
    HundredSteps range;
    WindowSchedule schedule(range.cuts, {{0.0, 60.0}, {60.0, 100.0}}, true);
    ScheduledWindow* first = schedule.next();
    ScheduledWindow* second = schedule.next();
    first->stop.reach(60.0 - (2 * MIN_SAMPLE_STEPS_PER_CUT - 1));
    second->stop.reach(100.0 - (2 * MIN_SAMPLE_STEPS_PER_CUT - 1));
    EXPECT_EQ(schedule.next(), nullptr);
    EXPECT_EQ(first->end, 60.0);
    EXPECT_EQ(first->stop.stop_at.load(), 60.0);
    first->stop.reach(60.0 - 2 * MIN_SAMPLE_STEPS_PER_CUT);
    EXPECT_NE(schedule.next(), nullptr) << "exactly twice the minimum span ahead is cut";
}

TEST(WindowSchedule, NeverCutsAFinishedWindowOrForAMethodThatCannotStop) {
    HundredSteps range;
    WindowSchedule schedule(range.cuts, {{0.0, 100.0}}, true);
    ScheduledWindow* only = schedule.next();
    schedule.finish(*only);
    EXPECT_EQ(schedule.next(), nullptr) << "finished, though it reached nothing";

    WindowSchedule uncut(range.cuts, {{0.0, 100.0}}, false);
    ASSERT_NE(uncut.next(), nullptr);
    EXPECT_EQ(uncut.next(), nullptr) << "100 steps ahead, but the method would not stop";
}

TEST(WindowSchedule, HandsOutNothingOnceCancelled) {
    HundredSteps range;
    WindowSchedule schedule(range.cuts, {{0.0, 50.0}, {50.0, 100.0}}, true);
    ASSERT_NE(schedule.next(), nullptr);
    schedule.cancel();
    EXPECT_EQ(schedule.next(), nullptr);
}

TEST(WindowSchedule, AWindowCutOffIsHandedOutOnlyToTheThreadThatCutIt) {
    HundredSteps range;
    WindowSchedule schedule(range.cuts, {{0.0, 60.0}, {60.0, 100.0}}, true);
    ScheduledWindow* first = schedule.next();
    ScheduledWindow* second = schedule.next();
    second->stop.reach(100.0);
    schedule.finish(*second);
    ScheduledWindow* taken = schedule.next();
    ASSERT_NE(taken, nullptr);
    first->stop.reach(first->end);
    taken->stop.reach(taken->end - 1.0);  // too little ahead to cut again
    EXPECT_EQ(schedule.next(), nullptr) << "the cut-off window is not handed out as a planned one";
    EXPECT_EQ(schedule.in_time_order().size(), 3u);
}

TEST(WindowSchedule, KeepsTheMinimumSpanInFlightplanStepsWhereSamplesMerge) {
    // the sheet turns every 10 samples: 10 flightplan steps over 100 sample steps
    const std::vector<MeshAnimation> meshes{animations::zigzag_sheet()};
    const Scene scene(meshes, true);
    const WindowCuts cuts(scene, {{0, 0}}, 0.0, 100.0);
    WindowSchedule schedule(cuts, {{0.0, 100.0}}, true);
    ScheduledWindow* running = schedule.next();
    ASSERT_NE(running, nullptr);
    running->stop.reach(100.0 - 10.0 * (2 * MIN_SAMPLE_STEPS_PER_CUT - 1));
    EXPECT_EQ(schedule.next(), nullptr) << "70 sample steps ahead, but 7 flightplan steps";
    running->stop.reach(100.0 - 10.0 * 2 * MIN_SAMPLE_STEPS_PER_CUT);
    ScheduledWindow* taken = schedule.next();
    ASSERT_NE(taken, nullptr) << "8 flightplan steps ahead are cut";
    EXPECT_EQ(taken->begin, 60.0) << "at the turn that leaves four steps on either side";
}
