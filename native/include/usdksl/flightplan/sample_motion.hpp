#pragma once
/// @file sample_motion.hpp
/// @brief How far a mesh's vertices move from one sample to the next, and the
///        box of each sample: what a loader's scan for blown-up vertices and
///        glitched samples looks at first, in one pass over the samples.

#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief Per sample interval k (K - 1 of them), the longest displacement of
///        any vertex from sample k to sample k + 1 (scene units): the square
///        root of the largest dx * dx + dy * dy + dz * dz, summed in that
///        order in double. `points` are sample-major, [K][N][3].
std::vector<double> longest_steps(const float* points, int64_t samples, int64_t vertices);
std::vector<double> longest_steps(const double* points, int64_t samples, int64_t vertices);

/// @brief Per sample, the least and the greatest coordinate of its vertices
///        along each axis (scene units): `lowest` and `highest` get 3 values
///        per sample (x, y, z). A sample of no vertex gets +inf and -inf.
void sample_boxes(const float* points, int64_t samples, int64_t vertices, double* lowest, double* highest);
void sample_boxes(const double* points, int64_t samples, int64_t vertices, double* lowest, double* highest);

} // namespace usdksl
