#pragma once
/// @file check_options.hpp
/// @brief How one check runs: the method, the time range, the CCD settings,
///        threads and progress (read by every method below collision/).

#include "usdksl/ccd/ccd_settings.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace usdksl {

/// @brief Which algorithm finds the contacts (all share the narrow phase).
enum class Method {
    /// @brief Kinetic separation lists on kinetic AABB trees (event based).
    KineticSeparationList,
    /// @brief Swept-volume AABB tree refit bottom-up per interval (baseline).
    SweptVolume,
    /// @brief Static triangle tests at each sample and substep (misses tunnelling).
    Discrete,
    /// @brief Every triangle pair on every step (reference; quadratic).
    BruteForce,
};

/// @brief Called now and then with (time code reached, contacts so far).
using ProgressCallback = std::function<void(double, int64_t)>;

/// @brief How one check runs.
struct CheckOptions {
    Method method = Method::KineticSeparationList;
    /// @brief Checked time range in time codes; a run over [a,b] merged with a
    ///        run over [b,c] (minimum time per triangle pair) equals a run over [a,c].
    double t_begin = 0.0;
    double t_end = 0.0;
    CCDSettings ccd;
    /// @brief Discrete method only: static tests per step (1 = at samples only).
    int32_t discrete_substeps = 1;
    /// @brief Frames per time code (the stage's clock; <= 0: unknown). Merged
    ///        flightplans step over the samples between whole frames (a
    ///        simulator's sub-frame samples), their distance from the frames'
    ///        chords counted as slack; the raw samples confirm every contact,
    ///        so the answer is the same as without.
    double frames_per_time_code = 0.0;
    /// @brief Threads to use (<= 0: every hardware thread). The range is split
    ///        into time windows checked in parallel; the contacts are the same
    ///        bit for bit whatever the count.
    int32_t threads = 1;
    /// @brief Triangle pairs (mesh_a, tri_a, mesh_b, tri_b, in either order)
    ///        whose first contact is known to come at or before t_begin: a run
    ///        over an earlier range found them. They are not tested again: a
    ///        run over [b, c] given the pairs a run over [a, b] found, merged
    ///        with that run, still equals the run over [a, c], without finding
    ///        again every contact that goes on across b (cloth resting on a
    ///        collider). Brute force, the reference, tests them all the same.
    std::vector<std::array<int32_t, 4>> settled_pairs;
    /// @brief Called with (time code reached, contacts so far); with several
    ///        threads, calls are serialized and the time is the start of the
    ///        range plus the total time covered by all windows.
    ProgressCallback progress;
};

} // namespace usdksl
