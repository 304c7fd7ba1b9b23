/// @file plane_kept_pile_test.cpp
/// @brief A pile of tilted cards that sway together, slide over each other
///        and finally tip onto each other gets exactly brute force's contacts
///        from the kinetic check, with planes keeping card pairs whole on the
///        way (kinetic/node_plane.hpp); two cards sinking onto each other
///        sleep on their plane and still touch when they do.

#include "animations.hpp"
#include "usdksl/collision/check.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <tuple>
#include <vector>

using namespace usdksl;

namespace {

using PairKey = std::tuple<int32_t, int32_t, int32_t, int32_t>;

std::map<PairKey, double> first_contacts(const std::vector<MeshAnimation>& meshes, Method method, double thickness,
                                         Counters* counters = nullptr) {
    std::vector<std::pair<int32_t, int32_t>> pairs;
    for (int32_t a = 0; a < static_cast<int32_t>(meshes.size()); ++a) {
        for (int32_t b = a; b < static_cast<int32_t>(meshes.size()); ++b) pairs.push_back({a, b});
    }
    CheckOptions options;
    options.method = method;
    options.ccd.thickness = thickness;
    options.t_begin = meshes[0].times.front();
    options.t_end = meshes[0].times.back();
    const CheckResult result = find_contacts(meshes, pairs, options);
    if (counters) *counters = result.counters;
    std::map<PairKey, double> out;
    for (const Contact& c : result.contacts) out[{c.mesh_a, c.tri_a, c.mesh_b, c.tri_b}] = c.time;
    return out;
}

/// Five tilted cards stacked `gap` apart along their normal, swaying together
/// on curves and sliding over each other; from sample 12 on the top card tips
/// about its near edge until its far edge passes through the card below.
std::vector<MeshAnimation> tipping_pile(double gap, int samples) {
    const Eigen::Matrix3d r = animations::tilt();
    std::vector<MeshAnimation> pile;
    for (int level = 0; level < 5; ++level) {
        pile.push_back(animations::sheet(4, samples, [&, level](double x, double z, int k) {
            const double t = static_cast<double>(k);
            Vec3 local(x + 0.02 * level * std::sin(0.3 * t), gap * level, z + 0.015 * level * t);
            if (level == 4 && k > 12) {
                const double angle = 0.06 * (k - 12);  // about the card's edge x = 0
                local = Vec3(local[0] * std::cos(angle), gap * level - local[0] * std::sin(angle), local[2]);
            }
            const Vec3 sway(0.3 * std::sin(0.2 * t), 0.1 * t - 0.004 * t * t, 0.2 * std::cos(0.25 * t));
            return Vec3(r * local + sway);
        }));
    }
    return pile;
}

} // namespace

TEST(PlaneKeptPile, ATippingPileGetsBruteForcesContactsWithPlanesKeepingCardPairsWhole) {
    for (double thickness : {0.0, 0.004}) {
        const std::vector<MeshAnimation> pile = tipping_pile(0.03, 30);
        const auto brute = first_contacts(pile, Method::BruteForce, thickness);
        ASSERT_FALSE(brute.empty()) << "the top card must tip through the one below";
        for (const auto& [key, time] : brute) {
            EXPECT_EQ(std::get<2>(key), 4) << "only the top card touches the others";
            EXPECT_GT(time, 12.0);
        }
        Counters counters;
        EXPECT_EQ(first_contacts(pile, Method::KineticSeparationList, thickness, &counters), brute)
            << "thickness " << thickness;
        EXPECT_GT(counters.plane_kept_steps, 100) << "planes must keep the sliding cards' pairs whole";
    }
}

TEST(PlaneKeptPile, ACardSinkingOntoAnotherSleepsOnTheirPlaneAndTouchesOnTime) {
    // Tilted, parallel, shifted within their plane so that the sinking
    // card's corners come down on the lower card's faces: every first
    // contact comes at the time the gap along the normal closes.
    const Eigen::Matrix3d r = animations::tilt();
    const int samples = 40;
    const double start = 0.71, speed = 0.02;  // contact at time code 35.5
    std::vector<MeshAnimation> cards;
    cards.push_back(animations::sheet(4, samples, [&](double x, double z, int) { return Vec3(r * Vec3(x, 0.0, z)); }));
    cards.push_back(animations::sheet(4, samples, [&](double x, double z, int k) {
        return Vec3(r * Vec3(x + 0.03, start - speed * k, z + 0.05));
    }));
    // Far off, a card swaying on a curve puts a breakpoint at every sample:
    // else the merged flightplans move the pair in one step, which no plane
    // keeps apart.
    cards.push_back(animations::sheet(2, samples, [&](double x, double z, int k) {
        return Vec3(x + 10.0, 0.2 * std::sin(0.3 * k), z);
    }));
    const double touch = start / speed;
    for (double thickness : {0.0, 0.004}) {
        const auto brute = first_contacts(cards, Method::BruteForce, thickness);
        ASSERT_FALSE(brute.empty());
        Counters counters;
        const auto kinetic = first_contacts(cards, Method::KineticSeparationList, thickness, &counters);
        EXPECT_EQ(kinetic, brute) << "thickness " << thickness;
        // The gap closes to the thickness `thickness / speed` time codes early.
        const double expected = touch - thickness / speed;
        for (const auto& [key, time] : kinetic) EXPECT_NEAR(time, expected, 1e-3) << "thickness " << thickness;
        // Looked at on every step it holds on, the card pair's plane (the
        // root pair's, then its children's near the touch) counts 50 steps.
        EXPECT_GT(counters.plane_kept_steps, 0);
        EXPECT_LT(counters.plane_kept_steps, 25) << "the kept pairs must sleep on their planes";
    }
}
