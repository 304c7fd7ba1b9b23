#include "usdksl/flightplan/crossing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace usdksl {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

bool satisfies(GapChange change, double f) {
    return change == GapChange::DropsBelowZero ? f < 0.0 : f >= 0.0;
}

/// Earliest breakpoint of vertex v strictly after t, given the segment k that
/// contains t (or the first one when t precedes every breakpoint).
double breakpoint_after(const Flightplans& plans, int32_t v, int64_t& k, double t) {
    while (k + 1 < plans.key_end(v) && plans.key_time(k + 1) <= t) ++k;
    if (plans.key_time(k) > t) return plans.key_time(k);
    return k + 1 < plans.key_end(v) ? plans.key_time(k + 1) : kInfinity;
}

} // namespace

CrossingTime first_gap_change(const AxisGap& gap, GapChange change, double t_from, double t_limit,
                              int max_pieces) {
    double t = t_from;
    double f_start = gap.at(t);
    if (satisfies(change, f_start)) return {t, false};
    // Walk with local segment indices: looking ahead must not move the
    // flightplans' cursors away from the current time.
    int64_t ka = gap.a_plans->segment_of(gap.a_vertex, t);
    int64_t kb = gap.b_plans->segment_of(gap.b_vertex, t);
    const auto gap_at = [&](double when) {
        while (ka + 1 < gap.a_plans->key_end(gap.a_vertex) && gap.a_plans->key_time(ka + 1) <= when) ++ka;
        while (kb + 1 < gap.b_plans->key_end(gap.b_vertex) && gap.b_plans->key_time(kb + 1) <= when) ++kb;
        return gap.a_plans->coord_in_segment(gap.a_vertex, ka, gap.axis, when) -
               gap.b_plans->coord_in_segment(gap.b_vertex, kb, gap.axis, when) + gap.offset;
    };
    for (int piece = 0; piece < max_pieces; ++piece) {
        if (t >= t_limit) return {kInfinity, false};
        const double piece_end = std::min({breakpoint_after(*gap.a_plans, gap.a_vertex, ka, t),
                                           breakpoint_after(*gap.b_plans, gap.b_vertex, kb, t), t_limit});
        if (piece_end == kInfinity) return {kInfinity, false};  // both hold still from here on
        const double f_end = gap_at(piece_end);
        if (satisfies(change, f_end)) {
            // f is linear on [t, piece_end]: interpolate the root, then step one
            // ulp earlier so that rounding never makes the event late.
            const double fraction = f_start / (f_start - f_end);
            double root = t + (piece_end - t) * std::clamp(fraction, 0.0, 1.0);
            root = std::max(t, std::nextafter(root, -kInfinity));
            return {root, false};
        }
        t = piece_end;
        f_start = f_end;
    }
    return {t, true};
}

} // namespace usdksl
