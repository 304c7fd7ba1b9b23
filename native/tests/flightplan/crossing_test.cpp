/// @file crossing_test.cpp
/// @brief The gap-crossing walk never reports a sign change late.

#include "animations.hpp"
#include "usdksl/flightplan/crossing.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace usdksl;

TEST(Crossing, FirstDropBelowZeroIsNeverLateAgainstDenseSampling) {
    const MeshAnimation mesh = animations::random_walk(40, 30, 21, 0.0);
    const Flightplans plans(mesh, false);
    int found = 0;
    for (int32_t a = 0; a < 40; a += 2) {
        for (int axis = 0; axis < 3; ++axis) {
            const AxisGap gap{&plans, a, &plans, a + 1, axis, 0.0};
            for (GapChange change : {GapChange::DropsBelowZero, GapChange::RisesToZero}) {
                const CrossingTime c = first_gap_change(gap, change, 0.0, 29.0, 1 << 20);
                // Dense reference: the first sampled instant where the change holds.
                double reference = std::numeric_limits<double>::infinity();
                for (int i = 0; i <= 29000; ++i) {
                    const double t = i * 1e-3;
                    const double f = gap.at(t);
                    if (change == GapChange::DropsBelowZero ? f < 0.0 : f >= 0.0) {
                        reference = t;
                        break;
                    }
                }
                EXPECT_FALSE(c.is_horizon);
                if (std::isfinite(reference)) {
                    ++found;
                    EXPECT_LE(c.time, reference) << "late crossing for vertices " << a << "," << a + 1;
                    EXPECT_GE(c.time, reference - 1e-3 - 1e-9);
                } else {
                    // No sampled change; a true one could only hide between samples.
                    if (std::isfinite(c.time)) EXPECT_LE(c.time, 29.0);
                }
            }
        }
    }
    EXPECT_GT(found, 20);
}

TEST(Crossing, StopsAtItsPieceBudgetAsAHorizon) {
    const MeshAnimation mesh = animations::sheet(1, 40, [](double x, double z, int k) {
        return Vec3(x + 10.0, 0.01 * std::sin(k), z);  // never crosses x = 0
    });
    const Flightplans plans(mesh, false);
    const AxisGap gap{&plans, 0, &plans, 1, 0, 100.0};
    const CrossingTime c = first_gap_change(gap, GapChange::DropsBelowZero, 0.0, 39.0, 4);
    EXPECT_TRUE(c.is_horizon);
    EXPECT_DOUBLE_EQ(c.time, 4.0);
}
