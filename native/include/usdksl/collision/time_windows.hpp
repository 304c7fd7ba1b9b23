#pragma once
/// @file time_windows.hpp
/// @brief Splits a checked time range into windows that threads check
///        independently; runs over windows merge exactly (earliest contact
///        per triangle pair), so the answer does not depend on the split.

#include "usdksl/collision/scene.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace usdksl {

/// @brief A checked time range [begin, end] in time codes.
struct TimeWindow {
    double begin;
    double end;
};

/// @brief Up to `count` consecutive windows covering [t_begin, t_end], cut at
///        sample times of the checked meshes. Near each evenly spaced cut it
///        prefers the sample time that most flightplan breakpoints share (a
///        keyframe of a resampled animation), so few merged steps straddle a
///        cut and get tested by two windows. One window when count <= 1 or
///        there is no sample inside the range.
std::vector<TimeWindow> split_into_windows(const Scene& scene,
                                           const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                                           double t_begin, double t_end, int32_t count);

} // namespace usdksl
