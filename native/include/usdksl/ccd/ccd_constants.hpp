#pragma once
/// @file ccd_constants.hpp
/// @brief Floating-point error bounds of the narrow phase, named in one place.

#include "usdksl/geometry/rounding.hpp"

namespace usdksl {

/// @brief Bound, in multiples of (unit roundoff x largest absolute input
///        coordinate on the same axis), on the rounding error of one corner
///        value of the vertex-face or edge-edge distance function
///        F(t,u,v) = W(t) - u E1(t) - v E2(t) as the root finder evaluates it
///        (positions interpolated in time, then differenced; no FMA).
///        The first-order analysis gives 50; 64 covers the second-order terms.
constexpr double CCD_CORNER_ERROR_FACTOR = 64.0 * DOUBLE_UNIT_ROUNDOFF;

/// @brief Smallest error bound (scene units) the root finder ever uses, so
///        that all-zero inputs and subnormal round-off stay conservative.
constexpr double CCD_MIN_ABSOLUTE_ERROR = 1e-300;

/// @brief A parameter box the float corner test cannot exclude is decided in
///        exact arithmetic when, on some axis, its float corner values all
///        lie within this many
///        corner error bounds (CCD_CORNER_ERROR_FACTOR x magnitude) of the
///        far side of the thickness: only there can exact values exclude it
///        where the float bound could not (dimensionless; 2 covers the
///        rounding of the comparison itself).
constexpr double EXACT_CHECK_ERROR_MULTIPLE = 2.0;

/// @brief Before a corner is decided in exact arithmetic, its float value c
///        decides it when far enough from the thickness T, in multiples of
///        the corner error bound E (|c - exact| <= E, and E >= the exact
///        check's guard CCD_MIN_ABSOLUTE_ERROR): c - T < -1.5 E (rounded)
///        means c - T < -E, so the exact value lies below T; c - T > 2.5 E
///        means c - T > 2 E, so the exact value lies beyond T + E >= T + guard.
///        Either way the exact sign is the one the float value shows, so only
///        corners within that band pay for exact arithmetic (dimensionless).
constexpr double FLOAT_DECIDES_SIGN_BELOW = 1.5;
constexpr double FLOAT_DECIDES_SIGN_ABOVE = 2.5;

/// @brief The float filter in front of the exact corner sign: its running
///        error bound, a sum of a few dozen rounded non-negative terms, is
///        inflated by this factor (far more than its own rounding, about 30
///        unit roundoffs), and the value must clear the bound by
///        FILTERED_SIGN_MIN_MARGIN (scene units), far above
///        CCD_MIN_ABSOLUTE_ERROR and any underflow, before its sign is taken
///        (dimensionless).
constexpr double FILTERED_SIGN_BOUND_INFLATION = 1.0 + 1e-12;
constexpr double FILTERED_SIGN_MIN_MARGIN = 1e-200;

/// @brief Largest input coordinate or thickness (scene units) for which the
///        exact check runs: products of three such numbers stay far from
///        overflow in the error-free transforms. Larger inputs keep the
///        conservative float answer.
constexpr double EXACT_CHECK_MAX_MAGNITUDE = 1e100;

/// @brief Relative inflation applied to (thickness + error bound) so the
///        rounding of that sum itself cannot reject a true contact.
constexpr double CCD_BOUND_INFLATION = 1.0 + 8.0 * DOUBLE_UNIT_ROUNDOFF;

/// @brief Factors applied to a clipped box's cut points (fractions of the
///        box along one parameter) before they become parameter values: the
///        lower cut moves down and the upper cut up by 16 unit roundoffs,
///        more than the rounding of the quotient that computed them, so a
///        clip never cuts off a root.
constexpr double CLIP_FRACTION_SHRINK = 1.0 - 16.0 * DOUBLE_UNIT_ROUNDOFF;
constexpr double CLIP_FRACTION_GROW = 1.0 + 16.0 * DOUBLE_UNIT_ROUNDOFF;

/// @brief When clipping keeps less than this fraction of a box's volume in
///        (t,u,v), the clipped box is evaluated again instead of split
///        (dimensionless; a speed heuristic, not an accuracy setting).
constexpr double CLIP_AGAIN_BELOW_KEPT_VOLUME = 0.5;

/// @brief Vertex-face parameter origin (speed heuristics, dimensionless, no
///        effect on answers): the corner opposite the face's longest edge
///        is the origin unless the vertex's barycentric weight on it is below
///        FACE_ORIGIN_NEAR_EDGE_WEIGHT (the vertex runs near that edge, which
///        would cut boxes diagonally); then the origin is the corner of
///        largest weight among those whose opposite edge is at least
///        FACE_ORIGIN_WIDE_EDGE_RATIO of the longest (angle not narrow).
constexpr double FACE_ORIGIN_NEAR_EDGE_WEIGHT = 0.05;
constexpr double FACE_ORIGIN_WIDE_EDGE_RATIO = 0.7;

/// @brief How many times finer than (tolerance x the query's largest reach)
///        the root finder resolves the face or edge parameters spatially
///        (dimensionless). A parameter is refined to the parametric tolerance
///        unless its edge is more than this many times shorter than the
///        query's reach, as on a blown-up sliver; 10 keeps every answer on the
///        public query sets as with purely parametric tolerances.
constexpr double SPATIAL_TOLERANCE_MARGIN = 10.0;

/// @brief Smallest sine of the angle between the distance function's rate in
///        time and the plane of its (u, v) rates at a box's centre for which
///        the root search clips that box along the rows of F's inverse
///        Jacobian (dimensionless): below it the Jacobian is too near
///        singular (coplanar motion, parallel edges, a pair holding still)
///        for them to separate better than the other directions (a speed
///        setting, no effect on conservativeness).
constexpr double BOX_DIRECTIONS_MIN_SINE = 1e-3;

/// @brief Where the root search splits a box along time, as a fraction of
///        its time range from the early end (dimensionless; a speed setting,
///        no effect on conservativeness: the earliest box is always searched
///        first). The root set often lasts from its first time on (a pair
///        staying within the thickness, a vertex sliding in a face's plane),
///        so clipping pins the box's early end there but cannot move its late
///        end: halving then takes log2(range / tolerance) boxes before the
///        earliest part is narrow enough to answer, splitting near the early
///        end about a third of that. 1/64 took the fewest boxes on the hits
///        of the Newton caches and the generated tablecloth (1/2 to 1/256 tried).
constexpr double TIME_SPLIT_FRACTION = 1.0 / 64.0;

/// @brief Smallest squared sine of the angle between a box's two (u, v) rates
///        for which its closest-point direction takes the free minimum of
///        |F|^2 over (u, v); below it (parallel edges, a sliver) the range's
///        sides alone are searched (dimensionless; a direction is only a
///        choice of slab, so this never affects conservativeness).
constexpr double NEAREST_POINT_MIN_SINE_SQUARED = 1e-12;

/// @brief Smallest tolerance (interval fraction) the root finder accepts;
///        finer requests are raised to it so refinement always terminates.
constexpr double CCD_MIN_TOLERANCE = 1.0 / 4503599627370496.0; // 2^-52

} // namespace usdksl
