#pragma once
/// @file sample_motion.hpp
/// @brief How far a mesh's vertices move from one sample to the next, and the
///        box of each sample: what a loader's scan for blown-up vertices and
///        glitched samples looks at first, in one pass over the samples.

#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief Fewest coordinates a thread of longest_steps() or sample_boxes()
///        reads (a shot of 16k vertices and 20 samples): a thread costs its
///        start, and a small mesh's pass is over before it.
constexpr int64_t SAMPLE_MOTION_VALUES_PER_THREAD = int64_t{1} << 20;

/// @brief Per sample interval k (K - 1 of them), the longest displacement of
///        any vertex from sample k to sample k + 1 (scene units): the square
///        root of the largest dx * dx + dy * dy + dz * dz, summed in that
///        order in double. `points` are sample-major, [K][N][3]. Up to
///        `threads` threads (fewer for a small mesh) split the intervals;
///        the answer is the same for any count.
std::vector<double> longest_steps(const float* points, int64_t samples, int64_t vertices, int32_t threads = 1);
std::vector<double> longest_steps(const double* points, int64_t samples, int64_t vertices, int32_t threads = 1);

/// @brief Per sample, the least and the greatest coordinate of its vertices
///        along each axis (scene units): `lowest` and `highest` get 3 values
///        per sample (x, y, z). A sample of no vertex gets +inf and -inf.
///        Threads as longest_steps().
void sample_boxes(const float* points, int64_t samples, int64_t vertices, double* lowest, double* highest,
                  int32_t threads = 1);
void sample_boxes(const double* points, int64_t samples, int64_t vertices, double* lowest, double* highest,
                  int32_t threads = 1);

} // namespace usdksl
