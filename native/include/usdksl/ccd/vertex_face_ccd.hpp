#pragma once
/// @file vertex_face_ccd.hpp
/// @brief Conservative continuous vertex-face test over one linear step.

#include "usdksl/ccd/ccd_settings.hpp"
#include "usdksl/ccd/finer_search_fork.hpp"
#include "usdksl/types.hpp"

namespace usdksl {

/// @brief Earliest time (fraction of the step) at which vertex p comes within
///        settings.thickness of triangle (a,b,c), all moving linearly from
///        their *_t0 to their *_t1 positions. Never reports "no contact" when
///        there is one; contact already at the start gives toi = 0.
CCDResult vertex_face_ccd(
    const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
    const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
    const CCDSettings& settings);

/// @brief Same query restricted to contacts strictly earlier than t_max
///        (fraction of the step, in (0,1]): the narrow phase passes the best
///        time found so far so that later roots are never searched for.
CCDResult vertex_face_ccd(
    const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
    const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
    const CCDSettings& settings, double t_max);

/// @brief The same query, also recording in `fork` (its finer_tolerance
///        set by the caller) where it parts from the search at that finer
///        tolerance; the answer is the same as without.
CCDResult vertex_face_ccd(
    const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
    const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
    const CCDSettings& settings, double t_max, FinerSearchFork& fork);

/// @brief vertex_face_ccd(..., finer_settings, t_max) for a fork the same
///        query recorded (diverged) at a coarser tolerance: the same answer,
///        bit for bit, going on from where the searches parted.
CCDResult vertex_face_ccd_resumed(
    const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
    const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
    const CCDSettings& finer_settings, double t_max, const FinerSearchFork& fork);


} // namespace usdksl
