/// @file shared_vertex_clearance_test.cpp
/// @brief The certificate of vertex-sharing triangles clears only steps the
///        narrow phase answers "no contact" on, keeps a pair that moves
///        together cleared, and ends when one folds onto the other.

#include "usdksl/narrow_phase/shared_vertex_clearance.hpp"
#include "usdksl/narrow_phase/triangle_pair.hpp"

#include <gtest/gtest.h>

#include <array>
#include <random>

using namespace usdksl;

namespace {

using Positions = std::array<Vec3, 3>;

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
    std::mt19937 random(20261123);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const auto point = [&](double scale) -> Vec3 { return Vec3(unit(random), unit(random), unit(random)) * scale; };
    int cleared = 0, hits = 0;
    for (double thickness : {0.0, 0.05}) {
        CCDSettings settings;
        settings.thickness = thickness;
        for (int trial = 0; trial < 400; ++trial) {
            const bool edge = trial % 2 == 0;
            const Triangle ids_a{0, 1, 2};
            const Triangle ids_b = edge ? Triangle{1, 0, 3} : Triangle{4, 0, 3};
            Positions a{Vec3(0, 0, 0), point(1.0), point(1.0)};
            Positions b{edge ? a[1] : point(1.0), a[0], point(1.0)};
            SharedVertexClearance clearance;
            clearance.start(ids_a, a, ids_b, b, thickness, settings.tolerance, kMagnitude);
            const Vec3 drift = point(0.1);
            for (int step = 0; step < 8; ++step) {
                Positions a1 = shifted(a, drift);
                a1[1] += point(0.03);
                a1[2] += point(0.03);
                Positions b1{edge ? a1[1] : b[0] + drift + point(0.03), a1[0], b[2] + drift + point(0.03)};
                const bool certified = clearance.holds_at(a1, b1);
                const bool hit = triangle_pair_ccd({ids_a, a, a1}, {ids_b, b, b1}, true, settings).hit;
                EXPECT_FALSE(certified && hit) << "trial " << trial << " step " << step;
                cleared += certified;
                hits += hit;
                if (!certified) break;
                a = a1;
                b = b1;
            }
        }
    }
    EXPECT_GT(cleared, 1000);
    EXPECT_GT(hits, 20);
}
