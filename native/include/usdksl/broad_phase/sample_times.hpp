#pragma once
/// @file sample_times.hpp
/// @brief The time axis the per-interval baselines step along.

#include "usdksl/scene/scene.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace usdksl {

/// @brief Union of the sample times (time codes) of the meshes in `mesh_pairs`
///        that fall inside [t_begin, t_end], plus t_begin and t_end themselves.
std::vector<double> merged_sample_times(const Scene& scene,
                                        const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                                        double t_begin, double t_end);

} // namespace usdksl
