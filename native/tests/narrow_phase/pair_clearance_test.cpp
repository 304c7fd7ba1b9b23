/// @file pair_clearance_test.cpp
/// @brief The clearance certificate clears only steps the narrow phase answers
///        "no contact" on, with and without thickness; its separating plane
///        keeps a pair sliding along another cleared however far it slides.

#include "usdksl/narrow_phase/pair_clearance.hpp"
#include "usdksl/narrow_phase/triangle_pair.hpp"

#include "narrow_phase/clearance_trials.hpp"

#include <gtest/gtest.h>

#include <array>

using namespace usdksl;

namespace {

using trials::Positions;
using trials::shifted;

/// Magnitude bound for positions within this many scene units of the origin.
constexpr double kMagnitude = 10.0;

} // namespace

TEST(PairClearance, ACardSlidingOverAnotherStaysClearedByTheSeparatingPlane) {
    const Triangle ids_a{0, 1, 2}, ids_b{0, 1, 2};
    const Positions floor{Vec3(-2, -2, 0), Vec3(2, -2, 0), Vec3(0, 2, 0)};
    const Positions card{Vec3(-1, -1, 0.05), Vec3(0, -1, 0.05), Vec3(-1, 0, 0.05)};
    const double thickness = 0.002;
    PairClearance clearance;
    clearance.start(ids_a, floor, ids_b, card, false, thickness, DEFAULT_CCD_TOLERANCE, kMagnitude);
    // Each step slides the card 0.3 along the floor: 6 times its height above it.
    for (int step = 1; step <= 8; ++step) {
        EXPECT_TRUE(clearance.holds_at(floor, shifted(card, Vec3(0.3 * step, 0.1 * step, 0)))) << "step " << step;
    }
    // Dipping to within reach of the floor (twice the thickness plus 1/1024
    // of the pair's size) ends the certificate.
    EXPECT_FALSE(clearance.holds_at(floor, shifted(card, Vec3(2.4, 0.8, -0.045))));
}

TEST(PairClearance, ClearsOnlyStepsTheNarrowPhaseFindsNoContactOn) {
    // Random pairs drifting over several steps, some coming close enough to
    // touch (within the thickness, even only along a diagonal).
    PairClearance clearance;
    Vec3 velocity_a, velocity_b;
    const auto start = [&](trials::TrialRandom& random, const CCDSettings& settings, int) {
        const trials::TrialPair pair{{0, 1, 2}, {3, 4, 5}, {random.point(1.0), random.point(1.0), random.point(1.0)},
                                      shifted({random.point(1.0), random.point(1.0), random.point(1.0)}, Vec3(0, 0, 0.5 + random.unit()))};
        clearance.start(pair.ids_a, pair.a, pair.ids_b, pair.b, false, settings.thickness, settings.tolerance,
                        kMagnitude);
        velocity_a = random.point(0.1);
        velocity_b = random.point(0.1) - Vec3(0, 0, 0.1);
        return pair;
    };
    const auto move = [&](trials::TrialRandom& random, const trials::TrialPair& pair) {
        return trials::TrialPair{pair.ids_a, pair.ids_b, shifted(pair.a, velocity_a + random.point(0.02)),
                                  shifted(pair.b, velocity_b + random.point(0.02))};
    };
    const auto holds = [&](const trials::TrialPair&, const trials::TrialPair& pair) { return clearance.holds_at(pair.a, pair.b); };
    const trials::ClearanceTrialCounts counts = trials::run_clearance_trials(20240611, false, start, move, holds);
    EXPECT_GT(counts.cleared, 15000);
    EXPECT_GT(counts.hits, 900);
}

TEST(PairClearance, AVertexOffTheCornerAlongTheDiagonalIsNotCleared) {
    // A vertex off a corner along the diagonal, where the per-axis gaps are
    // the smallest fraction of the distance: 0.55 thickness on each axis is
    // 0.95 thickness away, a contact. No certificate may clear it.
    const double thickness = 0.05;
    const Positions a{Vec3(0, 0, 0), Vec3(-1, 0, 0), Vec3(0, -1, 0)};
    const auto off_the_corner = [](double e) {
        return Positions{Vec3(e, e, e), Vec3(e + 1, e, e + 1), Vec3(e, e + 1, e + 1)};
    };
    CCDSettings settings;
    settings.thickness = thickness;
    const Positions b = off_the_corner(0.55 * thickness);
    ASSERT_TRUE(triangle_pair_ccd({{0, 1, 2}, a, a}, {{3, 4, 5}, b, b}, false, settings).hit);
    PairClearance clearance;
    clearance.start({0, 1, 2}, a, {3, 4, 5}, b, false, thickness, settings.tolerance, kMagnitude);
    EXPECT_FALSE(clearance.holds_at(a, b));
    // 0.9 thickness on each axis fits the per-axis cube but is 1.56
    // thicknesses away: not a contact (Euclidean distance decides).
    const Positions apart = off_the_corner(0.9 * thickness);
    EXPECT_FALSE(triangle_pair_ccd({{0, 1, 2}, a, a}, {{3, 4, 5}, apart, apart}, false, settings).hit);
}

TEST(SweptApart, ClearsOnlyStepsTheNarrowPhaseFindsNoContactOn) {
    // Random pairs moving and deforming over several steps, some coming
    // close enough to touch; each step is asked on its own.
    Vec3 velocity_a, velocity_b;
    double reach_thickness = 0.0, size_fraction = 0.0;
    const auto start = [&](trials::TrialRandom& random, const CCDSettings& settings, int) {
        const trials::TrialPair pair{{0, 1, 2}, {3, 4, 5}, {random.point(1.0), random.point(1.0), random.point(1.0)},
                                      shifted({random.point(1.0), random.point(1.0), random.point(1.0)}, Vec3(0, 0, 0.5 + random.unit()))};
        reach_thickness = settings.thickness;
        size_fraction = clearance_size_fraction(settings.tolerance);
        velocity_a = random.point(0.1);
        velocity_b = random.point(0.1) - Vec3(0, 0, 0.1);
        return pair;
    };
    const auto move = [&](trials::TrialRandom& random, const trials::TrialPair& pair) {
        trials::TrialPair next = pair;
        for (int i = 0; i < 3; ++i) {
            next.a[i] += velocity_a + random.point(0.03);
            next.b[i] += velocity_b + random.point(0.03);
        }
        return next;
    };
    const auto holds = [&](const trials::TrialPair& before, const trials::TrialPair& next) {
        const double diameter = std::max(pair_box_diagonal(before.a, before.b), pair_box_diagonal(next.a, next.b));
        return swept_apart(before.a, next.a, before.b, next.b,
                           clearance_reach(reach_thickness, size_fraction, diameter, 0.0, kMagnitude));
    };
    const trials::ClearanceTrialCounts counts = trials::run_clearance_trials(20261124, false, start, move, holds);
    EXPECT_GT(counts.cleared, 10000);
    EXPECT_GT(counts.hits, 900);
}
