/// @file shared_vertex_clearance_test.cpp
/// @brief The certificate of vertex-sharing triangles clears only steps the
///        narrow phase answers "no contact" on, keeps a pair that moves or
///        turns together cleared, and ends when one folds onto the other.

#include "usdksl/narrow_phase/shared_vertex_clearance.hpp"
#include "usdksl/narrow_phase/triangle_pair.hpp"

#include "narrow_phase/clearance_trials.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <array>
#include <cmath>

using namespace usdksl;

namespace {

using trials::Positions;
using trials::shifted;

/// Positions turned by `turn` about `centre`.
Positions turned(const Positions& p, const Eigen::Matrix3d& turn, const Vec3& centre) {
    return {centre + turn * (p[0] - centre), centre + turn * (p[1] - centre), centre + turn * (p[2] - centre)};
}

/// Magnitude bound for positions within this many scene units of the origin.
constexpr double kMagnitude = 10.0;


/// Two triangles of a cloth's fan around vertex 0 that share only it, at an
/// angle of 90 degrees between them.
const Triangle kFanA{0, 1, 2}, kFanB{3, 0, 4};
const Positions kFanAt{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.7, 0.7, 0)};
const Positions kFanBt{Vec3(-0.7, 0.7, 0), Vec3(0, 0, 0), Vec3(-1, 0, 0)};

/// A pair folded almost flat: A in the plane z = 0 with its corner 0 shared,
/// B hinged on A's edge (0, 1) or fanned about vertex 0 (`edge`), its free
/// corners over A at a height up to `largest_gap` (scene units).
trials::TrialPair nearly_folded_pair(trials::TrialRandom& random, bool edge, double largest_gap) {
    const double gap = 0.02 + largest_gap * std::abs(random.unit());
    const Positions a{Vec3(0, 0, 0), Vec3(1, 0.2 * random.unit(), 0), Vec3(0.5 + 0.3 * random.unit(), 1, 0)};
    const Vec3 free_b(0.5 + 0.3 * random.unit(), 0.3 + 0.6 * std::abs(random.unit()), gap);
    return {{0, 1, 2}, edge ? Triangle{1, 0, 3} : Triangle{4, 0, 3}, a,
            {edge ? a[1] : Vec3(0.9, 0.6 * random.unit(), gap), a[0], free_b}};
}

} // namespace

TEST(SharedVertexClearance, APairMovingTogetherStaysCleared) {
    // Two cloth triangles sharing the edge (0, 1), flat, translated each step.
    const Triangle ids_a{0, 1, 2}, ids_b{1, 0, 3};
    const Positions a{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    const Positions b{Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(1, -1, 0)};
    SharedVertexClearance clearance;
    clearance.start(ids_a, a, ids_b, b, kMagnitude);
    for (int step = 1; step <= 20; ++step) {
        const Vec3 from(0.3 * (step - 1), -0.2 * (step - 1), 0.1 * (step - 1));
        const Vec3 by(0.3 * step, -0.2 * step, 0.1 * step);
        EXPECT_TRUE(clearance.holds_over(ids_a, shifted(a, from), shifted(a, by), ids_b, shifted(b, from),
                                         shifted(b, by), 0.001, DEFAULT_CCD_TOLERANCE))
            << "step " << step;
    }
}

TEST(SharedVertexClearance, APairTurningTogetherStaysCleared) {
    // A fan pair (sharing a vertex) and a hinged pair (sharing an edge) turn
    // a whole turn about a tilted axis through a point off the pair, 10
    // degrees a step, while moving: the drift from where they started grows
    // to twice their size, so only a proof that turns with them keeps them
    // cleared.
    const Triangle hinge_a{0, 1, 2}, hinge_b{1, 0, 3};
    const Positions hinge_at{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.4, 0.9, 0.1)};
    const Positions hinge_bt{Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(0.6, -0.8, 0.2)};
    const Vec3 axis = Vec3(0.3, -1.0, 0.5).normalized();
    const Vec3 centre(2.0, -1.0, 0.5);
    const auto at = [&](int step, const Positions& p) {
        const Eigen::Matrix3d turn = Eigen::AngleAxisd(step * M_PI / 18.0, axis).toRotationMatrix();
        return shifted(turned(p, turn, centre), Vec3(0.05 * step, 0.0, -0.02 * step));
    };
    for (const bool hinged : {false, true}) {
        const Triangle& ids_a = hinged ? hinge_a : kFanA;
        const Triangle& ids_b = hinged ? hinge_b : kFanB;
        const Positions& a = hinged ? hinge_at : kFanAt;
        const Positions& b = hinged ? hinge_bt : kFanBt;
        SharedVertexClearance clearance;
        clearance.start(ids_a, a, ids_b, b, kMagnitude);
        for (int step = 1; step <= 36; ++step) {
            EXPECT_TRUE(clearance.holds_over(ids_a, at(step - 1, a), at(step, a), ids_b, at(step - 1, b), at(step, b),
                                             0.001, DEFAULT_CCD_TOLERANCE))
                << "step " << step << (hinged ? ", hinged pair" : ", fan pair");
        }
    }
}

TEST(SharedVertexClearance, FoldingOneTriangleOntoTheOtherEndsIt) {
    // B turns about the shared edge, or about the shared vertex alone, until
    // it lies on A: before it gets there, the certificate must have stopped
    // clearing.
    const double thickness = 0.01;
    CCDSettings settings;
    settings.thickness = thickness;
    for (const bool shares_edge : {true, false}) {
        const Triangle ids_a{0, 1, 2};
        const Triangle ids_b = shares_edge ? Triangle{0, 1, 3} : Triangle{0, 4, 3};
        const Positions a{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0)};
        const auto folded = [&](double angle) {
            const Vec3 free(0.5, -std::cos(angle), std::sin(angle));
            // Sharing only vertex 0, B's second corner turns with its third.
            const Vec3 second = shares_edge ? Vec3(1, 0, 0) : Vec3(0.8, -0.6 * std::cos(angle), 0.6 * std::sin(angle));
            return Positions{Vec3(0, 0, 0), second, free};
        };
        SharedVertexClearance clearance;
        clearance.start(ids_a, a, ids_b, folded(0.0), kMagnitude);
        bool ended = false;
        const int steps = 64;
        for (int step = 1; step <= steps && !ended; ++step) {
            const double before = M_PI * (step - 1) / steps, after = M_PI * step / steps;
            const bool hit =
                triangle_pair_ccd({ids_a, a, a}, {ids_b, folded(before), folded(after)}, true, settings).hit;
            ended = !clearance.holds_over(ids_a, a, a, ids_b, folded(before), folded(after),
                                          thickness, settings.tolerance);
            EXPECT_FALSE(!ended && hit) << "step " << step << (shares_edge ? " sharing an edge" : " sharing a vertex");
        }
        EXPECT_TRUE(ended) << (shares_edge ? "sharing an edge" : "sharing a vertex");
    }
}

TEST(SharedVertexClearance, ClearsOnlyStepsTheNarrowPhaseFindsNoContactOn) {
    // Random vertex-sharing pairs (one shared vertex or a shared edge) whose
    // free vertices wander over several steps, some folding into contact,
    // while the whole pair drifts and, in every other trial, turns by up to
    // a fifth of a radian a step (the plane proof's case).
    SharedVertexClearance clearance;
    Vec3 drift;
    Eigen::Matrix3d turn;
    bool edge = false;
    const auto start = [&](trials::TrialRandom& random, const CCDSettings&, int trial) {
        edge = trial % 2 == 0;
        const Positions a{Vec3(0, 0, 0), random.point(1.0), random.point(1.0)};
        const trials::TrialPair pair{{0, 1, 2}, edge ? Triangle{1, 0, 3} : Triangle{4, 0, 3}, a,
                                      {edge ? a[1] : random.point(1.0), a[0], random.point(1.0)}};
        clearance.start(pair.ids_a, pair.a, pair.ids_b, pair.b, kMagnitude);
        drift = random.point(0.1);
        const Vec3 axis = random.point(1.0);
        const double angle = trial % 4 < 2 ? 0.0 : 0.2 * random.unit();
        turn = axis.norm() > 0.0 ? Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix()
                                 : Eigen::Matrix3d::Identity();
        return pair;
    };
    const auto move = [&](trials::TrialRandom& random, const trials::TrialPair& pair) {
        const Vec3 centre = pair.a[0];
        Positions a1 = shifted(turned(pair.a, turn, centre), drift);
        a1[1] += random.point(0.03);
        a1[2] += random.point(0.03);
        const Positions b_turned = shifted(turned(pair.b, turn, centre), drift);
        const Positions b1{edge ? a1[1] : b_turned[0] + random.point(0.03), a1[0], b_turned[2] + random.point(0.03)};
        return trials::TrialPair{pair.ids_a, pair.ids_b, a1, b1};
    };
    CCDSettings settings;
    const auto holds = [&](const trials::TrialPair& before, const trials::TrialPair& next) {
        // The trials' thicknesses in turn: the reach follows the one being run.
        return clearance.holds_over(before.ids_a, before.a, next.a, before.ids_b, before.b, next.b,
                                    settings.thickness, settings.tolerance);
    };
    const auto start_at = [&](trials::TrialRandom& random, const CCDSettings& run, int trial) {
        settings = run;
        return start(random, run, trial);
    };
    const trials::ClearanceTrialCounts counts = trials::run_clearance_trials(20261123, true, start_at, move, holds);
    EXPECT_GT(counts.cleared, 20000);
    EXPECT_GT(counts.hits, 250);
}

TEST(SharedVertexClearance, ClearsOnlyStepsTheNarrowPhaseFindsNoContactOnWhenNearlyFolded) {
    // Pairs folded almost flat onto each other (hinged on an edge, or fanned
    // about a vertex with B turned over A), their free vertices a few
    // thicknesses off the other triangle and wandering by as much a step:
    // near misses and contacts within every proof's reach of each other.
    SharedVertexClearance clearance;
    bool edge = false;
    CCDSettings settings;
    const auto start = [&](trials::TrialRandom& random, const CCDSettings& run, int trial) {
        settings = run;
        edge = trial % 2 == 0;
        const trials::TrialPair pair = nearly_folded_pair(random, edge, 0.1);
        clearance.start(pair.ids_a, pair.a, pair.ids_b, pair.b, kMagnitude);
        return pair;
    };
    const auto move = [&](trials::TrialRandom& random, const trials::TrialPair& pair) {
        Positions a1 = pair.a;
        a1[1] += random.point(0.02);
        a1[2] += random.point(0.02);
        const Positions b1{edge ? a1[1] : pair.b[0] + random.point(0.02), a1[0], pair.b[2] + random.point(0.02)};
        return trials::TrialPair{pair.ids_a, pair.ids_b, a1, b1};
    };
    const auto holds = [&](const trials::TrialPair& before, const trials::TrialPair& next) {
        return clearance.holds_over(before.ids_a, before.a, next.a, before.ids_b, before.b, next.b,
                                    settings.thickness, settings.tolerance);
    };
    const trials::ClearanceTrialCounts counts = trials::run_clearance_trials(20261127, true, start, move, holds);
    EXPECT_GT(counts.cleared, 5000);
    EXPECT_GT(counts.hits, 1000) << counts.cleared;
}

TEST(SharedVertexClearance, TheAllowanceIsTravelTheProofSurvives) {
    // After a cleared step, each corner other than the shared vertex is moved
    // relative to it straight towards the other triangle, by a tenth of the
    // allowance a step, for as long as the total stays within it, while the
    // whole pair drifts: every such step must still be cleared at its end
    // alone, and the narrow phase must find no contact on it.
    trials::TrialRandom random(20261127);
    int checked_steps = 0, allowed_pairs = 0;
    for (const double thickness : trials::kTrialThicknesses) {
        CCDSettings settings;
        settings.thickness = thickness;
        for (int trial = 0; trial < 2000; ++trial) {
            const bool edge = trial % 2 == 0;
            trials::TrialPair pair = nearly_folded_pair(random, edge, 0.3);
            // Every other pair of trials has B turned away from A across the shared vertex.
            if (trial % 4 >= 2) {
                const double gap = pair.b[2].z();
                pair.b = {edge ? pair.a[1] : Vec3(0.9, -0.8, 0.1 * random.unit()), pair.a[0], Vec3(0.4, -0.9, gap)};
            }
            const Triangle &ids_a = pair.ids_a, &ids_b = pair.ids_b;
            const Positions &a = pair.a, &b = pair.b;
            SharedVertexClearance clearance;
            clearance.start(ids_a, a, ids_b, b, kMagnitude);
            Positions a1 = shifted(a, random.point(0.05)), b1 = shifted(b, a1[0] - a[0]);
            b1[2] += random.point(0.01);
            if (!clearance.holds_over(ids_a, a, a1, ids_b, b, b1, thickness, settings.tolerance)) continue;
            const double allowance = clearance.allowance();
            if (!(allowance > 0.0)) continue;
            ++allowed_pairs;
            const double step = 0.1 * allowance;
            Positions from_a = a1, from_b = b1;
            for (int k = 1; k <= 9; ++k) {
                const Vec3 centre_a = (from_a[0] + from_a[1] + from_a[2]) / 3.0;
                const Vec3 centre_b = (from_b[0] + from_b[1] + from_b[2]) / 3.0;
                const Vec3 drift = random.point(0.05);
                Positions to_a = shifted(from_a, drift), to_b = shifted(from_b, drift);
                // Every corner but the shared one (index 0 of A, 1 of B) towards the other triangle.
                for (int i = 1; i < 3; ++i) to_a[i] += step * (centre_b - from_a[i]).normalized();
                to_b[2] += step * (centre_a - from_b[2]).normalized();
                if (edge) to_b[0] = to_a[1];
                else to_b[0] += step * (centre_a - from_b[0]).normalized();
                to_b[1] = to_a[0];
                EXPECT_TRUE(clearance.holds_at_end(to_a, to_b)) << "trial " << trial << " step " << k;
                EXPECT_FALSE(triangle_pair_ccd({ids_a, from_a, to_a}, {ids_b, from_b, to_b}, true, settings).hit)
                    << "trial " << trial << " step " << k;
                ++checked_steps;
                from_a = to_a;
                from_b = to_b;
            }
        }
    }
    EXPECT_GT(allowed_pairs, 1000);
    EXPECT_GT(checked_steps, 9000);
}

TEST(SharedVertexClearance, OnlyAPlaneRulesOutAPiercingEdge) {
    // A's edge between its free corners passes through B's inside, far from
    // B's edges and from its own ends: every tested primitive pair is apart,
    // so a proof may hold, but no plane through the shared vertex does.
    const Triangle ids_a{0, 1, 2}, ids_b{0, 3, 4};
    const Positions a{Vec3(0, 0, 0), Vec3(0.5, 0.5, 1), Vec3(0.5, 0.5, -1)};
    const Positions b{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0)};
    ASSERT_TRUE(edge_pierces_triangle(ids_a, a, ids_b, b));
    SharedVertexClearance pierced;
    pierced.start(ids_a, a, ids_b, b, kMagnitude);
    ASSERT_TRUE(pierced.holds_over(ids_a, a, a, ids_b, b, b, 0.01, DEFAULT_CCD_TOLERANCE));
    EXPECT_FALSE(pierced.separated_by_plane());
    // The fan pair is held apart by a plane.
    SharedVertexClearance fan;
    fan.start(kFanA, kFanAt, kFanB, kFanBt, kMagnitude);
    ASSERT_TRUE(fan.holds_over(kFanA, kFanAt, kFanAt, kFanB, kFanBt, kFanBt, 0.01, DEFAULT_CCD_TOLERANCE));
    EXPECT_TRUE(fan.separated_by_plane());
}
