#pragma once
/// @file edge_edge_ccd.hpp
/// @brief Conservative continuous edge-edge test over one linear step.

#include "usdksl/ccd/ccd_settings.hpp"
#include "usdksl/ccd/finer_search_fork.hpp"
#include "usdksl/types.hpp"

namespace usdksl {

/// @brief Earliest time (fraction of the step) at which edge (ea0,ea1) comes
///        within settings.thickness of edge (eb0,eb1), all moving linearly.
///        Never reports "no contact" when there is one.
CCDResult edge_edge_ccd(
    const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0, const Vec3& eb1_t0,
    const Vec3& ea0_t1, const Vec3& ea1_t1, const Vec3& eb0_t1, const Vec3& eb1_t1,
    const CCDSettings& settings);

/// @brief Same query restricted to contacts strictly earlier than t_max
///        (fraction of the step, in (0,1]): the narrow phase passes the best
///        time found so far so that later roots are never searched for.
CCDResult edge_edge_ccd(
    const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0, const Vec3& eb1_t0,
    const Vec3& ea0_t1, const Vec3& ea1_t1, const Vec3& eb0_t1, const Vec3& eb1_t1,
    const CCDSettings& settings, double t_max);

/// @brief The same query, also recording in `fork` (its finer_tolerance
///        set by the caller) where it parts from the search at that finer
///        tolerance; the answer is the same as without.
CCDResult edge_edge_ccd(
    const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0, const Vec3& eb1_t0,
    const Vec3& ea0_t1, const Vec3& ea1_t1, const Vec3& eb0_t1, const Vec3& eb1_t1,
    const CCDSettings& settings, double t_max, FinerSearchFork& fork);

/// @brief edge_edge_ccd(..., finer_settings, t_max) for a fork the same
///        query recorded (diverged) at a coarser tolerance: the same answer,
///        bit for bit, going on from where the searches parted.
CCDResult edge_edge_ccd_resumed(
    const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0, const Vec3& eb1_t0,
    const Vec3& ea0_t1, const Vec3& ea1_t1, const Vec3& eb0_t1, const Vec3& eb1_t1,
    const CCDSettings& finer_settings, double t_max, const FinerSearchFork& fork);


} // namespace usdksl
