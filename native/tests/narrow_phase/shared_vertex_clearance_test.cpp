/// @file shared_vertex_clearance_test.cpp
/// @brief The certificate of vertex-sharing triangles clears only steps the
///        narrow phase answers "no contact" on, keeps a pair that moves
///        together cleared, and ends when one folds onto the other.

#include "usdksl/narrow_phase/shared_vertex_clearance.hpp"
#include "usdksl/narrow_phase/triangle_pair.hpp"

#include "narrow_phase/clearance_trials.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

using namespace usdksl;

namespace {

using trials::Positions;

Positions shifted(const Positions& p, const Vec3& by) { return {p[0] + by, p[1] + by, p[2] + by}; }

/// Magnitude bound for positions within this many scene units of the origin.
constexpr double kMagnitude = 10.0;

} // namespace

TEST(SharedVertexClearance, APairMovingTogetherStaysCleared) {
    // Two cloth triangles sharing the edge (0, 1), flat, translated each step.
    const Triangle ids_a{0, 1, 2}, ids_b{1, 0, 3};
    const Positions a{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    const Positions b{Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(1, -1, 0)};
    SharedVertexClearance clearance;
    clearance.start(ids_a, a, ids_b, b, 0.001, DEFAULT_CCD_TOLERANCE, kMagnitude);
    for (int step = 1; step <= 20; ++step) {
        const Vec3 by(0.3 * step, -0.2 * step, 0.1 * step);
        EXPECT_TRUE(clearance.holds_at(shifted(a, by), shifted(b, by))) << "step " << step;
    }
}

TEST(SharedVertexClearance, FoldingOneTriangleOntoTheOtherEndsIt) {
    // B turns about the shared edge until it lies on A: before it gets there,
    // the certificate must have stopped clearing.
    const Triangle ids_a{0, 1, 2}, ids_b{0, 1, 3};
    const Positions a{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0)};
    const auto folded = [](double angle) {
        return Positions{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, -std::cos(angle), std::sin(angle))};
    };
    const double thickness = 0.01;
    CCDSettings settings;
    settings.thickness = thickness;
    SharedVertexClearance clearance;
    clearance.start(ids_a, a, ids_b, folded(0.0), thickness, settings.tolerance, kMagnitude);
    bool ended = false;
    const int steps = 64;
    for (int step = 1; step <= steps && !ended; ++step) {
        const double before = M_PI * (step - 1) / steps, after = M_PI * step / steps;
        const bool hit = triangle_pair_ccd({ids_a, a, a}, {ids_b, folded(before), folded(after)}, true, settings).hit;
        ended = !clearance.holds_at(a, folded(after));
        EXPECT_FALSE(!ended && hit) << "step " << step;
    }
    EXPECT_TRUE(ended);
}

TEST(SharedVertexClearance, ClearsOnlyStepsTheNarrowPhaseFindsNoContactOn) {
    // Random vertex-sharing pairs (one shared vertex or a shared edge) whose
    // free vertices wander over several steps, some folding into contact.
    SharedVertexClearance clearance;
    Vec3 drift;
    bool edge = false;
    const auto start = [&](trials::TrialRandom& random, const CCDSettings& settings, int trial) {
        edge = trial % 2 == 0;
        const Positions a{Vec3(0, 0, 0), random.point(1.0), random.point(1.0)};
        const trials::TrialPair pair{{0, 1, 2}, edge ? Triangle{1, 0, 3} : Triangle{4, 0, 3}, a,
                                      {edge ? a[1] : random.point(1.0), a[0], random.point(1.0)}};
        clearance.start(pair.ids_a, pair.a, pair.ids_b, pair.b, settings.thickness, settings.tolerance, kMagnitude);
        drift = random.point(0.1);
        return pair;
    };
    const auto move = [&](trials::TrialRandom& random, const trials::TrialPair& pair) {
        Positions a1 = shifted(pair.a, drift);
        a1[1] += random.point(0.03);
        a1[2] += random.point(0.03);
        const Positions b1{edge ? a1[1] : pair.b[0] + drift + random.point(0.03), a1[0], pair.b[2] + drift + random.point(0.03)};
        return trials::TrialPair{pair.ids_a, pair.ids_b, a1, b1};
    };
    const auto holds = [&](const trials::TrialPair& pair) { return clearance.holds_at(pair.a, pair.b); };
    const trials::ClearanceTrialCounts counts = trials::run_clearance_trials(20261123, true, start, move, holds);
    EXPECT_GT(counts.cleared, 20000);
    EXPECT_GT(counts.hits, 250);
}
