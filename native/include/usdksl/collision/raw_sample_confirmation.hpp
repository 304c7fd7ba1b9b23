#pragma once
/// @file raw_sample_confirmation.hpp
/// @brief Turns candidate contacts found on merged flightplans (with slack)
///        into the contract's answer: the first time the raw-sample
///        trajectories come within the user's thickness.

#include "usdksl/ccd/ccd_settings.hpp"
#include "usdksl/collision/check.hpp"
#include "usdksl/collision/contact.hpp"
#include "usdksl/collision/counters.hpp"
#include "usdksl/collision/scene.hpp"

#include <vector>

namespace usdksl {

/// @brief Re-tests every candidate whose meshes' flightplans dropped samples on the raw
///        samples, with `settings.thickness` alone, from the raw sample
///        interval that holds the candidate's time to `t_end` (time codes).
///        A candidate's time never comes after its raw first contact (the
///        slack only makes contact earlier), so the first raw contact found
///        from there is the pair's first contact; a candidate that never
///        touches on the raw samples is dropped. Candidates of meshes whose
///        flightplans kept every sample are already raw answers and pass unchanged.
///        `progress` (may be empty) is called every so many candidates with t_end.
/// @return The confirmed contacts sorted by contact_before.
std::vector<Contact> confirm_on_raw_samples(const Scene& candidate_scene, const std::vector<Contact>& candidates,
                                            const CCDSettings& settings, double t_begin, double t_end,
                                            Counters& counters, const ProgressCallback& progress = {});

} // namespace usdksl
