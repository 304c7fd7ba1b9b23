#pragma once
/// @file constants.hpp
/// @brief Every tolerance and default the core uses, named in one place.

#include <cstdint>

namespace usdksl {

/// @brief Default CCD tolerance: width of the time interval (fraction of one
///        step, in [0,1]) at which the root search stops refining.
constexpr double DEFAULT_CCD_TOLERANCE = 1e-6;

/// @brief Default cap on sub-box refinements of one CCD query; a query that
///        reaches it is "undecided" and counted as a contact.
constexpr int64_t DEFAULT_CCD_MAX_ITERATIONS = 1'000'000;

/// @brief Default minimum separation d (scene units): contact is distance <= d.
constexpr double DEFAULT_THICKNESS = 0.0;

/// @brief Relative tolerance (to the segment's own displacement) below which
///        a vertex's consecutive flightplan segments count as collinear and
///        merge into one.
constexpr double FLIGHTPLAN_COLLINEAR_TOLERANCE = 1e-12;

} // namespace usdksl
