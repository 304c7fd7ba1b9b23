#pragma once
/// @file baselines.hpp
/// @brief The methods KSL is measured against: swept-volume BVH, discrete
///        per-sample checks, and the brute-force reference.

#include "usdksl/scene/check_options.hpp"
#include "usdksl/scene/scene.hpp"
#include "usdksl/scene/triangle_pair_tester.hpp"
#include "usdksl/scene/window_stop.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace usdksl {

/// @brief Swept-volume baseline (paper section 7): per interval of the merged
///        sample times, refit each tree bottom-up with boxes over the start
///        and end positions, traverse the BVTT, and run the narrow phase on
///        every overlapping leaf pair over that interval. Given a `stop`, ends
///        early as WindowStop describes.
void run_swept_volume(const Scene& scene, const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                      const CheckOptions& options, TrianglePairTester& tester, Counters& counters,
                      WindowStop* stop = nullptr);

/// @brief Discrete baseline: static triangle tests at every merged sample and
///        `discrete_substeps - 1` evenly spaced instants between samples.
///        Misses contacts that begin and end between two instants. Given a
///        `stop`, tests no instant at or after its stop_at (but the first).
void run_discrete(const Scene& scene, const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                  const CheckOptions& options, TrianglePairTester& tester, Counters& counters,
                  WindowStop* stop = nullptr);

/// @brief Reference: every triangle pair on every flightplan step, no culling.
///        It goes pair by pair, not step by step, so it cannot end early:
///        given a `stop`, it only publishes that it reached t_end.
void run_brute_force(const Scene& scene, const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                     const CheckOptions& options, TrianglePairTester& tester, WindowStop* stop = nullptr);

} // namespace usdksl
