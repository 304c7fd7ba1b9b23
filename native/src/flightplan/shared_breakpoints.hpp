#pragma once
/// @file shared_breakpoints.hpp
/// @brief Where a vertex breaks when its samples stop merging: at a sample
///        that other vertices keep too. The kinetic core steps along the
///        union of every vertex's breakpoints, so breakpoints that line up
///        across vertices make the step count follow the motion, not the
///        sampling: on a cache resampled densely with linear in-betweens, a
///        slowly moving vertex that merges across several frames would
///        otherwise break at whichever in-between its merge failed, each
///        vertex at another one, and the union would hold nearly every sample.

#include "usdksl/mesh_animation.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief Share (dimensionless) of the largest popularity in a stretch of
///        samples that a sample of that stretch needs to be a preferred
///        break: the latest such sample wins, so a vertex keeps long merges
///        while breaking where most vertices break.
constexpr double PREFERRED_BREAK_SHARE = 0.5;

/// @brief The sample in (anchor, k] at which a vertex whose samples
///        anchor..k+1 do not merge prefers to break: the latest whose
///        popularity (how many vertices keep it, indexed by sample) is at
///        least PREFERRED_BREAK_SHARE times the largest in that stretch.
///        k when `popularity` is null.
int64_t preferred_break(const int64_t* popularity, int64_t anchor, int64_t k);

/// @brief Where a vertex's run of merged samples ends.
struct RunEnd {
    int64_t sample = 0;      ///< the sample kept as the run's breakpoint
    double deviation = 0.0;  ///< largest distance (infinity norm, scene units) of a dropped sample from the run's chord
};

/// @brief The end of vertex v's run from sample `anchor` when merging
///        anchor..k+1 failed: preferred_break(popularity, anchor, k) when the
///        samples it drops lie within the merge tolerance of its own chord
///        (FLIGHTPLAN_COLLINEAR_TOLERANCE times the largest absolute
///        coordinate of the run's samples), else k (the run anchor..k
///        merged). The deviation is measured for the run kept.
RunEnd aligned_run_end(const MeshAnimation& mesh, int32_t v, int64_t anchor, int64_t k, const int64_t* popularity);

/// @brief Index in `kept` (a vertex's breakpoints, sample indices as the
///        plain greedy merge keeps them) of the first break that is not the
///        one preferred_break() picks in its stretch; kept.size() when every
///        break is (the first sample and the last of `sample_count` are kept
///        anyway). Aligning replays the greedy merge up to the break before
///        it, and with every break preferred keeps the same breakpoints with
///        the same deviation.
size_t first_unpreferred_break(const std::vector<int64_t>& kept, int64_t sample_count, const int64_t* popularity);

} // namespace usdksl
