#include "usdksl/flightplan/sample_motion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

using namespace usdksl;

namespace {

/// Three samples of two vertices: vertex 1 moves (3, 4, 0) then (0, 0, -12); vertex 0 moves 1 along x twice.
std::vector<double> two_vertices() {
    return {0, 0, 0, 10, 10, 10,    //
            1, 0, 0, 13, 14, 10,    //
            2, 0, 0, 13, 14, -2};
}

} // namespace

TEST(SampleMotion, LongestStepIsTheFastestVertexOfEachInterval) {
    const std::vector<double> points = two_vertices();
    const std::vector<double> longest = longest_steps(points.data(), 3, 2);
    ASSERT_EQ(longest.size(), 2u);
    EXPECT_EQ(longest[0], 5.0);
    EXPECT_EQ(longest[1], 12.0);
    EXPECT_TRUE(longest_steps(points.data(), 1, 2).empty());
}

TEST(SampleMotion, FloatPointsGiveTheSameDoublesAsTheirWidenedCopy) {
    std::vector<float> floats;
    std::vector<double> widened;
    for (int i = 0; i < 5 * 7 * 3; ++i) {
        floats.push_back(static_cast<float>(std::sin(0.37 * i) * 1e3 + 0.1 * i));
        widened.push_back(static_cast<double>(floats.back()));
    }
    EXPECT_EQ(longest_steps(floats.data(), 5, 7), longest_steps(widened.data(), 5, 7));
    std::vector<double> lo_f(15), hi_f(15), lo_d(15), hi_d(15);
    sample_boxes(floats.data(), 5, 7, lo_f.data(), hi_f.data());
    sample_boxes(widened.data(), 5, 7, lo_d.data(), hi_d.data());
    EXPECT_EQ(lo_f, lo_d);
    EXPECT_EQ(hi_f, hi_d);
}

TEST(SampleMotion, AnOverflowingStepIsInfiniteNotLost) {
    const double huge = std::numeric_limits<double>::max();
    const std::vector<double> points = {-huge, 0, 0, huge, 0, 0};
    EXPECT_EQ(longest_steps(points.data(), 2, 1)[0], std::numeric_limits<double>::infinity());
}

TEST(SampleMotion, BoxesHoldEachSampleAlone) {
    const std::vector<double> points = two_vertices();
    std::vector<double> lowest(9), highest(9);
    sample_boxes(points.data(), 3, 2, lowest.data(), highest.data());
    EXPECT_EQ(lowest, (std::vector<double>{0, 0, 0, 1, 0, 0, 2, 0, -2}));
    EXPECT_EQ(highest, (std::vector<double>{10, 10, 10, 13, 14, 10, 13, 14, 0}));
}

TEST(SampleMotion, AnyThreadCountGivesTheSameSteps) {
    // enough coordinates for four threads: 40 samples of 36,000 vertices
    const int64_t samples = 40, vertices = 36000;
    ASSERT_GE(samples * vertices * 3, 4 * SAMPLE_MOTION_VALUES_PER_THREAD);
    std::vector<float> points(static_cast<size_t>(samples * vertices * 3));
    for (size_t i = 0; i < points.size(); ++i) points[i] = static_cast<float>(std::sin(0.37 * static_cast<double>(i)) * (1.0 + i % 97));
    const std::vector<double> one = longest_steps(points.data(), samples, vertices, 1);
    std::vector<double> lo_one(3 * samples), hi_one(3 * samples);
    sample_boxes(points.data(), samples, vertices, lo_one.data(), hi_one.data(), 1);
    for (int32_t threads : {2, 3, 4, 7}) {
        EXPECT_EQ(longest_steps(points.data(), samples, vertices, threads), one) << threads << " threads";
        std::vector<double> lo(3 * samples), hi(3 * samples);
        sample_boxes(points.data(), samples, vertices, lo.data(), hi.data(), threads);
        EXPECT_EQ(lo, lo_one) << threads << " threads";
        EXPECT_EQ(hi, hi_one) << threads << " threads";
    }
}
