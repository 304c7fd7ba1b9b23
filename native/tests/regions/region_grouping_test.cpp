/// @file region_grouping_test.cpp
/// @brief Rows join a region through a shared vertex on either side only
///        while their spans overlap; a row's span follows the samples at
///        which its faces stay in contact (within the thickness).

#include "region_shapes.hpp"

#include "usdksl/regions/inside_depth.hpp"
#include "usdksl/regions/region_depths.hpp"
#include "usdksl/regions/region_grouping.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

using namespace usdksl;
using namespace usdksl::region_shapes;

namespace {

/// Rows held as columns.
struct Rows {
    std::vector<double> time;
    std::vector<int32_t> mesh_a, face_a, mesh_b, face_b;

    void add(double t, int32_t ma, int32_t fa, int32_t mb, int32_t fb) {
        time.push_back(t);
        mesh_a.push_back(ma);
        face_a.push_back(fa);
        mesh_b.push_back(mb);
        face_b.push_back(fb);
    }
    ContactRows view() const {
        ContactRows rows;
        rows.count = static_cast<int64_t>(time.size());
        rows.time = time.data();
        rows.mesh_a = mesh_a.data();
        rows.face_a = face_a.data();
        rows.mesh_b = mesh_b.data();
        rows.face_b = face_b.data();
        return rows;
    }
};

std::vector<double> integer_times(int count) {
    std::vector<double> times;
    for (int k = 0; k < count; ++k) times.push_back(k);
    return times;
}

/// Face (i, j) of a 4 x 4 sheet.
int32_t face(int i, int j) { return i * 4 + j; }

} // namespace

TEST(RegionGrouping, SharedVerticesJoinRowsOnlyWhileTheirSpansOverlap) {
    // Two sheets ten units apart never touch: every row is a graze, spanning [i0, i0 + 1].
    const StoredMesh low = sheet(4, 0, 1, 0, 1, {0.0}, [](double) { return 0.0; });
    const StoredMesh high = sheet(4, 0, 1, 0, 1, {0.0}, [](double) { return 10.0; });
    const std::vector<MeshView> meshes = {low.view(), high.view()};
    Rows rows;
    rows.add(0.5, 0, face(0, 0), 1, face(0, 0));  // span [0, 1]
    rows.add(1.5, 0, face(1, 1), 1, face(3, 3));  // [1, 2]: shares corner (1, 1) of low with row 0
    rows.add(5.2, 0, face(3, 3), 1, face(3, 3));  // [5, 6]: shares high's face (3, 3) with row 1, years later
    rows.add(5.5, 0, face(0, 0), 1, face(0, 0));  // [5, 6]: row 0's faces again, but far later
    rows.add(5.9, 0, face(2, 2), 1, face(0, 2));  // [5, 6]: corner (3, 3) of low with row 2
    rows.add(7.0, 0, face(2, 2), 1, face(0, 2));  // [7, 8]: starts where none of the others reach
    const RegionGrouping g = group_regions(meshes, rows.view(), integer_times(11), 0.0, 2);
    EXPECT_EQ(g.row_region, (std::vector<int32_t>{0, 0, 1, 2, 1, 3}));
    EXPECT_EQ(g.region_count, 4);
    EXPECT_EQ(g.row_span_first, (std::vector<int32_t>{0, 1, 5, 5, 5, 7}));
    EXPECT_EQ(g.row_span_last, (std::vector<int32_t>{1, 2, 6, 6, 6, 8}));
    EXPECT_EQ(g.row_last_sampled, rows.time) << "a graze's last sampled contact is its own time";
}

TEST(RegionGrouping, AChainOfOverlapsJoinsRowsThatDoNotOverlapEachOther) {
    const StoredMesh low = sheet(4, 0, 1, 0, 1, {0.0}, [](double) { return 0.0; });
    const StoredMesh high = sheet(4, 0, 1, 0, 1, {0.0}, [](double) { return 10.0; });
    const std::vector<MeshView> meshes = {low.view(), high.view()};
    Rows rows;
    // All on low's face (0, 0); spans [0, 1], [1, 2], [2, 3]: the first and the last meet through the middle.
    rows.add(0.5, 0, face(0, 0), 1, face(0, 0));
    rows.add(1.5, 0, face(0, 0), 1, face(2, 0));
    rows.add(2.5, 0, face(0, 0), 1, face(0, 2));
    rows.add(4.5, 0, face(0, 0), 1, face(3, 3));  // [4, 5]: after the chain ends
    const RegionGrouping g = group_regions(meshes, rows.view(), integer_times(11), 0.0, 1);
    EXPECT_EQ(g.row_region, (std::vector<int32_t>{0, 0, 0, 1}));
}

TEST(RegionGrouping, FacesOfOneMeshConnectAcrossSides) {
    const StoredMesh cloth = sheet(4, 0, 1, 0, 1, {0.0}, [](double) { return 0.0; });
    const StoredMesh other = sheet(4, 5, 6, 0, 1, {0.0}, [](double) { return 0.0; });
    const std::vector<MeshView> meshes = {cloth.view(), other.view()};
    Rows rows;
    rows.add(0.5, 0, face(0, 0), 0, face(3, 3));
    rows.add(0.6, 0, face(2, 0), 0, face(1, 1));  // its face_b touches row 0's face_a
    rows.add(0.7, 0, face(3, 0), 1, face(3, 3));  // another mesh pair: never with the self rows
    rows.add(0.8, 0, face(0, 3), 0, face(3, 2));  // face_b shares with row 0's face_b
    const RegionGrouping g = group_regions(meshes, rows.view(), integer_times(3), 0.0, 1);
    EXPECT_EQ(g.row_region, (std::vector<int32_t>{0, 0, 1, 0}));
}

TEST(RegionGrouping, TheSpanFollowsTheContactWithinTheThickness) {
    // low at z = 0; high comes down at a quarter unit per sample, through z = 0 at time 4
    const StoredMesh low = sheet(2, 0, 1, 0, 1, {0.0}, [](double) { return 0.0; });
    const StoredMesh high = sheet(2, 0, 1, 0, 1, {0.0, 10.0}, [](double t) { return 1.0 - 0.25 * t; });
    const std::vector<MeshView> meshes = {low.view(), high.view()};
    Rows rows;
    rows.add(4.0, 0, 0, 1, 0);
    RegionGrouping g = group_regions(meshes, rows.view(), integer_times(11), 0.0, 1);
    EXPECT_EQ(g.row_last_sampled[0], 4.0);
    EXPECT_EQ(g.row_span_first[0], 4);
    EXPECT_EQ(g.row_span_last[0], 5) << "at least one step";
    g = group_regions(meshes, rows.view(), integer_times(11), 0.6, 1);
    EXPECT_EQ(g.row_last_sampled[0], 6.0) << "0.5 below at time 6 is within 0.6, 0.75 at time 7 is not";
    EXPECT_EQ(g.row_span_last[0], 6);
}

TEST(RegionGrouping, AContactHeldStillLastsToTheLastSample) {
    // high comes down onto low by time 4, its last sample: held still after it, it stays in contact
    const StoredMesh low = sheet(2, 0, 1, 0, 1, {0.0}, [](double) { return 0.0; });
    const StoredMesh high = sheet(2, 0.01, 1.01, 0.02, 1.02, {0.0, 4.0}, [](double t) { return 1.0 - 0.25 * t; });
    const std::vector<MeshView> meshes = {low.view(), high.view()};
    Rows rows;
    rows.add(4.0, 0, 0, 1, 0);
    rows.add(4.0, 0, 3, 1, 3);
    const RegionGrouping g = group_regions(meshes, rows.view(), integer_times(11), 0.0, 1);
    EXPECT_EQ(g.row_last_sampled, (std::vector<double>{10.0, 10.0}));
    EXPECT_EQ(g.row_span_last, (std::vector<int32_t>{10, 10}));
    EXPECT_EQ(g.region_count, 1) << "faces 0 and 3 of a 2 x 2 sheet share its middle vertex";
}

TEST(RegionGrouping, RowsTheMeshesDoNotHaveAreRefused) {
    const StoredMesh low = sheet(2, 0, 1, 0, 1, {0.0}, [](double) { return 0.0; });
    const std::vector<MeshView> meshes = {low.view()};
    Rows rows;
    rows.add(0.0, 0, 0, 0, 4);  // a 2 x 2 sheet has faces 0..3
    EXPECT_THROW(group_regions(meshes, rows.view(), integer_times(2), 0.0, 1), std::invalid_argument);
}

/// A static 8 x 8 sheet at z = 0, a little off the origin so that no edge runs through the box's corners.
StoredMesh flat_sheet() { return sheet(8, -2.03, 1.97, -1.98, 2.02, {0.0}, [](double) { return 0.0; }); }

/// A box of half-size 0.5 rising through z = 0: its centre at z = -1 + t / 2 over times 0..4.
StoredMesh rising_box() {
    const StoredMesh resting = box(Vec3::Zero(), Vec3(0.5, 0.5, 0.5));
    StoredMesh cube = resting;
    cube.times = {0.0, 4.0};
    cube.points.clear();
    for (double shift : {-1.0, 1.0})
        for (int v = 0; v < 8; ++v)
            cube.points.insert(cube.points.end(), {resting.points[3 * v], resting.points[3 * v + 1],
                                                   resting.points[3 * v + 2] + shift});
    return cube;
}

TEST(RegionDepths, BoxThroughASheetAtEverySampleOfItsSpan) {
    // A static sheet at z = 0; a box of half-size 0.5 rises through it, centre at z = -1 + t / 2.
    const StoredMesh plane = flat_sheet();
    const StoredMesh cube = rising_box();
    const std::vector<MeshView> meshes = {plane.view(), cube.view()};
    // Every sheet face against the box's bottom (face 0), first touching at time 1.
    Rows rows;
    for (int32_t f = 0; f < 64; ++f) rows.add(1.0, 0, f, 1, 0);
    const std::vector<int32_t> row_region(64, 0);
    const std::vector<int32_t> span_last(64, 4);
    const RowRegions grouping{row_region.data(), span_last.data(), 1};
    const std::vector<double> times = integer_times(5);
    const std::vector<char> every(times.size(), 1);
    const RegionDepthSamples d = measure_region_depths(meshes, rows.view(), grouping, times, every, {0, 1}, 2);
    ASSERT_EQ(d.region.size(), 4u) << "samples 1..4";
    const double accuracy = DEPTH_RELATIVE_ACCURACY * 0.5 * std::sqrt(2.0);  // the sheet's longest edge
    for (size_t i = 0; i < d.region.size(); ++i) {
        EXPECT_EQ(d.sample[i], static_cast<int32_t>(i) + 1);
        const double t = times[d.sample[i]];
        const double expected = std::max(0.0, 0.5 - std::abs(-1.0 + 0.5 * t));
        EXPECT_LE(d.penetration[i], expected + 1e-12) << t;
        EXPECT_GE(d.penetration[i] + accuracy, expected) << t;
    }
    EXPECT_GT(d.penetration[1], 0.45) << "at time 2 the sheet halves the box";
    // the sides are not closed: no penetration is measured
    const RegionDepthSamples open = measure_region_depths(meshes, rows.view(), grouping, times, every, {0, 0}, 1);
    for (double p : open.penetration) EXPECT_TRUE(std::isnan(p));
}

TEST(RegionDepths, AContactBetweenFramesIsMeasuredAtItsFirstAndLastSamples) {
    // Samples every quarter time code over 0..4; the flags mark whole time codes only (frames, say).
    // A static sheet at z = 0; a box of half-size 0.5 rises through it, centre at z = -1 + t / 2.
    const StoredMesh plane = flat_sheet();
    const StoredMesh cube = rising_box();
    const std::vector<MeshView> meshes = {plane.view(), cube.view()};
    std::vector<double> times;
    std::vector<char> whole;
    for (int k = 0; k <= 16; ++k) {
        times.push_back(0.25 * k);
        whole.push_back(k % 4 == 0);
    }
    // Region 0 first touches at 1.1 (its first sample is 1.25) and its span ends at sample 11 (2.75); region 1
    // lies between two whole time codes (2.25 to 2.5); region 2 is one sample long (3.75).
    Rows rows;
    for (int32_t f = 0; f < 64; ++f) rows.add(1.1, 0, f, 1, 0);
    rows.add(2.1, 0, 0, 1, 1);
    rows.add(3.6, 0, 1, 1, 2);
    std::vector<int32_t> row_region(64, 0), span_last(64, 11);
    row_region.insert(row_region.end(), {1, 2});
    span_last.insert(span_last.end(), {10, 15});
    const RowRegions grouping{row_region.data(), span_last.data(), 3};
    const RegionDepthSamples d = measure_region_depths(meshes, rows.view(), grouping, times, whole, {0, 1}, 2);
    EXPECT_EQ(d.region, (std::vector<int32_t>{0, 0, 0, 1, 1, 2}));
    EXPECT_EQ(d.sample, (std::vector<int32_t>{5, 8, 11, 9, 10, 15}))
        << "first (1.25), the whole time code 2 and last (2.75); 2.25 and 2.5; 3.75";
    // The measured samples are those rows of a run that measures every sample.
    const RegionDepthSamples all =
        measure_region_depths(meshes, rows.view(), grouping, times, std::vector<char>(times.size(), 1), {0, 1}, 1);
    for (size_t i = 0; i < d.region.size(); ++i) {
        size_t j = 0;
        while (j < all.region.size() && !(all.region[j] == d.region[i] && all.sample[j] == d.sample[i])) ++j;
        ASSERT_LT(j, all.region.size()) << i;
        EXPECT_EQ(d.penetration[i], all.penetration[j]) << i;
        EXPECT_EQ(d.intersection_length[i], all.intersection_length[j]) << i;
    }
    EXPECT_GT(d.penetration[1], 0.45) << "at time 2 the sheet halves the box";
    EXPECT_THROW(measure_region_depths(meshes, rows.view(), grouping, times, std::vector<char>(3, 1), {0, 1}, 1),
                 std::invalid_argument);
}
