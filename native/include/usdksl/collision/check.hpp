#pragma once
/// @file check.hpp
/// @brief The one entry point of the core: first contacts of mesh pairs over a time range.

#include "usdksl/ccd/ccd_settings.hpp"
#include "usdksl/collision/contact.hpp"
#include "usdksl/collision/counters.hpp"
#include "usdksl/collision/mesh_animation.hpp"

#include <cstdint>
#include <functional>
#include <utility>
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
    /// @brief Threads to use (<= 0: every hardware thread). The range is split
    ///        into time windows checked in parallel; the contacts are the same
    ///        bit for bit whatever the count.
    int32_t threads = 1;
    /// @brief Called with (time code reached, contacts so far); with several
    ///        threads, calls are serialized and the time is the start of the
    ///        range plus the total time covered by all windows.
    ProgressCallback progress;
};

/// @brief Contacts (first per triangle pair, sorted by contact_before) and counters.
struct CheckResult {
    std::vector<Contact> contacts;
    Counters counters;
};

/// @brief First contact of every triangle pair of the given mesh pairs over
///        [options.t_begin, options.t_end]. A pair (i, i) is a self check.
CheckResult find_contacts(const std::vector<MeshAnimation>& meshes,
                          const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                          const CheckOptions& options);

} // namespace usdksl
