#pragma once
/// @file crossing.hpp
/// @brief When does the gap between two flightplans along one axis change sign?
///        The segment walk of the paper's Algorithm 2.

#include "usdksl/flightplan/flightplans.hpp"

#include <cstdint>

namespace usdksl {

/// @brief The gap f(t) = A_a(t)[axis] - B_b(t)[axis] + offset (scene units)
///        between vertex a of flightplans A and vertex b of flightplans B.
struct AxisGap {
    const Flightplans* a_plans;
    int32_t a_vertex;
    const Flightplans* b_plans;
    int32_t b_vertex;
    int axis;
    double offset;

    /// @brief f at time code t.
    double at(double t) const {
        return a_plans->coord(a_vertex, axis, t) - b_plans->coord(b_vertex, axis, t) + offset;
    }
};

/// @brief Which sign change to look for.
enum class GapChange {
    /// @brief First time f(t) < 0.
    DropsBelowZero,
    /// @brief First time f(t) >= 0.
    RisesToZero,
};

/// @brief Answer of a crossing search.
struct CrossingTime {
    /// @brief Time code of the change (never later than the true one), or the
    ///        end of the searched horizon when `is_horizon`, or +inf when the
    ///        change does not happen before the limit.
    double time;
    /// @brief True when the search stopped at its piece budget: nothing is known
    ///        past `time`, so the caller re-checks then.
    bool is_horizon;
};

/// @brief Walks the linear pieces of f (bounded by both vertices' breakpoints)
///        from time code t_from up to t_limit, looking at no more than
///        max_pieces pieces. Returns t_from itself when f already satisfies
///        the change there. Roots are rounded toward earlier times.
CrossingTime first_gap_change(const AxisGap& gap, GapChange change, double t_from, double t_limit,
                              int max_pieces);

} // namespace usdksl
