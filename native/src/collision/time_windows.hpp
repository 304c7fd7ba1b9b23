#pragma once
/// @file time_windows.hpp
/// @brief Splits a checked time range into windows that threads check
///        independently; runs over windows merge exactly (earliest contact
///        per triangle pair), so the answer does not depend on the split.

#include "usdksl/scene/scene.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace usdksl {

/// @brief A checked time range [begin, end] in time codes.
struct TimeWindow {
    double begin;
    double end;
};

/// @brief Fewest sample steps (intervals between consecutive sample times of
///        the checked meshes) a window spans. Each window sets up its own
///        separation lists and finds again every contact still touching at
///        its start, which on a short shot costs more than the window saves:
///        an 11-sample shot split over 2 threads took 1.9x the CPU of one.
constexpr int64_t MIN_SAMPLE_STEPS_PER_WINDOW = 8;

/// @brief Fewest sample steps, and flightplan steps, either part of a
///        running window keeps when a thread that came free takes its later
///        half: fewer than a planned window, since the thread would idle
///        otherwise, and the last cuts decide how long the other thread runs
///        on alone. On the Newton tablecloth sampled ten times denser, counted
///        in sample steps only, a check made seven windows where the original
///        made five, each with its own set-up.
constexpr int64_t MIN_SAMPLE_STEPS_PER_CUT = 4;

/// @brief Where a checked range may be cut into windows: its sample times,
///        and how many flightplan breakpoints fall on each.
class WindowCuts {
public:
    WindowCuts(const Scene& scene, const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs, double t_begin,
               double t_end);

    /// @brief t_begin, every sample time strictly between, t_end (time codes).
    const std::vector<double>& times() const { return times_; }
    /// @brief Sample steps in the range (intervals between consecutive times()).
    int64_t steps() const { return static_cast<int64_t>(times_.size()) - 1; }
    /// @brief Index of the first of times() at or after `t` (steps() past the end).
    int64_t index_at_or_after(double t) const;
    /// @brief The index in [lo, hi] within `reach` of `ideal` at which most
    ///        flightplan breakpoints fall (a keyframe of a resampled
    ///        animation: few merged steps straddle a cut there and get tested
    ///        by two windows), the nearest to `ideal` among equals; -1 when
    ///        that range is empty.
    int64_t best_cut(int64_t ideal, int64_t reach, int64_t lo, int64_t hi) const;
    /// @brief Indices [lo, hi] between `first` and `last` (indices of
    ///        times(), first < last) at which a cut leaves at least `steps`
    ///        flightplan steps on either side: the part before a cut at i
    ///        counts the times in (first, i] where some flightplan breaks, the
    ///        part after it those in (i, last), and `last`. A shot sampled ten
    ///        times denser along the same motion breaks where the original is
    ///        sampled, so its windows are cut as the original's are. lo > hi
    ///        when no index does.
    std::pair<int64_t, int64_t> keeping_flightplan_steps(int64_t first, int64_t last, int64_t steps) const;

private:
    /// Per time of times_[first..last]: flightplan breakpoints that fall on
    /// it. Counted where a cut is looked for only, not over the whole range
    /// (all vertices' breakpoints of a per-frame cache: 5 ms before two
    /// threads could start on the shirt cache).
    std::vector<int64_t> breakpoints_at(int64_t first, int64_t last) const;

    const Scene& scene_;  // outlives the cuts
    std::vector<int32_t> used_meshes_;
    std::vector<double> times_;
};

/// @brief How the planned windows of a check divide its range.
enum class WindowSizes {
    /// @brief Equal shares, for a method whose running windows can be cut:
    ///        one window per thread, all started at once; a thread that comes
    ///        free takes the later half of a running window's rest
    ///        (WindowSchedule). Falling sizes would only make that cut certain,
    ///        and each window pays a set-up and finds again the contacts an
    ///        earlier window finds at the same time (the shirt cache on two
    ///        threads: 0.955 against 0.977 s, four windows against three).
    Equal,
    /// @brief Falling linearly, `count` shares for the first window down to
    ///        one for the last, for windows that cannot be cut and outnumber
    ///        the threads: they are handed out in order, so the last one
    ///        handed out is the smallest and no thread is left with a long
    ///        window while the others idle.
    Falling,
};

/// @brief Up to `count` consecutive windows covering the range of `cuts`, cut
///        at its sample times, sized as `sizes` says. Each cut is
///        WindowCuts::best_cut within a quarter of the smaller neighbouring
///        window of its ideal place. The count shrinks until the smallest
///        window spans about MIN_SAMPLE_STEPS_PER_WINDOW sample steps; one
///        window when count <= 1 or the range is too short.
std::vector<TimeWindow> split_into_windows(const WindowCuts& cuts, int32_t count, WindowSizes sizes);

} // namespace usdksl
