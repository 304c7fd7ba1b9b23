#pragma once
/// @file counters.hpp
/// @brief Work counters every method fills, for benchmarks and the report.

#include <cstdint>

namespace usdksl {

/// @brief Counts of work done by one check.
struct Counters {
    int64_t kinetic_tree_events = 0;
    int64_t bv_overlap_events = 0;
    int64_t fathers_do_not_overlap_events = 0;
    int64_t leaves_do_not_overlap_events = 0;
    int64_t polygons_collide_events = 0;
    int64_t bv_change_events = 0;
    /// @brief Box-box overlap tests (swept, discrete) or overlap-time computations (KSL).
    int64_t bv_tests = 0;
    /// @brief Triangle-pair narrow-phase calls (continuous or static).
    int64_t narrow_phase_tests = 0;
    /// @brief Flightplan steps of leaf pairs that a clearance certificate
    ///        skipped without a narrow-phase call (KSL).
    int64_t cleared_steps = 0;
    /// @brief Primitive (vertex-face, edge-edge) CCD queries.
    int64_t primitive_queries = 0;
    /// @brief Primitive queries that hit the iteration cap.
    int64_t undecided_queries = 0;
    /// @brief Candidate contacts of merged flightplans re-tested on the raw samples.
    int64_t raw_confirmations = 0;
    /// @brief Re-tested candidates that never touch on the raw samples (dropped).
    int64_t raw_rejections = 0;
};

} // namespace usdksl
