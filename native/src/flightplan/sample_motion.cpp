#include "usdksl/flightplan/sample_motion.hpp"

#include "usdksl/run_on_threads.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace usdksl {
namespace {

/// Threads for a pass over `samples` samples of `vertices` vertices: no more
/// than the caller allows, each with SAMPLE_MOTION_VALUES_PER_THREAD values at least.
int32_t threads_for(int64_t samples, int64_t vertices, int32_t threads) {
    const int64_t values = samples * vertices * 3;
    return static_cast<int32_t>(std::clamp<int64_t>(values / SAMPLE_MOTION_VALUES_PER_THREAD, 1, std::max(threads, 1)));
}

template <typename Real>
std::vector<double> longest_steps_of(const Real* points, int64_t samples, int64_t vertices, int32_t threads) {
    std::vector<double> longest(static_cast<size_t>(std::max<int64_t>(samples - 1, 0)), 0.0);
    const size_t row = static_cast<size_t>(vertices) * 3;
    parallel_for(threads_for(samples, vertices, threads), static_cast<int32_t>(samples - 1), [&](int32_t k) {
        const Real* p = points + static_cast<size_t>(k) * row;
        const Real* q = p + row;
        double largest = 0.0;
        for (size_t i = 0; i < row; i += 3) {
            const double dx = static_cast<double>(q[i]) - static_cast<double>(p[i]);
            const double dy = static_cast<double>(q[i + 1]) - static_cast<double>(p[i + 1]);
            const double dz = static_cast<double>(q[i + 2]) - static_cast<double>(p[i + 2]);
            const double squared = dx * dx + dy * dy + dz * dz;
            // a NaN (no finite input gives one) stays: the scan then looks at the interval
            largest = squared > largest || std::isnan(squared) ? squared : largest;
        }
        longest[static_cast<size_t>(k)] = std::sqrt(largest);
    });
    return longest;
}

template <typename Real>
void sample_boxes_of(const Real* points, int64_t samples, int64_t vertices, double* lowest, double* highest,
                     int32_t threads) {
    const size_t row = static_cast<size_t>(vertices) * 3;
    parallel_for(threads_for(samples, vertices, threads), static_cast<int32_t>(samples), [&](int32_t k) {
        const Real* p = points + static_cast<size_t>(k) * row;
        double lo[3], hi[3];
        for (int axis = 0; axis < 3; ++axis) {
            lo[axis] = std::numeric_limits<double>::infinity();
            hi[axis] = -std::numeric_limits<double>::infinity();
        }
        for (size_t i = 0; i < row; i += 3) {
            for (int axis = 0; axis < 3; ++axis) {
                const double value = static_cast<double>(p[i + static_cast<size_t>(axis)]);
                lo[axis] = std::min(lo[axis], value);
                hi[axis] = std::max(hi[axis], value);
            }
        }
        for (int axis = 0; axis < 3; ++axis) {
            lowest[3 * k + axis] = lo[axis];
            highest[3 * k + axis] = hi[axis];
        }
    });
}

} // namespace

std::vector<double> longest_steps(const float* points, int64_t samples, int64_t vertices, int32_t threads) {
    return longest_steps_of(points, samples, vertices, threads);
}

std::vector<double> longest_steps(const double* points, int64_t samples, int64_t vertices, int32_t threads) {
    return longest_steps_of(points, samples, vertices, threads);
}

void sample_boxes(const float* points, int64_t samples, int64_t vertices, double* lowest, double* highest,
                  int32_t threads) {
    sample_boxes_of(points, samples, vertices, lowest, highest, threads);
}

void sample_boxes(const double* points, int64_t samples, int64_t vertices, double* lowest, double* highest,
                  int32_t threads) {
    sample_boxes_of(points, samples, vertices, lowest, highest, threads);
}

} // namespace usdksl
