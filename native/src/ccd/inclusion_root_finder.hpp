#pragma once
/// @file inclusion_root_finder.hpp
/// @brief Conservative inclusion-based root finder (in the spirit of Tight
///        Inclusion, Wang et al. 2021) for the multilinear distance function
///        F(t,u,v) = W(t) - u E1(t) - v E2(t) of a vertex-face or edge-edge
///        pair moving linearly over one step.

#include "usdksl/ccd/ccd_settings.hpp"
#include "usdksl/ccd/finer_search_fork.hpp"
#include "usdksl/types.hpp"

#include <array>

namespace usdksl {

/// @brief Which primitive pair the distance function belongs to; fixes the
///        parameter domain (u,v): the triangle u+v<=1, or the unit square.
enum class PrimitivePairKind { VertexFace, EdgeEdge };

/// @brief One primitive pair moving linearly over a step, as its four points.
///        Vertex-face: (p, a, b, c) with W = p - a, E1 = b - a, E2 = c - a.
///        Edge-edge: (ea0, ea1, eb0, eb1) with W = ea0 - eb0, E1 = ea0 - ea1,
///        E2 = eb1 - eb0. Either way F(t,u,v) = W(t) - u E1(t) - v E2(t) is
///        the vector between the two closest-candidate points.
struct MultilinearDistance {
    /// @brief The four points at the start of the step (scene units).
    std::array<Vec3, 4> at_start;
    /// @brief The four points at the end of the step (scene units).
    std::array<Vec3, 4> at_end;
    PrimitivePairKind kind;
};

/// @brief Earliest time in [0, t_max) (fraction of the step) at which the
///        distance function may come within settings.thickness (Euclidean
///        distance, scene units), found by clipping and subdividing the
///        (t,u,v) box earliest-time first until the box is narrower than
///        settings.tolerance in t, and in u and v than the same tolerance or,
///        for an edge far shorter than the query's reach, the same spatial
///        resolution (see parameter_tolerances). Conservative: boxes are only
///        discarded, and only clipped, where their corner values, inflated by
///        a rounding-error bound derived from the input magnitude, rule out
///        the thickness cube per world axis or the thickness ball along a
///        separating direction, or where their exact corner values
///        (error-free arithmetic, tried only when the float hull lies within
///        that bound of the cube) rule out the cube on some axis: a near miss
///        closer than the rounding bound is not a contact, a touch at
///        distance exactly thickness is. Above thickness 0 every box gets the
///        direction to its point nearest the origin, so a box that answers
///        lies within the thickness ball up to rounding and its own size
///        (the per-axis cube alone would accept pairs up to sqrt(3) x the
///        thickness apart); at 0 the ball and the cube are both the origin.
///        For vertex-face pairs the root search picks which face corner is
///        the (u,v) origin (the face is the same point set either way).
CCDResult find_earliest_root(const MultilinearDistance& f, const CCDSettings& settings,
                             double t_max, FinerSearchFork* fork = nullptr);

/// @brief find_earliest_root(f, finer_settings, t_max), for a fork that a
///        search of the same f, thickness, iteration cap and t_max recorded
///        with diverged set and finer_tolerance = finer_settings.tolerance:
///        the same answer, bit for bit, without redoing the shared steps.
CCDResult resume_finer_search(const MultilinearDistance& f, const CCDSettings& finer_settings, double t_max,
                              const FinerSearchFork& fork);

} // namespace usdksl
