#pragma once
/// @file ccd_settings.hpp
/// @brief The accuracy knob and the answer of one continuous collision query.

#include "usdksl/constants.hpp"

#include <cstdint>

namespace usdksl {

/// @brief Accuracy settings shared by every narrow-phase query.
struct CCDSettings {
    /// @brief Time tolerance as a fraction of the step (interval fraction).
    double tolerance = DEFAULT_CCD_TOLERANCE;
    /// @brief Refinement cap; reaching it makes the answer "undecided".
    int64_t max_iterations = DEFAULT_CCD_MAX_ITERATIONS;
    /// @brief Minimum separation d >= 0 in scene units.
    double thickness = DEFAULT_THICKNESS;
};

/// @brief Answer of one primitive-pair query over one linear step.
struct CCDResult {
    /// @brief True when the pair may come within `thickness` during the step
    ///        (always true for an undecided query: conservative).
    bool hit = false;
    /// @brief Earliest possible time of impact, fraction of the step in [0,1];
    ///        a lower bound, never later than the true first contact.
    double toi = 1.0;
    /// @brief Width of the time interval the answer was narrowed to
    ///        (interval fraction); <= tolerance unless undecided.
    double reached_tolerance = 0.0;
    /// @brief True when the iteration cap stopped the search.
    bool undecided = false;
    /// @brief Parameter boxes the root search examined (the quantity
    ///        max_iterations caps); a machine-independent measure of cost.
    int64_t iterations = 0;
};

} // namespace usdksl
