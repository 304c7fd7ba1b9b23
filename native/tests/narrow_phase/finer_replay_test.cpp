/// @file finer_replay_test.cpp
/// @brief finer_triangle_pair_ccd, worked out from a coarser search's
///        replay, answers exactly as a fresh search at the finer tolerance,
///        on triangle pairs moving through and past each other.

#include "usdksl/narrow_phase/triangle_pair.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <random>

using namespace usdksl;

namespace {

using Positions = std::array<Vec3, 3>;

Vec3 random_point(std::mt19937_64& random, double spread) {
    std::uniform_real_distribution<double> coordinate(-spread, spread);
    return Vec3(coordinate(random), coordinate(random), coordinate(random));
}

/// Triangle B's corners at a step's ends: near a random start (within start_spread), all moved by
/// one random travel plus a little each.
void sweeping_triangle(std::mt19937_64& random, double start_spread, Positions& b0, Positions& b1) {
    const Vec3 start = random_point(random, start_spread), travel = random_point(random, 3.0);
    for (int i = 0; i < 3; ++i) {
        b0[i] = start + random_point(random, 0.6);
        b1[i] = b0[i] + travel + random_point(random, 0.1);
    }
}

bool bit_equal(double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0; }

/// The search settings both tests compare: the check's tolerance and the confirmation's finer one.
struct CoarseAndFiner {
    CCDSettings coarse, finer;
    CoarseAndFiner() {
        coarse.tolerance = 1e-6;
        finer = coarse;
        finer.tolerance = 1e-9;
    }
};

/// Success when the replayed finer answer is the fresh finer search's, bit for bit.
::testing::AssertionResult same_answer(const TrianglePairContact& replayed, const TrianglePairContact& fresh) {
    if (replayed.hit != fresh.hit) return ::testing::AssertionFailure() << "hit " << replayed.hit << " vs " << fresh.hit;
    if (!bit_equal(replayed.toi, fresh.toi))
        return ::testing::AssertionFailure() << "toi " << replayed.toi << " vs " << fresh.toi;
    if (replayed.feature != fresh.feature) return ::testing::AssertionFailure() << "feature differs";
    if (replayed.undecided != fresh.undecided) return ::testing::AssertionFailure() << "undecided differs";
    if (replayed.queries != fresh.queries)
        return ::testing::AssertionFailure() << "queries " << replayed.queries << " vs " << fresh.queries;
    return ::testing::AssertionSuccess();
}

} // namespace

TEST(FinerReplay, AnswersAsAFreshFinerSearchBitForBit) {
    std::mt19937_64 random(1123);
    CoarseAndFiner settings;
    CCDSettings& coarse = settings.coarse;
    CCDSettings& finer = settings.finer;
    FinerReplay replay(finer.tolerance);
    VertexFaceMemo memo;
    int hits = 0, parted = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        // Triangle B sweeps through or past A (thickness 0 or small).
        const Positions a0{random_point(random, 1.0), random_point(random, 1.0), random_point(random, 1.0)};
        const Vec3 drift = random_point(random, 0.05);
        const Positions a1{a0[0] + drift, a0[1] + drift, a0[2] + drift};
        Positions b0, b1;
        sweeping_triangle(random, 1.5, b0, b1);
        coarse.thickness = finer.thickness = trial % 3 == 0 ? 0.01 : 0.0;
        // Self pairs share a vertex id now and then (those primitive pairs are skipped).
        const bool same_mesh = trial % 4 == 0;
        const MovingTriangle a{Triangle{0, 1, 2}, a0, a1};
        const MovingTriangle b{same_mesh ? Triangle{2, 3, 4} : Triangle{0, 1, 2}, b0, b1};
        // With and without a memo: its answers come without a fork.
        const TrianglePairContact first = triangle_pair_ccd(a, b, same_mesh, coarse, trial % 2 ? &memo : nullptr, &replay);
        EXPECT_EQ(first.hit, triangle_pair_ccd(a, b, same_mesh, coarse).hit);
        const TrianglePairContact fresh = triangle_pair_ccd(a, b, same_mesh, finer);
        const TrianglePairContact replayed = finer_triangle_pair_ccd(a, b, same_mesh, finer, replay);
        ASSERT_TRUE(same_answer(replayed, fresh)) << "trial " << trial;
        hits += fresh.hit ? 1 : 0;
        parted += fresh.hit && !bit_equal(first.toi, fresh.toi) ? 1 : 0;
    }
    // The shots exercise both sides: hits whose coarse and finer searches part.
    EXPECT_GT(hits, 200);
    EXPECT_GT(parted, 50) << "of " << hits << " hits";
}

TEST(FinerReplay, FinerMemoAnswersAsAFreshFinerSearchBitForBit) {
    // Two triangles A = (x, s, y) and A2 = (z, s, w) share corner s, which
    // each asks against B second, up to the time its first corner's query
    // left: the memo of finer answers is asked for s both up to the t_max
    // it holds an answer for (then it must answer) and up to another
    // (then it must not).
    std::mt19937_64 random(2027);
    CoarseAndFiner settings;
    CCDSettings& coarse = settings.coarse;
    CCDSettings& finer = settings.finer;
    FinerReplay replay(finer.tolerance);
    VertexFaceMemo coarse_memo, finer_memo;
    int hits = 0, from_memo = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        Vec3 drift = random_point(random, 0.05);
        Vec3 corner0[5];
        for (Vec3& corner : corner0) corner = random_point(random, 0.7);
        Positions b0, b1;
        sweeping_triangle(random, 0.8, b0, b1);
        if (trial % 2 == 1) {
            // Everything in one plane, as on a flat cloth sliding over itself:
            // searches there stay costly (a singular Jacobian gets no
            // parameter-isolating directions), so the memo keeps their finer
            // answers; elsewhere most hits now cost too few boxes to be kept.
            drift.z() = 0.0;
            for (Vec3& corner : corner0) corner.z() = 0.0;
            for (int i = 0; i < 3; ++i) b0[i].z() = b1[i].z() = 0.0;
        }
        coarse.thickness = finer.thickness = trial % 3 == 0 ? 0.01 : 0.0;
        const MovingTriangle b{Triangle{5, 6, 7}, b0, b1};
        // Corner 1 is s.
        const int corners[2][3] = {{0, 1, 2}, {3, 1, 4}};
        for (const auto& ids : corners) {
            MovingTriangle a{Triangle{ids[0], ids[1], ids[2]}, {}, {}};
            for (int i = 0; i < 3; ++i) {
                a.t0[i] = corner0[ids[i]];
                a.t1[i] = corner0[ids[i]] + drift;
            }
            triangle_pair_ccd(a, b, false, coarse, &coarse_memo, &replay);
            const TrianglePairContact fresh = triangle_pair_ccd(a, b, false, finer);
            const TrianglePairContact replayed = finer_triangle_pair_ccd(a, b, false, finer, replay, &finer_memo);
            ASSERT_TRUE(same_answer(replayed, fresh)) << "trial " << trial;
            hits += fresh.hit ? 1 : 0;
            from_memo += replayed.reused_queries;
        }
    }
    EXPECT_GT(hits, 300);
    // The memo must have answered: the coarser search took the repeats from
    // its own memo, without a fork, so the finer search asks its memo.
    EXPECT_GT(from_memo, 30) << "of " << hits << " hits";
}
