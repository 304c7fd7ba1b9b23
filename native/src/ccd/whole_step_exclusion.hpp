#pragma once
/// @file whole_step_exclusion.hpp
/// @brief A filter in front of the root search: most primitive pairs that
///        reach the CCD are apart over their whole step along a world axis or
///        a normal, which a handful of differences of the input points proves
///        at a fraction of a search's set-up cost.

#include "inclusion_root_finder.hpp"

namespace usdksl {

/// @brief True when the distance function of `f` stays outside the
///        thickness over the whole step (t in [0, 1], interval fraction) and
///        the whole parameter domain, along a world axis or along the face's
///        normal (vertex-face), the edges' common normal or their offset
///        (edge-edge) at either end of the step: then find_earliest_root has
///        no root to find. Rigorous: every value carries the root search's
///        rounding bound, and a NaN or infinite input proves nothing.
///
///        F is linear in t for fixed (u, v), and affine in (u, v) for fixed
///        t, so along any fixed direction its extremes over the step lie at
///        t = 0 or 1 and a corner of the domain: the face's three corners
///        (vertex-face), the four end pairs (edge-edge). These are the input
///        points' own differences, tighter than the (u, v) box the search
///        starts from, whose fourth corner lies outside a face.
bool excluded_over_whole_step(const MultilinearDistance& f, double thickness);

} // namespace usdksl
