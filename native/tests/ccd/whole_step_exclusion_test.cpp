/// @file whole_step_exclusion_test.cpp
/// @brief A query the CCD answers "no contact" has no point of its step and
///        parameter domain within the thickness: checked by sampling on
///        random queries built to graze the thickness, where a filter in front of
///        the root search that trusts a bound too small (or a corner set too
///        small) answers "no contact" wrongly.

#include "near_queries.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

using namespace usdksl;

namespace {

constexpr int kTrials = 4000;
/// Samples per parameter (t, u, v) of the check.
constexpr int kSamples = 24;

using Query = test_queries::NearQuery;

/// A near query (see near_query) with no thickness a quarter of the time,
/// else up to 0.3: its distance function passes about that far from the origin.
Query grazing_query(std::mt19937_64& random, bool edge_edge) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Query q = test_queries::near_query(random, edge_edge);
    q.thickness = random() % 4 == 0 ? 0.0 : 0.3 * unit(random);
    return q;
}

/// Smallest |F| over the samples: the CCD may not answer "no contact" for a
/// step that comes within the thickness (it may for one that only enters
/// the cube max_k |F_k| <= thickness around that ball).
double sampled_distance(const Query& q, bool edge_edge) {
    double best = INFINITY;
    for (int it = 0; it <= kSamples; ++it) {
        const double t = static_cast<double>(it) / kSamples;
        std::array<Vec3, 4> p;
        for (int i = 0; i < 4; ++i) p[i] = q.start[i] + t * (q.end[i] - q.start[i]);
        for (int iu = 0; iu <= kSamples; ++iu) {
            for (int iv = 0; iv <= kSamples; ++iv) {
                const double u = static_cast<double>(iu) / kSamples, v = static_cast<double>(iv) / kSamples;
                Vec3 f;
                if (edge_edge) {
                    f = (p[0] + u * (p[1] - p[0])) - (p[2] + v * (p[3] - p[2]));
                } else {
                    if (iu + iv > kSamples) continue;
                    f = p[0] - (p[1] + u * (p[2] - p[1]) + v * (p[3] - p[1]));
                }
                best = std::min(best, f.norm());
            }
        }
    }
    return best;
}

void expect_no_missed_sample(bool edge_edge, uint64_t seed) {
    std::mt19937_64 random(seed);
    int misses_near_contact = 0;
    for (int trial = 0; trial < kTrials; ++trial) {
        const Query q = grazing_query(random, edge_edge);
        const CCDResult result = test_queries::ccd_answer(q, edge_edge);
        if (result.hit) continue;
        const double distance = sampled_distance(q, edge_edge);
        ASSERT_GT(distance, q.thickness) << "trial " << trial << ": no contact answered, yet a sample is within the thickness";
        if (distance < 1.5 * q.thickness) ++misses_near_contact;
    }
    // The trials must graze: enough "no contact" answers come within 1.5
    // thicknesses for a bound that is too tight to show.
    EXPECT_GT(misses_near_contact, kTrials / 40);
}

} // namespace

TEST(WholeStepExclusion, VertexFaceNoContactHasNoSampleWithinTheThickness) {
    for (uint64_t seed : {1u, 2u}) expect_no_missed_sample(false, seed);
}

TEST(WholeStepExclusion, EdgeEdgeNoContactHasNoSampleWithinTheThickness) {
    for (uint64_t seed : {3u, 4u}) expect_no_missed_sample(true, seed);
}
