/// @file euclidean_thickness_test.cpp
/// @brief Above thickness 0 a contact means Euclidean distance within the
///        thickness: on random queries built to pass near it, a reported
///        contact is within the thickness (plus the search's spatial
///        resolution) at its time of impact, by the static distance
///        functions, which share nothing with the root search. The root
///        search's per-axis cube alone would accept pairs up to sqrt(3)
///        thicknesses apart.

#include "usdksl/geometry/primitive_distance.hpp"
#include "near_queries.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

using namespace usdksl;

namespace {

constexpr int kTrials = 4000;
/// Distance a reported contact may lie beyond the thickness (scene units,
/// for unit-sized queries): the search narrows (t, u, v) to about the
/// tolerance, over which the pair moves by about the tolerance times its
/// speed and size (both below 3 here); the cube's excess reaches 0.7 x 0.3.
constexpr double kSpatialSlack = 1e-4;

using Query = test_queries::NearQuery;

/// A near query (see near_query) with a thickness from 0.01 to 0.3.
Query near_query(std::mt19937_64& random, bool edge_edge) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Query q = test_queries::near_query(random, edge_edge);
    q.thickness = 0.01 + 0.29 * unit(random);
    return q;
}

double distance_at(const Query& q, bool edge_edge, double t) {
    std::array<Vec3, 4> p;
    for (int i = 0; i < 4; ++i) p[i] = q.start[i] + t * (q.end[i] - q.start[i]);
    return std::sqrt(edge_edge ? segment_segment_distance_squared(p[0], p[1], p[2], p[3])
                               : point_triangle_distance_squared(p[0], p[1], p[2], p[3]));
}

void expect_contacts_within_the_thickness(bool edge_edge, uint64_t seed) {
    std::mt19937_64 random(seed);
    int hits_after_start = 0;
    for (int trial = 0; trial < kTrials; ++trial) {
        const Query q = near_query(random, edge_edge);
        const CCDResult result = test_queries::ccd_answer(q, edge_edge);
        if (!result.hit || result.undecided) continue;
        if (result.toi > 0.0) ++hits_after_start;
        ASSERT_LE(distance_at(q, edge_edge, result.toi), q.thickness + kSpatialSlack)
            << "trial " << trial << ": contact reported at " << result.toi << " with the pair beyond the thickness";
    }
    // The trials must reach contact during the step, not only start in it.
    EXPECT_GT(hits_after_start, kTrials / 20);
}

} // namespace

TEST(EuclideanThickness, VertexFaceContactIsWithinTheThicknessAtItsTime) {
    for (uint64_t seed : {11u, 12u}) expect_contacts_within_the_thickness(false, seed);
}

TEST(EuclideanThickness, EdgeEdgeContactIsWithinTheThicknessAtItsTime) {
    for (uint64_t seed : {13u, 14u}) expect_contacts_within_the_thickness(true, seed);
}
