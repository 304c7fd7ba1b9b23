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

/// @brief Up to `count` consecutive windows covering [t_begin, t_end], cut at
///        sample times of the checked meshes. Window sizes fall linearly (the
///        first spans `count` shares of the range, the last one share): threads
///        take windows in order, so the last one handed out is the smallest
///        and no thread is left with a long window while the others idle.
///        Near each cut it prefers the sample time that most flightplan
///        breakpoints share (a keyframe of a resampled animation), so few
///        merged steps straddle a cut and get tested by two windows. The count
///        shrinks until the smallest window spans about
///        MIN_SAMPLE_STEPS_PER_WINDOW sample steps; one window when count <= 1
///        or the range is too short.
std::vector<TimeWindow> split_into_windows(const Scene& scene,
                                           const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                                           double t_begin, double t_end, int32_t count);

} // namespace usdksl
