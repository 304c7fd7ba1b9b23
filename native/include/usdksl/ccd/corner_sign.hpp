#pragma once
/// @file corner_sign.hpp
/// @brief Exact sign of one world-axis component of the root finder's
///        distance function F = W - u E1 - v E2 at one corner (t, u, v) of a
///        parameter box, offset by the thickness: what decides whether a box
///        lies beyond the thickness when float corners cannot tell.

namespace usdksl {

/// @brief Which of a primitive pair's four points W, E1 and E2 are
///        differences of (minuend, subtrahend).
struct PairIndices {
    int w_plus, w_minus, e1_plus, e1_minus, e2_plus, e2_minus;
};

/// @brief One world axis of a primitive pair moving linearly over a step:
///        the four points' coordinates at the step's start and end (scene
///        units), and which points W, E1 and E2 are differences of.
struct CornerAxis {
    double start[4];
    double end[4];
    PairIndices pairs;
    /// @brief Thickness (scene units, >= 0, finite).
    double thickness;
};

/// @brief filtered_corner_sign's answer when the float filter cannot tell.
constexpr int CORNER_SIGN_UNDECIDED = 2;

/// @brief Exact sign (-1, 0, 1) of F(t,u,v) + offset_sign x (thickness +
///        CCD_MIN_ABSOLUTE_ERROR), positions being the exact interpolation
///        s + t e - t s of the step's end points (t, u, v in [0, 1]). With
///        offset_sign -1, positive means the corner lies beyond +thickness;
///        with +1, negative means beyond -thickness. Coordinates and
///        thickness must lie within EXACT_CHECK_MAX_MAGNITUDE. Tries
///        filtered_corner_sign first, expansion arithmetic only when it
///        cannot tell.
int exact_corner_sign(const CornerAxis& axis, double t, double u, double v, double offset_sign);

/// @brief exact_corner_sign's answer from floating point when the value
///        provably clears zero, else CORNER_SIGN_UNDECIDED.
int filtered_corner_sign(const CornerAxis& axis, double t, double u, double v, double offset_sign);

/// @brief exact_corner_sign in expansion arithmetic alone.
int expanded_corner_sign(const CornerAxis& axis, double t, double u, double v, double offset_sign);

} // namespace usdksl
