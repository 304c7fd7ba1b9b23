/// @file collinear_merge_test.cpp
/// @brief Merge walks of several vertices taking turns on one thread keep
///        exactly the breakpoints and deviation that one vertex's walk keeps.

#include "animations.hpp"

#include "../../src/flightplan/collinear_merge.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

using usdksl::align_collinear_samples;
using usdksl::COLLINEAR_MERGE_LANES;
using usdksl::MeshAnimation;
using usdksl::merge_collinear_samples;
using usdksl::merge_collinear_samples_of;
using usdksl::animations::random_walk;

namespace {

/// A random walk (straight stretches, some noisy) whose vertices 3, 11 and 17
/// never move and vertex 5 moves at one sample only, so that walks of
/// different lengths take turns.
MeshAnimation mixed_walks(double noise) {
    MeshAnimation mesh = random_walk(23, 40, 7, noise);
    const size_t n = static_cast<size_t>(mesh.vertex_count);
    for (size_t k = 1; k < mesh.times.size(); ++k) {
        for (size_t v : {3, 11, 17, 5}) {
            for (size_t axis = 0; axis < 3; ++axis) {
                const double first = mesh.points[v * 3 + axis];
                mesh.points[(k * n + v) * 3 + axis] = v == 5 && k == 20 ? first + 0.25 : first;
            }
        }
    }
    return mesh;
}

} // namespace

TEST(CollinearMerge, WalksTakingTurnsKeepWhatOneWalkKeeps) {
    for (double noise : {0.0, 1e-9, 1e-3}) {
        const MeshAnimation mesh = mixed_walks(noise);
        for (int32_t count = 1; count <= COLLINEAR_MERGE_LANES; ++count) {
            for (int32_t first = 0; first + count <= mesh.vertex_count; first += 5) {
                std::vector<int64_t> kept[COLLINEAR_MERGE_LANES];
                double deviation[COLLINEAR_MERGE_LANES];
                merge_collinear_samples_of(mesh, first, count, kept, deviation);
                for (int32_t i = 0; i < count; ++i) {
                    std::vector<int64_t> alone;
                    const double alone_deviation = merge_collinear_samples(mesh, first + i, nullptr, alone);
                    EXPECT_EQ(kept[i], alone) << "noise " << noise << ", vertex " << first + i;
                    EXPECT_EQ(deviation[i], alone_deviation) << "noise " << noise << ", vertex " << first + i;
                }
            }
        }
    }
}

TEST(CollinearMerge, AStillVertexKeepsItsFirstSampleAloneAndOneMovingOnceBreaksAroundTheMove) {
    const MeshAnimation mesh = mixed_walks(0.0);
    std::vector<int64_t> kept[COLLINEAR_MERGE_LANES];
    double deviation[COLLINEAR_MERGE_LANES];
    merge_collinear_samples_of(mesh, 3, 3, kept, deviation);
    EXPECT_EQ(kept[0], std::vector<int64_t>({0}));                       // vertex 3, still
    EXPECT_EQ(kept[2], std::vector<int64_t>({0, 19, 20, 21, 39}));       // vertex 5: there and back at sample 20
    EXPECT_EQ(deviation[0], 0.0);
    EXPECT_GT(kept[1].size(), 2u);                                       // vertex 4, a random walk
}

TEST(CollinearMerge, AligningGoesOnFromTheFirstMovedBreakAndKeepsWhatAWholeWalkKeeps) {
    // Straight stretches of one to six samples break at many samples; random
    // popularity moves some breaks early in a walk, some late, some none.
    std::mt19937 random(29);
    std::uniform_int_distribution<int64_t> kept_by(0, 40);
    int moved = 0;
    for (double noise : {0.0, 1e-9, 1e-3}) {
        const MeshAnimation mesh = mixed_walks(noise);
        for (int trial = 0; trial < 4; ++trial) {
            std::vector<int64_t> popularity(mesh.times.size());
            for (int64_t& count : popularity) count = kept_by(random);
            for (int32_t v = 0; v < mesh.vertex_count; ++v) {
                std::vector<int64_t> whole;
                const double whole_deviation = merge_collinear_samples(mesh, v, popularity.data(), whole);
                std::vector<int64_t> greedy;
                const double greedy_deviation = merge_collinear_samples(mesh, v, nullptr, greedy);
                std::vector<int64_t> aligned = greedy;
                const double deviation = align_collinear_samples(mesh, v, popularity.data(), aligned, greedy_deviation);
                EXPECT_EQ(aligned, whole) << "noise " << noise << ", vertex " << v;
                EXPECT_EQ(deviation, whole_deviation) << "noise " << noise << ", vertex " << v;
                moved += aligned != greedy;
            }
        }
    }
    EXPECT_GT(moved, 20);  // the trials do move breaks
}
