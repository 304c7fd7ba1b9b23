#pragma once
/// @file clearance_trials.hpp
/// @brief The random-trial check that both clearance certificates share: a
///        step the certificate clears must be one the narrow phase finds no
///        contact on.

#include "usdksl/ccd/ccd_settings.hpp"
#include "usdksl/narrow_phase/triangle_pair.hpp"

#include <gtest/gtest.h>

#include <array>
#include <random>

namespace usdksl::trials {

using Positions = std::array<Vec3, 3>;

/// @brief Positions moved by `by` (scene units).
inline Positions shifted(const Positions& p, const Vec3& by) { return {p[0] + by, p[1] + by, p[2] + by}; }

/// @brief A triangle pair at one breakpoint: ids and positions (scene units).
struct TrialPair {
    Triangle ids_a, ids_b;
    Positions a, b;
};

/// @brief The trials' random numbers, from one seeded engine.
class TrialRandom {
public:
    explicit TrialRandom(uint32_t seed) : engine_(seed) {}
    /// @brief Uniform in [-1, 1].
    double unit() { return unit_(engine_); }
    /// @brief A random offset of at most `scale` scene units along each axis.
    Vec3 point(double scale) {
        const double x = unit(), y = unit(), z = unit();
        return Vec3(x, y, z) * scale;
    }

private:
    std::mt19937 engine_;
    std::uniform_real_distribution<double> unit_{-1.0, 1.0};
};

/// @brief Thicknesses (scene units) every trial set runs at.
constexpr std::array<double, 2> kTrialThicknesses = {0.0, 0.05};
/// Enough that a reach a quarter too short is caught many times over, not by one lucky trial.
constexpr int kTrialsPerThickness = 4000;
constexpr int kStepsPerTrial = 8;

struct ClearanceTrialCounts {
    int cleared = 0;  ///< steps the certificate cleared
    int hits = 0;     ///< steps the narrow phase found a contact on
};

/// @brief Runs the trials. `start(random, settings, trial)` returns a trial's
///        pair at its start and starts the certificate there; `move(random,
///        pair)` returns the pair at the next breakpoint; `holds(pair, next)`
///        asks the certificate over the step from one to the other. A trial
///        ends at the first step not cleared.
template <class Start, class Move, class Holds>
ClearanceTrialCounts run_clearance_trials(uint32_t seed, bool same_mesh, Start&& start, Move&& move, Holds&& holds) {
    TrialRandom random(seed);
    ClearanceTrialCounts counts;
    for (double thickness : kTrialThicknesses) {
        CCDSettings settings;
        settings.thickness = thickness;
        for (int trial = 0; trial < kTrialsPerThickness; ++trial) {
            TrialPair pair = start(random, settings, trial);
            for (int step = 0; step < kStepsPerTrial; ++step) {
                const TrialPair next = move(random, pair);
                const bool certified = holds(pair, next);
                const bool hit = triangle_pair_ccd({pair.ids_a, pair.a, next.a}, {pair.ids_b, pair.b, next.b},
                                                   same_mesh, settings).hit;
                EXPECT_FALSE(certified && hit) << "thickness " << thickness << " trial " << trial << " step " << step;
                counts.cleared += certified;
                counts.hits += hit;
                if (!certified) break;
                pair = next;
            }
        }
    }
    return counts;
}

} // namespace usdksl::trials
