#pragma once
/// @file constants.hpp
/// @brief The ground floor's constants: the defaults of a check that the
///        bindings hand to Python (CCD tolerance, iteration cap, thickness),
///        the box padding the broad phase and the kinetic trees share, and
///        the flightplan's merge tolerance and work size.
///
/// Every other constant is named in its topic's header, beside the code it
/// tunes: the narrow phase's error bounds in `ccd/ccd_constants.hpp`,
/// rounding in `geometry/rounding.hpp`, clearance margins in
/// `narrow_phase/pair_clearance.hpp`, hysteresis and look-ahead in
/// `kinetic/separation_list.hpp` and `kinetic/step_box_tree.hpp`, page sizes
/// in `huge_page_allocator.hpp`, and so on; one that only a topic's own
/// sources use (time-window sizes, progress intervals, cache shapes) stays
/// private in `src/<topic>/`.

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

/// @brief Tolerance, relative to the largest absolute coordinate of the
///        samples that would merge, below which a vertex's consecutive
///        flightplan segments count as collinear and merge into one. USD stores points as float32, so
///        keyframes resampled linearly are collinear only to float32 precision
///        (2^-24 relative); four times that keeps merging reliable. The
///        deviation a merge introduces is added to the contact distance of
///        that mesh's pairs, so merging never hides a contact, and every
///        reported contact is confirmed on the raw samples.
constexpr double FLIGHTPLAN_COLLINEAR_TOLERANCE = 0x1p-22;

/// @brief Vertex samples (vertices x samples) per run of vertices handed to
///        one thread when flightplans are built: smaller runs would cost more
///        in hand-outs than they even out.
constexpr int64_t FLIGHTPLAN_SAMPLES_PER_RUN = 1 << 16;

/// @brief Relative padding (to the magnitude of the vertices under a box)
///        added to every box overlap test on top of the thickness, covering
///        rounding in box evaluation. Local, so one far-away vertex pads only
///        the boxes that hold it.
constexpr double BOX_PADDING = 1e-10;

} // namespace usdksl
