/// @file flightplans_test.cpp
/// @brief Merged flightplans stay within their stated deviation of the raw
///        samples, and the merge tolerance is local to each vertex.

#include "animations.hpp"
#include "usdksl/constants.hpp"
#include "usdksl/flightplan/flightplans.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

using usdksl::Flightplans;
using usdksl::MeshAnimation;
using usdksl::Vec3;
using usdksl::animations::random_walk;
using usdksl::animations::raw_position;

namespace {

/// Largest infinity-norm distance between merged and raw positions of v over
/// every sample time and every midpoint between samples.
double worst_deviation(const Flightplans& plans, const MeshAnimation& mesh, int32_t v) {
    double worst = 0.0;
    for (size_t k = 0; k < mesh.times.size(); ++k) {
        const double t = mesh.times[k];
        worst = std::max(worst, (plans.position(v, t) - raw_position(mesh, v, t)).cwiseAbs().maxCoeff());
        if (k + 1 < mesh.times.size()) {
            const double mid = 0.5 * (t + mesh.times[k + 1]);
            worst = std::max(worst, (plans.position(v, mid) - raw_position(mesh, v, mid)).cwiseAbs().maxCoeff());
        }
    }
    return worst;
}

} // namespace

TEST(Flightplans, RawPlansReproduceEverySample) {
    const MeshAnimation mesh = random_walk(30, 25, 7, 0.0);
    const Flightplans raw(mesh, false);
    EXPECT_FALSE(raw.merged());
    EXPECT_EQ(raw.merge_deviation(), 0.0);
    for (int32_t v = 0; v < mesh.vertex_count; ++v) {
        EXPECT_EQ(raw.key_end(v) - raw.key_begin(v), static_cast<int64_t>(mesh.times.size()));
        EXPECT_EQ(worst_deviation(raw, mesh, v), 0.0);
    }
}

TEST(Flightplans, RawPlansMeasureEachVertexOverEverySampleOnAnyThreadCount) {
    MeshAnimation mesh = random_walk(30, 25, 11, 1e-3);
    mesh.points[(17 * 30 + 4) * 3 + 1] = -250.0;  // vertex 4 far away at one sample
    for (int32_t threads : {1, 2, 3}) {
        const Flightplans raw(mesh, false, threads);
        for (int32_t v = 0; v < mesh.vertex_count; ++v) {
            double largest = 0.0;
            for (size_t k = 0; k < mesh.times.size(); ++k) {
                for (int axis = 0; axis < 3; ++axis) {
                    largest = std::max(largest, std::abs(mesh.points[(k * 30 + static_cast<size_t>(v)) * 3 + axis]));
                }
            }
            EXPECT_EQ(raw.vertex_magnitude(v), largest) << "vertex " << v << ", threads " << threads;
        }
        EXPECT_EQ(raw.max_abs_coordinate(), 250.0);
    }
}

TEST(Flightplans, ANonFiniteCoordinateIsRefusedMergedOrRaw) {
    // Anywhere: the first and last samples, one a merge would drop (vertex 3
    // moves on a straight line), any vertex, any axis.
    const size_t samples = 25, vertices = 30;
    const size_t places[][3] = {{24, 29, 2}, {0, 0, 0}, {0, 29, 1}, {12, 3, 1}, {1, 17, 2}, {23, 3, 0}, {24, 0, 0}};
    for (double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
        for (const auto& place : places) {
            MeshAnimation mesh = random_walk(static_cast<int>(vertices), static_cast<int>(samples), 13, 0.0);
            for (size_t k = 0; k < samples; ++k) {
                for (size_t axis = 0; axis < 3; ++axis) mesh.points[(k * vertices + 3) * 3 + axis] = 0.1 * k * (axis + 1);
            }
            mesh.points[(place[0] * vertices + place[1]) * 3 + place[2]] = bad;
            for (bool merge : {false, true}) {
                EXPECT_THROW(Flightplans(mesh, merge, 2), std::invalid_argument)
                    << "merge " << merge << ", sample " << place[0] << ", vertex " << place[1];
            }
        }
    }
}

TEST(Flightplans, MergingDropsCollinearSamplesWithinTheStatedDeviation) {
    for (double noise : {0.0, 1e-9, 1e-7}) {
        const MeshAnimation mesh = random_walk(60, 40, 11, noise);
        const Flightplans merged(mesh, true);
        EXPECT_TRUE(merged.merged()) << "straight runs must merge (noise " << noise << ")";
        int64_t breakpoints = 0;
        for (int32_t v = 0; v < mesh.vertex_count; ++v) {
            breakpoints += merged.key_end(v) - merged.key_begin(v);
            const double worst = worst_deviation(merged, mesh, v);
            // Positions between samples are linear in both, so the sample
            // deviation bounds the whole trajectory.
            EXPECT_LE(worst, merged.merge_deviation() * (1.0 + 1e-12)) << "vertex " << v;
            EXPECT_LE(worst, usdksl::FLIGHTPLAN_COLLINEAR_TOLERANCE * merged.vertex_magnitude(v) * 1.01)
                << "vertex " << v;
        }
        EXPECT_LT(breakpoints, static_cast<int64_t>(mesh.vertex_count) * 40);
    }
}

TEST(Flightplans, AFarAwaySampleOfOneVertexLoosensNoOtherVertex) {
    MeshAnimation calm = random_walk(30, 30, 5, 1e-7);
    MeshAnimation blown = calm;
    blown.points[(static_cast<size_t>(15) * 30 + 4) * 3 + 1] = 1e9;  // vertex 4 at sample 15
    const Flightplans a(calm, true), b(blown, true);
    for (int32_t v = 0; v < 30; ++v) {
        if (v == 4) continue;
        ASSERT_EQ(a.key_end(v) - a.key_begin(v), b.key_end(v) - b.key_begin(v)) << "vertex " << v;
        for (int64_t k = 0; k < a.key_end(v) - a.key_begin(v); ++k) {
            EXPECT_EQ(a.key_time(v, a.key_begin(v) + k), b.key_time(v, b.key_begin(v) + k));
        }
        EXPECT_EQ(a.vertex_magnitude(v), b.vertex_magnitude(v));
    }
    EXPECT_GE(b.vertex_magnitude(4), 1e9);
    // The spike itself is kept: it is not on any chord.
    EXPECT_EQ(b.position(4, 15.0)[1], 1e9);
}

TEST(Flightplans, SegmentLookupAgreesWithBinarySearchInAnyQueryOrder) {
    const MeshAnimation mesh = random_walk(9, 50, 3, 0.0);
    const Flightplans merged(mesh, true);
    const double queries[] = {0.0, 49.0, 12.5, 3.0, 48.9, 0.1, 25.0, 25.0, 60.0, -5.0};
    for (int32_t v = 0; v < 9; ++v) {
        for (double t : queries) {
            const int64_t k = merged.segment_of(v, t);
            EXPECT_GE(k, merged.key_begin(v));
            EXPECT_LT(k, merged.key_end(v));
            if (t >= merged.key_time(v, merged.key_begin(v))) EXPECT_LE(merged.key_time(v, k), t);
            if (k + 1 < merged.key_end(v)) EXPECT_GT(merged.key_time(v, k + 1), t);
        }
    }
}

TEST(Flightplans, AnyThreadCountBuildsTheSameFlightplans) {
    // Large enough to be split over threads (FLIGHTPLAN_SAMPLES_PER_RUN),
    // with merges, a few still vertices and deviations left by the noise.
    MeshAnimation mesh = random_walk(3001, 120, 11, 1e-7);
    for (int k = 0; k < 120; ++k) {
        for (int axis = 0; axis < 3; ++axis) mesh.points[(static_cast<size_t>(k) * 3001 + 1500) * 3 + axis] = 0.25;
    }
    ASSERT_GT(static_cast<int64_t>(mesh.times.size()) * mesh.vertex_count, 3 * usdksl::FLIGHTPLAN_SAMPLES_PER_RUN);
    const Flightplans one(mesh, true, 1);
    ASSERT_TRUE(one.merged());
    ASSERT_GT(one.merge_deviation(), 0.0);
    for (int32_t threads : {2, 3, 8}) {
        const Flightplans many(mesh, true, threads);
        EXPECT_EQ(many.merged(), one.merged());
        EXPECT_EQ(many.merge_deviation(), one.merge_deviation());
        EXPECT_EQ(many.max_abs_coordinate(), one.max_abs_coordinate());
        for (int32_t v = 0; v < mesh.vertex_count; ++v) {
            ASSERT_EQ(many.key_begin(v), one.key_begin(v)) << "vertex " << v << ", " << threads << " threads";
            ASSERT_EQ(many.key_end(v), one.key_end(v)) << "vertex " << v << ", " << threads << " threads";
            EXPECT_EQ(many.vertex_magnitude(v), one.vertex_magnitude(v));
            EXPECT_EQ(many.vertex_deviation(v), one.vertex_deviation(v));
            for (int64_t k = one.key_begin(v); k < one.key_end(v); ++k) {
                ASSERT_EQ(many.key_time(v, k), one.key_time(v, k));
                for (int axis = 0; axis < 3; ++axis) ASSERT_EQ(many.key_coord(v, k, axis), one.key_coord(v, k, axis));
            }
        }
    }
    EXPECT_EQ(one.key_end(1500) - one.key_begin(1500), 1);  // the still vertex keeps one breakpoint
}

TEST(Flightplans, MeshesBuiltTogetherGetTheFlightplansEachGetsAlone) {
    // Runs of several meshes share one pool of work: each mesh's breakpoints
    // must still start at its own first key, merged or not. Merging meshes
    // prefer to break at times the others keep (shared_breakpoints_test.cpp):
    // the tiny one shares no sample time with the large one, so each gets
    // what it gets alone.
    const MeshAnimation large = random_walk(2001, 90, 5, 1e-7);  // several runs
    const MeshAnimation raw = random_walk(700, 90, 6, 1e-7);
    MeshAnimation tiny = random_walk(3, 90, 7, 0.0);
    for (double& t : tiny.times) t += 0.5;
    ASSERT_GT(static_cast<int64_t>(large.times.size()) * large.vertex_count, 2 * usdksl::FLIGHTPLAN_SAMPLES_PER_RUN);
    const std::vector<usdksl::FlightplanRequest> requests{{&large, true}, {&raw, false}, {&tiny, true}, {&large, false}};
    const std::vector<Flightplans> together = Flightplans::build_all(requests, 2);
    ASSERT_EQ(together.size(), requests.size());
    for (size_t r = 0; r < requests.size(); ++r) {
        const MeshAnimation& mesh = *requests[r].mesh;
        const Flightplans alone(mesh, requests[r].merge_collinear, 1);
        const Flightplans& plans = together[r];
        EXPECT_EQ(plans.merged(), alone.merged()) << "mesh " << r;
        EXPECT_EQ(plans.merge_deviation(), alone.merge_deviation());
        EXPECT_EQ(plans.max_abs_coordinate(), alone.max_abs_coordinate());
        ASSERT_EQ(plans.vertex_count(), mesh.vertex_count);
        for (int32_t v = 0; v < mesh.vertex_count; ++v) {
            ASSERT_EQ(plans.key_begin(v), alone.key_begin(v)) << "mesh " << r << " vertex " << v;
            ASSERT_EQ(plans.key_end(v), alone.key_end(v)) << "mesh " << r << " vertex " << v;
            EXPECT_EQ(plans.vertex_magnitude(v), alone.vertex_magnitude(v));
            for (int64_t k = plans.key_begin(v); k < plans.key_end(v); ++k) {
                ASSERT_EQ(plans.key_time(v, k), alone.key_time(v, k));
                for (int axis = 0; axis < 3; ++axis) ASSERT_EQ(plans.key_coord(v, k, axis), alone.key_coord(v, k, axis));
            }
        }
        if (!requests[r].merge_collinear) {
            // Raw samples: every sample is a breakpoint, as authored.
            for (int32_t v = 0; v < mesh.vertex_count; v += 97) {
                ASSERT_EQ(plans.key_end(v) - plans.key_begin(v), static_cast<int64_t>(mesh.times.size()));
                for (size_t k = 0; k < mesh.times.size(); ++k) {
                    const int64_t key = plans.key_begin(v) + static_cast<int64_t>(k);
                    ASSERT_EQ(plans.key_time(v, key), mesh.times[k]);
                    for (int axis = 0; axis < 3; ++axis) {
                        ASSERT_EQ(plans.key_coord(v, key, axis), mesh.points[(k * static_cast<size_t>(mesh.vertex_count) + v) * 3 + axis]);
                    }
                }
            }
        }
    }
    EXPECT_TRUE(together[0].merged());
    EXPECT_FALSE(together[3].merged());
}
