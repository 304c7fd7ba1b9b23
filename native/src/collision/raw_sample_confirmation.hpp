#pragma once
/// @file raw_sample_confirmation.hpp
/// @brief Turns candidate contacts found on merged flightplans (with slack)
///        into the contract's answer: the first time the raw-sample
///        trajectories come within the user's thickness.

#include "usdksl/ccd/ccd_settings.hpp"
#include "usdksl/collision/check.hpp"
#include "usdksl/scene/contact.hpp"
#include "usdksl/scene/counters.hpp"
#include "usdksl/scene/scene.hpp"

#include <vector>

namespace usdksl {

/// @brief Tolerance of the confirming search relative to the candidate
///        search's (dimensionless). The root finder stops refining (t, u, v)
///        boxes at the tolerance, so a pair that stays closer than about
///        tolerance x its size without touching can be a candidate; the
///        confirming search resolves such near misses a thousand times finer,
///        so a reported time is the first touch, not the first near approach.
constexpr double CONFIRMATION_TOLERANCE_FACTOR = 1e-3;

/// @brief The confirming search's settings: `settings` with the tolerance
///        CONFIRMATION_TOLERANCE_FACTOR times finer, never below the root
///        finder's floor CCD_MIN_TOLERANCE.
CCDSettings confirming(const CCDSettings& settings);

/// @brief Re-tests every candidate on the raw samples, with `settings.thickness`
///        alone and the tolerance CONFIRMATION_TOLERANCE_FACTOR x
///        `settings.tolerance`, from the raw sample interval that holds the
///        candidate's time to `t_end` (time codes). A candidate's time never
///        comes after its raw first contact (slack and a coarser tolerance only
///        make contact earlier), so the first raw contact found from there is
///        the pair's first contact; a candidate that never touches on the raw
///        samples is dropped. Every reported time comes from one raw sample
///        interval, whatever the method or time window found the candidate, so
///        answers are bit-identical across them. A candidate that carries
///        its step's confirming test (CarriedConfirmation) takes it from
///        there instead of testing that step again: the same answer.
/// @return The confirmed contacts sorted by contact_before.
std::vector<Contact> confirm_on_raw_samples(const Scene& candidate_scene, const std::vector<Contact>& candidates,
                                            const CCDSettings& settings, double t_begin, double t_end,
                                            Counters& counters, const ProgressCallback& progress = {});

/// @brief Marks (as RawSamples in `kinds`, sized to the scene's meshes) every
///        mesh that a candidate involves.
void mark_meshes_to_confirm(const Scene& candidate_scene, const std::vector<Contact>& candidates,
                            std::vector<FlightplanKind>& kinds);

/// @brief confirm_on_raw_samples on a raw scene built beforehand with (at
///        least) the kinds mark_meshes_to_confirm asks for; `raw_scene` may be
///        a per-thread copy.
std::vector<Contact> confirm_on_raw_scene(const Scene& raw_scene, const std::vector<Contact>& candidates,
                                          const CCDSettings& settings, double t_begin, double t_end,
                                          Counters& counters, const ProgressCallback& progress = {});

} // namespace usdksl
