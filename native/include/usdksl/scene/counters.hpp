#pragma once
/// @file counters.hpp
/// @brief Work counters every method fills, for benchmarks and the report.

#include <cstdint>

namespace usdksl {

/// @brief Counts of work done by one check.
struct Counters {
    /// @brief KSL: tree refits (every used mesh's tree, once per step between breakpoints).
    int64_t kinetic_tree_events = 0;
    /// @brief KSL: front entries whose boxes started to meet (expanded, or leaves turned overlapping).
    int64_t bv_overlap_events = 0;
    /// @brief KSL: fathers that stayed apart for a step and replaced their children in the front.
    int64_t fathers_do_not_overlap_events = 0;
    /// @brief KSL: overlapping leaf pairs that stayed apart for a step and left the narrow phase.
    int64_t leaves_do_not_overlap_events = 0;
    /// @brief KSL: steps on which a front entry whose boxes meet stayed whole
    ///        because a plane, looked for on that step, kept every vertex
    ///        under one node apart from every vertex under the other, beyond
    ///        the narrow phase's reach (the steps such an entry then sleeps
    ///        through, its gap provably open, are not counted).
    int64_t plane_kept_steps = 0;
    /// @brief KSL: narrow-phase runs over one leaf pair's flightplan steps.
    int64_t polygons_collide_events = 0;
    /// @brief KSL: steps between consecutive breakpoints the front was brought up to date on.
    int64_t bv_change_events = 0;
    /// @brief Box-box overlap tests (swept, discrete) or moving-box meeting tests (KSL).
    int64_t bv_tests = 0;
    /// @brief Triangle-pair narrow-phase calls (continuous or static).
    int64_t narrow_phase_tests = 0;
    /// @brief Flightplan steps of leaf pairs that a clearance certificate
    ///        skipped without a narrow-phase call (KSL).
    int64_t cleared_steps = 0;
    /// @brief Primitive (vertex-face, edge-edge) CCD queries.
    int64_t primitive_queries = 0;
    /// @brief Vertex-face queries of those answered by a memo of the same inputs
    ///        (no root search). Depends on how the check was split into
    ///        time windows, never changes an answer.
    int64_t reused_queries = 0;
    /// @brief Primitive queries that hit the iteration cap.
    int64_t undecided_queries = 0;
    /// @brief Candidate contacts of merged flightplans re-tested on the raw samples.
    int64_t raw_confirmations = 0;
    /// @brief Re-tested candidates that never touch on the raw samples (dropped).
    int64_t raw_rejections = 0;
    /// @brief Time windows the range was checked in: 1 on one thread; with
    ///        several, the planned ones plus one per window cut short for a
    ///        thread that came free (varies from run to run, the answer never).
    int64_t time_windows = 0;
};

} // namespace usdksl
