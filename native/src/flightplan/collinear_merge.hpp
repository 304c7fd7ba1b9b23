#pragma once
/// @file collinear_merge.hpp
/// @brief The breakpoints of one vertex: its samples, less those it passes
///        through on a straight line at constant speed.

#include "usdksl/mesh_animation.hpp"

#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief Fills `kept` with vertex v's breakpoints (sample indices,
///        ascending): walking forward from the last kept sample, a sample is
///        dropped while every sample since the last kept one lies on the
///        chord from the last kept sample to the next sample, within
///        FLIGHTPLAN_COLLINEAR_TOLERANCE times the largest absolute coordinate
///        of those samples (local to the vertex and to that stretch of time:
///        one vertex far away, a simulation blow-up, loosens nothing
///        elsewhere). Where a merge fails the run ends at the sample
///        aligned_run_end() picks with `popularity` (how many vertices keep
///        each sample; null: where it failed). A vertex that never moves
///        keeps its first sample alone.
/// @return The largest distance (infinity norm, scene units) of a dropped
///         sample from v's merged flightplan, computed for the runs kept.
double merge_collinear_samples(const MeshAnimation& mesh, int32_t v, const int64_t* popularity,
                               std::vector<int64_t>& kept);

} // namespace usdksl
