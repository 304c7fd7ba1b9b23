/// @file sub_frame_samples_test.cpp
/// @brief Which samples lie between whole frames, and merged flightplans that
///        step over them: every sample stays within its vertex's deviation of
///        the flightplan, which stays within the slack, and a mesh sampled
///        once a frame gets the flightplans it always got.

#include "animations.hpp"

#include "../../src/flightplan/sub_frame_samples.hpp"

#include "usdksl/flightplan/flightplans.hpp"
#include "usdksl/single_precision.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

using usdksl::Flightplans;
using usdksl::FlightplanRequest;
using usdksl::MeshAnimation;
using usdksl::Vec3;
using usdksl::keep_bent_stretches;
using usdksl::sub_frame_slack;
using usdksl::whole_frame_samples;

namespace {

/// One vertex sampled at `times`, at x = sin(t * speed), y = t (a curve).
MeshAnimation curve(const std::vector<double>& times, double speed) {
    MeshAnimation mesh;
    mesh.times = times;
    mesh.vertex_count = 1;
    for (double t : times) mesh.points.insert(mesh.points.end(), {std::sin(t * speed), t, 0.0});
    return mesh;
}

std::vector<int64_t> left_samples(const MeshAnimation& mesh, double frames_per_time_code) {
    const auto view = whole_frame_samples(mesh, frames_per_time_code);
    if (!view) return {};
    return view->sample;
}

/// A grid of n x n quads, each vertex on its own circle (radius and speed
/// vary across the grid), `per_frame` samples a frame over `frames` frames;
/// one corner jumps at frame 3 (an impact).
MeshAnimation circling_grid(int n, int frames, int per_frame) {
    MeshAnimation mesh;
    mesh.vertex_count = (n + 1) * (n + 1);
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            const int32_t a = i * (n + 1) + j, b = a + 1, c = a + n + 1, d = c + 1;
            mesh.triangles.push_back({a, b, d});
            mesh.triangles.push_back({a, d, c});
        }
    }
    for (int k = 0; k <= frames * per_frame; ++k) {
        const double t = static_cast<double>(k) / per_frame;
        mesh.times.push_back(t);
        for (int i = 0; i <= n; ++i) {
            for (int j = 0; j <= n; ++j) {
                const double radius = 0.002 * (1 + i), speed = 0.2 * (1 + j);
                double x = j * 0.1 + radius * std::cos(speed * t), y = i * 0.1 + radius * std::sin(speed * t);
                if (i == n && j == n && t > 3.0 && t < 4.0) x += 0.05;
                mesh.points.insert(mesh.points.end(), {x, y, 0.01 * t});
            }
        }
    }
    return mesh;
}

Vec3 sample(const MeshAnimation& mesh, int64_t k, int32_t v) { return mesh.sample_point(k, v); }

} // namespace

TEST(SubFrameSamples, OnlySamplesBetweenTwoWholeFramesAFrameApartAreLeftOut) {
    // 1.25 and 1.5 lie between frames 1 and 3 (2 is not sampled): they stay, as does 0.5, before any
    // whole frame, and 5.25, the last sample; 3.5 and 4.5 lie between consecutive frames.
    const MeshAnimation mesh = curve({0.5, 1.0, 1.25, 1.5, 3.0, 3.5, 4.0, 4.5, 5.0, 5.25}, 1.0);
    EXPECT_EQ(left_samples(mesh, 1.0), (std::vector<int64_t>{0, 1, 2, 3, 4, 6, 8, 9}));
    // Two time codes a frame: whole frames at even time codes; 1.0 and 3.0 lie between frames then.
    const MeshAnimation halves = curve({0.0, 1.0, 2.0, 3.0, 4.0}, 1.0);
    EXPECT_EQ(left_samples(halves, 0.5), (std::vector<int64_t>{0, 2, 4}));
    // Nothing to leave out: a sample a frame, every other frame, an unknown clock, only sub-frame samples.
    EXPECT_TRUE(whole_frame_samples(curve({0, 1, 2, 3}, 1.0), 1.0) == nullptr);
    EXPECT_TRUE(whole_frame_samples(curve({0, 2, 4}, 1.0), 1.0) == nullptr);
    EXPECT_TRUE(whole_frame_samples(curve({0, 0.5, 1}, 1.0), 0.0) == nullptr);
    EXPECT_TRUE(whole_frame_samples(curve({0.25, 0.5, 0.75, 1.25}, 1.0), 1.0) == nullptr);
    // The view holds the left samples' times and positions.
    const auto view = whole_frame_samples(curve({0, 0.5, 1, 1.5, 2}, 3.0), 1.0);
    ASSERT_NE(view, nullptr);
    EXPECT_EQ(view->mesh.times, (std::vector<double>{0, 1, 2}));
    EXPECT_EQ(view->mesh.sample_point(1, 0), Vec3(std::sin(3.0), 1.0, 0.0));
}

TEST(SubFrameSamples, ABentStretchKeepsItsSamplesAndTheOthersStayWithinTheSlack) {
    // Samples every quarter frame of a curve; breakpoints at the whole frames.
    std::vector<double> times;
    for (int k = 0; k <= 16; ++k) times.push_back(k / 4.0);
    MeshAnimation mesh = curve(times, 0.3);
    mesh.points[3 * 9] += 0.5;  // sample 9 (t = 2.25) far off: frame 2..3 bends
    std::vector<int64_t> kept{0, 4, 8, 12, 16};
    const double slack = 0.01;
    std::vector<double> per_segment;
    const double deviation = keep_bent_stretches(mesh, 0, slack, kept, &per_segment);
    EXPECT_EQ(kept, (std::vector<int64_t>{0, 4, 8, 9, 10, 11, 12, 16}));
    EXPECT_GT(deviation, 0.0);
    EXPECT_LE(deviation, slack);
    // Per breakpoint: its segment's own distance; the bent frame's samples are breakpoints (none left out).
    ASSERT_EQ(per_segment.size(), kept.size());
    for (size_t i : {2, 3, 4, 5}) EXPECT_EQ(per_segment[i], 0.0) << "breakpoint " << i;
    EXPECT_GT(per_segment[0], 0.0);
    EXPECT_EQ(*std::max_element(per_segment.begin(), per_segment.end()), deviation);
    // Held still after its last breakpoint, a vertex that moves there keeps those samples too.
    std::vector<int64_t> first_only{0};
    EXPECT_EQ(keep_bent_stretches(curve(times, 0.3), 0, 10.0, first_only), 4.0);  // y = t, held at 0
    EXPECT_EQ(first_only, (std::vector<int64_t>{0}));
    std::vector<int64_t> held{0};
    keep_bent_stretches(curve(times, 0.3), 0, slack, held);
    EXPECT_EQ(held.size(), times.size());
    // A sample left out must be finite.
    mesh.points[3 * 5 + 1] = std::numeric_limits<double>::quiet_NaN();
    std::vector<int64_t> frames{0, 4, 8, 12, 16};
    EXPECT_THROW(keep_bent_stretches(mesh, 0, slack, frames), std::invalid_argument);
}

TEST(SubFrameSamples, MergedFlightplansStepOverSubFrameSamplesWithinTheirVerticesDeviation) {
    const MeshAnimation mesh = circling_grid(6, 8, 5);
    const double slack = sub_frame_slack(mesh);
    EXPECT_NEAR(slack, 0.1 / 64.0, 1e-3 / 64.0);  // the median edge is a side of a quad
    const Flightplans over = std::move(Flightplans::build_all({FlightplanRequest{&mesh, true, 1.0}}, 2).front());
    const Flightplans every = std::move(Flightplans::build_all({FlightplanRequest{&mesh, true, 0.0}}, 2).front());
    EXPECT_TRUE(over.merged());
    int64_t keys_over = 0, keys_every = 0, below_vertex = 0;
    bool some_bent = false;
    for (int32_t v = 0; v < mesh.vertex_count; ++v) {
        keys_over += over.key_end(v) - over.key_begin(v);
        keys_every += every.key_end(v) - every.key_begin(v);
        EXPECT_LE(over.vertex_deviation(v), slack) << "vertex " << v;
        for (int64_t k = over.key_begin(v); k < over.key_end(v); ++k) {
            const double frame = over.key_time(v, k);
            some_bent = some_bent || frame != std::round(frame);
        }
        // Every sample lies within its segment's deviation of the flightplan (the slack its contacts get on
        // that segment's steps), and so within the vertex's.
        for (size_t k = 0; k < mesh.times.size(); ++k) {
            const double t = mesh.times[k];
            const double off = (over.position(v, t) - sample(mesh, static_cast<int64_t>(k), v)).cwiseAbs().maxCoeff();
            int64_t segment = over.segment_of(v, t);
            // A sample on a breakpoint closes the segment before it too.
            if (segment > over.key_begin(v) && over.key_time(v, segment) == t) --segment;
            EXPECT_LE(off, over.segment_deviation(v, segment)) << "vertex " << v << ", sample " << k;
            // Kept in single precision, rounded up.
            const double vertex_bound = usdksl::float_at_least(over.vertex_deviation(v));
            EXPECT_LE(over.segment_deviation(v, segment), vertex_bound);
            below_vertex += over.segment_deviation(v, segment) < vertex_bound;
        }
    }
    EXPECT_TRUE(over.deviation_per_segment());
    EXPECT_GT(below_vertex, 0);            // segments of the same vertex bend differently
    EXPECT_LT(2 * keys_over, keys_every);  // most sub-frame samples are stepped over
    EXPECT_TRUE(some_bent);                // the corner's jump keeps its frame's samples

    // Sampled once a frame, the same motion gets the flightplans it gets without the clock.
    MeshAnimation frames = circling_grid(6, 8, 1);
    const Flightplans clocked = std::move(Flightplans::build_all({FlightplanRequest{&frames, true, 1.0}}, 2).front());
    const Flightplans plain = std::move(Flightplans::build_all({FlightplanRequest{&frames, true, 0.0}}, 2).front());
    for (int32_t v = 0; v < frames.vertex_count; ++v) {
        ASSERT_EQ(clocked.key_end(v) - clocked.key_begin(v), plain.key_end(v) - plain.key_begin(v));
        for (int64_t k = 0; k < clocked.key_end(v) - clocked.key_begin(v); ++k) {
            EXPECT_EQ(clocked.key_time(v, clocked.key_begin(v) + k), plain.key_time(v, plain.key_begin(v) + k));
            EXPECT_EQ(clocked.key_point(v, clocked.key_begin(v) + k), plain.key_point(v, plain.key_begin(v) + k));
        }
        EXPECT_EQ(clocked.vertex_deviation(v), plain.vertex_deviation(v));
    }
}
