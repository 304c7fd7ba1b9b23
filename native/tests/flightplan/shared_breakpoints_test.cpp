/// @file shared_breakpoints_test.cpp
/// @brief Where a vertex must break, it breaks where the other vertices do:
///        a cache resampled densely with linear in-betweens keeps breakpoints
///        at its original frames only, every vertex within the merge
///        tolerance, the same for any thread count; the velocity window
///        decides every merge as measuring each sample does.

#include "animations.hpp"
#include "usdksl/constants.hpp"
#include "usdksl/flightplan/flightplans.hpp"

#include "../../src/flightplan/chord_deviation.hpp"
#include "../../src/flightplan/collinear_merge.hpp"
#include "../../src/flightplan/shared_breakpoints.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

using usdksl::Flightplans;
using usdksl::MeshAnimation;
using usdksl::Vec3;
using usdksl::animations::random_walk;
using usdksl::animations::raw_position;

namespace {

/// Vertex v turns on a circle (radius 0.1, about a center near (1, 0.5, -0.7),
/// with a wobble out of its plane) by speeds[v] radians per frame, sampled at
/// frames 0..frames, each frame interval then resampled `density` times with
/// linear in-betweens, as a cache densified for motion blur is.
MeshAnimation dense_circles(const std::vector<double>& speeds, int frames, int density) {
    MeshAnimation mesh;
    mesh.vertex_count = static_cast<int32_t>(speeds.size());
    const auto at = [&](size_t v, int frame) {
        const double a = speeds[v] * frame + 0.37 * static_cast<double>(v);
        const Vec3 center(1.0 + 0.01 * static_cast<double>(v % 7), 0.5, -0.7);
        return Vec3(center + 0.1 * Vec3(std::cos(a), std::sin(a), 0.3 * std::sin(2.0 * a)));
    };
    for (int f = 0; f <= frames; ++f) {
        for (int i = 0; i < (f < frames ? density : 1); ++i) {
            mesh.times.push_back(static_cast<double>(f * density + i) / density);
            const double w = static_cast<double>(i) / density;
            for (size_t v = 0; v < speeds.size(); ++v) {
                const Vec3 p = i == 0 ? at(v, f) : Vec3(at(v, f) + w * (at(v, f + 1) - at(v, f)));
                mesh.points.insert(mesh.points.end(), {p[0], p[1], p[2]});
            }
        }
    }
    return mesh;
}

/// `fast` vertices that bend at every frame, then `slow` ones whose turn
/// stays within the merge tolerance over a few frames (a few to about
/// fifteen, by speed) before it bends enough to break.
std::vector<double> circle_speeds(int fast, int slow) {
    std::vector<double> speeds;
    for (int i = 0; i < fast; ++i) speeds.push_back(0.05 + 0.25 * i / std::max(fast - 1, 1));
    for (int i = 0; i < slow; ++i) speeds.push_back(3e-4 + 1.7e-3 * i / std::max(slow - 1, 1));
    return speeds;
}

bool on_a_frame(double t) { return std::floor(t) == t; }

/// Largest infinity-norm distance between v's flightplan and its raw samples, at every sample time.
double worst_deviation(const Flightplans& plans, const MeshAnimation& mesh, int32_t v) {
    double worst = 0.0;
    for (double t : mesh.times) worst = std::max(worst, (plans.position(v, t) - raw_position(mesh, v, t)).cwiseAbs().maxCoeff());
    return worst;
}

/// Every breakpoint of `plans` against the mesh: one of v's own samples, the
/// flightplan within v's recorded deviation of the samples, which stays
/// within the merge tolerance.
void expect_within_tolerance(const Flightplans& plans, const MeshAnimation& mesh) {
    const size_t n = static_cast<size_t>(mesh.vertex_count);
    for (int32_t v = 0; v < mesh.vertex_count; ++v) {
        ASSERT_EQ(plans.key_time(v, plans.key_begin(v)), mesh.times.front()) << "vertex " << v;
        for (int64_t key = plans.key_begin(v); key < plans.key_end(v); ++key) {
            const auto sample = std::lower_bound(mesh.times.begin(), mesh.times.end(), plans.key_time(v, key));
            ASSERT_TRUE(sample != mesh.times.end() && *sample == plans.key_time(v, key)) << "vertex " << v;
            const size_t k = static_cast<size_t>(sample - mesh.times.begin());
            for (int axis = 0; axis < 3; ++axis) ASSERT_EQ(plans.key_coord(v, key, axis), mesh.points[(k * n + v) * 3 + axis]);
        }
        EXPECT_LE(worst_deviation(plans, mesh, v), plans.vertex_deviation(v) + 1e-15 * plans.vertex_magnitude(v))
            << "vertex " << v;
        EXPECT_LE(plans.vertex_deviation(v), usdksl::FLIGHTPLAN_COLLINEAR_TOLERANCE * plans.vertex_magnitude(v))
            << "vertex " << v;
        EXPECT_LE(plans.vertex_deviation(v), plans.merge_deviation());
    }
}

/// The greedy merge as first written: at every sample, the distance of every
/// sample since the last kept one from the new chord, measured again.
std::vector<int64_t> measured_greedy(const MeshAnimation& mesh, int32_t v, double& deviation) {
    const int64_t count = static_cast<int64_t>(mesh.times.size());
    std::vector<int64_t> kept{0};
    double run_deviation = 0.0, run_magnitude = usdksl::sample_magnitude(mesh, v, 0);
    deviation = 0.0;
    for (int64_t k = 1; k < count; ++k) {
        if (k + 1 < count) {
            const double magnitude = std::max({run_magnitude, usdksl::sample_magnitude(mesh, v, k),
                                               usdksl::sample_magnitude(mesh, v, k + 1)});
            const double tolerance = usdksl::FLIGHTPLAN_COLLINEAR_TOLERANCE * magnitude;
            double worst = 0.0;
            for (int64_t j = kept.back() + 1; j <= k; ++j) {
                worst = std::max(worst, usdksl::deviation_from_chord(mesh, v, kept.back(), j, k + 1));
            }
            if (worst <= tolerance) {
                run_magnitude = std::max(run_magnitude, usdksl::sample_magnitude(mesh, v, k));
                run_deviation = worst;
                continue;
            }
            deviation = std::max(deviation, run_deviation);
            run_deviation = 0.0;
        }
        kept.push_back(k);
        run_magnitude = usdksl::sample_magnitude(mesh, v, k);
    }
    deviation = std::max(deviation, run_deviation);
    return kept;
}

} // namespace

TEST(SharedBreakpoints, DenseLinearInBetweensOfCurvedMotionBreakOnlyAtTheFrames) {
    const int frames = 40, density = 10;
    const MeshAnimation mesh = dense_circles(circle_speeds(60, 40), frames, density);
    // Alone, a slow vertex breaks wherever its merge fails: mostly between frames.
    int slow_breaking_between_frames = 0;
    std::vector<int64_t> kept;
    for (int32_t v = 60; v < 100; ++v) {
        usdksl::merge_collinear_samples(mesh, v, nullptr, kept);
        slow_breaking_between_frames += std::any_of(kept.begin(), kept.end(), [&](int64_t k) {
            return !on_a_frame(mesh.times[static_cast<size_t>(k)]);
        });
    }
    ASSERT_GE(slow_breaking_between_frames, 20) << "the slow vertices must need aligning";

    const Flightplans plans(mesh, true);
    int slow_merging_frames = 0;
    std::set<double> steps;  // the union the kinetic core steps along
    for (int32_t v = 0; v < mesh.vertex_count; ++v) {
        const int64_t breakpoints = plans.key_end(v) - plans.key_begin(v);
        for (int64_t key = plans.key_begin(v); key < plans.key_end(v); ++key) {
            EXPECT_TRUE(on_a_frame(plans.key_time(v, key))) << "vertex " << v << " breaks at " << plans.key_time(v, key);
            steps.insert(plans.key_time(v, key));
        }
        if (v < 60) EXPECT_EQ(breakpoints, frames + 1) << "a fast vertex bends at every frame";
        else slow_merging_frames += breakpoints <= frames / 2;
    }
    EXPECT_EQ(steps.size(), static_cast<size_t>(frames + 1));
    EXPECT_GE(slow_merging_frames, 30) << "slow vertices still merge across frames";
    expect_within_tolerance(plans, mesh);
}

TEST(SharedBreakpoints, ARunEndingAtThePreferredSampleOffItsOwnChordFallsBack) {
    // One vertex, samples 0..4. The walk of merge_collinear_samples never
    // offers such a stretch (every shorter run merged on its way to k), so
    // the run's end is asked for directly.
    MeshAnimation mesh;
    mesh.vertex_count = 1;
    mesh.times = {0.0, 1.0, 2.0, 3.0, 4.0};
    const double off = 1e-3;  // far beyond the tolerance (2^-22 of about 1)
    mesh.points = {1.0, 0.0, 0.0,   1.1, off, 0.0,   1.2, 0.0, 0.0,   1.3, 0.0, 0.0,   1.5, 0.3, 0.0};
    const int64_t popularity[] = {10, 0, 9, 1, 10};
    ASSERT_EQ(usdksl::preferred_break(popularity, 0, 3), 2);
    const usdksl::RunEnd fell_back = usdksl::aligned_run_end(mesh, 0, 0, 3, popularity);
    EXPECT_EQ(fell_back.sample, 3);
    EXPECT_EQ(fell_back.deviation, usdksl::run_deviation(mesh, 0, 0, 3));
    EXPECT_GT(fell_back.deviation, 0.5 * off);

    // On its chord, the preferred sample ends the run, with its own deviation.
    mesh.points[4] = 0.0;
    const usdksl::RunEnd preferred = usdksl::aligned_run_end(mesh, 0, 0, 3, popularity);
    EXPECT_EQ(preferred.sample, 2);
    EXPECT_EQ(preferred.deviation, usdksl::deviation_from_chord(mesh, 0, 0, 1, 2));
    EXPECT_LE(preferred.deviation, 1e-15);

    // Without counts, or where the latest sample is popular enough, the run ends where the merge failed.
    EXPECT_EQ(usdksl::preferred_break(nullptr, 0, 3), 3);
    const int64_t flat[] = {10, 0, 9, 5, 10};
    EXPECT_EQ(usdksl::preferred_break(flat, 0, 3), 3);
}

TEST(SharedBreakpoints, OneAndFourThreadsBuildTheSameAlignedFlightplans) {
    // Fast vertices first, slow ones last: the slow ones' runs of vertices
    // learn where to break from the counts of other runs.
    const MeshAnimation mesh = dense_circles(circle_speeds(300, 300), 40, 10);
    ASSERT_GT(static_cast<int64_t>(mesh.times.size()) * mesh.vertex_count, 3 * usdksl::FLIGHTPLAN_SAMPLES_PER_RUN);
    const Flightplans one(mesh, true, 1);
    const Flightplans four(mesh, true, 4);
    ASSERT_TRUE(one.merged());
    EXPECT_EQ(four.merge_deviation(), one.merge_deviation());
    EXPECT_EQ(four.max_abs_coordinate(), one.max_abs_coordinate());
    for (int32_t v = 0; v < mesh.vertex_count; ++v) {
        ASSERT_EQ(four.key_begin(v), one.key_begin(v)) << "vertex " << v;
        ASSERT_EQ(four.key_end(v), one.key_end(v)) << "vertex " << v;
        EXPECT_EQ(four.vertex_deviation(v), one.vertex_deviation(v));
        for (int64_t k = one.key_begin(v); k < one.key_end(v); ++k) {
            ASSERT_EQ(four.key_time(v, k), one.key_time(v, k));
            EXPECT_TRUE(on_a_frame(one.key_time(v, k))) << "vertex " << v;
            for (int axis = 0; axis < 3; ++axis) ASSERT_EQ(four.key_coord(v, k, axis), one.key_coord(v, k, axis));
        }
    }
    expect_within_tolerance(one, mesh);
}

TEST(SharedBreakpoints, MeshesBuiltTogetherBreakAtTimesEitherKeeps) {
    // A mesh of slow vertices alone breaks between frames; built with a mesh
    // that bends at every frame, it breaks at those frames.
    const MeshAnimation slow = dense_circles(circle_speeds(0, 30), 40, 10);
    const MeshAnimation fast = dense_circles(circle_speeds(40, 0), 40, 10);
    const Flightplans alone(slow, true);
    bool between_frames = false;
    for (int32_t v = 0; v < slow.vertex_count; ++v) {
        for (int64_t k = alone.key_begin(v); k < alone.key_end(v); ++k) between_frames |= !on_a_frame(alone.key_time(v, k));
    }
    ASSERT_TRUE(between_frames);
    const std::vector<Flightplans> together = Flightplans::build_all({{&slow, true}, {&fast, true}}, 2);
    for (int32_t v = 0; v < slow.vertex_count; ++v) {
        for (int64_t k = together[0].key_begin(v); k < together[0].key_end(v); ++k) {
            EXPECT_TRUE(on_a_frame(together[0].key_time(v, k))) << "vertex " << v;
        }
    }
    expect_within_tolerance(together[0], slow);
    expect_within_tolerance(together[1], fast);
}

TEST(SharedBreakpoints, TheVelocityWindowDecidesEveryMergeAsMeasuringEachSampleDoes) {
    // Noise around the merge tolerance (2^-22 of coordinates about 1) puts
    // samples on either side of it. Vertices 3 and 4 start at the origin,
    // where the window, sized by the anchor, leaves the decision to
    // measuring: 3 accelerates, 4 moves away on a straight line. No vertex
    // holds still (merge_collinear_samples keeps one sample of those).
    for (double noise : {0.0, 1e-7, 2.4e-7, 5e-7}) {
        MeshAnimation mesh = random_walk(40, 80, 13, noise);
        for (size_t k = 0; k < mesh.times.size(); ++k) {
            const double t = static_cast<double>(k);
            for (int axis = 0; axis < 3; ++axis) {
                mesh.points[(k * 40 + 3) * 3 + axis] = 0.001 * t * t;
                mesh.points[(k * 40 + 4) * 3 + axis] = 0.01 * t * (axis + 1);
            }
        }
        std::vector<int64_t> kept;
        for (int32_t v = 0; v < mesh.vertex_count; ++v) {
            double expected_deviation = 0.0;
            std::vector<int64_t> expected = measured_greedy(mesh, v, expected_deviation);
            const double deviation = usdksl::merge_collinear_samples(mesh, v, nullptr, kept);
            EXPECT_EQ(kept, expected) << "vertex " << v << ", noise " << noise;
            EXPECT_EQ(deviation, expected_deviation) << "vertex " << v << ", noise " << noise;
        }
    }
}
