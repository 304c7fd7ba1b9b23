#pragma once
/// @file shared_vertex_clearance.hpp
/// @brief A step-by-step certificate that two triangles of one mesh that share
///        a vertex stay out of reach, kept small: a cloth holds several such
///        pairs per triangle, and each carries its certificate for the whole
///        check.

#include "usdksl/types.hpp"

#include <array>
#include <cstdint>

namespace usdksl {

/// @brief What the reach of a vertex-sharing pair depends on besides its
///        positions (PairClearance's reach, PAIR_CLEARANCE_* constants).
struct SharedVertexReach {
    /// @brief Contact distance of the pair (scene units).
    double contact_distance = 0.0;
    /// @brief CCD time tolerance (fraction of a step).
    double tolerance = 0.0;
    /// @brief Scene units that no absolute coordinate of the six vertices ever exceeds.
    double magnitude = 0.0;
};

/// @brief Proves, one step at a time, that no primitive pair of two triangles
///        of one mesh that share a vertex (only pairs sharing no vertex are
///        tested) comes within reach during the step, by either of two proofs:
///
///        - the plane proof, for a pair sharing exactly one vertex: a plane
///          through the shared vertex with the other two vertices of A
///          beyond the reach on one side and those of B on the other, at
///          both ends of the step. Every tested primitive holds a vertex off
///          the plane by that much, with the other primitive on the other
///          side, and heights above a plane through the moving shared vertex
///          are linear over a linear step, so it holds throughout. It turns
///          with the pair: the last plane is tried first, then one fitted to
///          the step.
///        - the centroid proof, for any vertex-sharing pair (two triangles
///          hinged on a shared edge have no such plane): each tested
///          primitive pair apart beyond the reach along the direction between
///          their centroids, at both ends of the step;
///        - the drift proof of PairClearance, with the shared vertex as the
///          reference (it drifts from neither triangle) and the distance at
///          the certificate's start measured only when the other proofs
///          first fail.
///
///        A cloth turning as a whole keeps the plane and centroid proofs
///        where the drift proof runs out after a few steps.
class SharedVertexClearance {
public:
    /// @brief Starts at the positions of both triangles at one instant. The
    ///        triangles must share a vertex.
    void start(const Triangle& ids_a, const std::array<Vec3, 3>& a, const Triangle& ids_b,
               const std::array<Vec3, 3>& b);

    /// @brief True when no tested primitive pair comes within reach on the
    ///        linear step from (a0, b0) to (a1, b1): each proof is asked at
    ///        both ends of the step, and holds between them (heights along a
    ///        plane are linear over the step, the drift is convex). Steps may
    ///        be asked in any order. `ids_a`, `ids_b`: as given to start().
    bool holds_over(const Triangle& ids_a, const std::array<Vec3, 3>& a0, const std::array<Vec3, 3>& a1,
                    const Triangle& ids_b, const std::array<Vec3, 3>& b0, const std::array<Vec3, 3>& b1,
                    const SharedVertexReach& reach);

private:
    bool plane_holds(const Vec3& normal, const std::array<Vec3, 3>& a0, const std::array<Vec3, 3>& a1,
                     const std::array<Vec3, 3>& b0, const std::array<Vec3, 3>& b1, double reach) const;
    Vec3 fitted_normal(const std::array<Vec3, 3>& a0, const std::array<Vec3, 3>& a1, const std::array<Vec3, 3>& b0,
                       const std::array<Vec3, 3>& b1) const;
    static bool primitives_apart(const Triangle& ids_a, const std::array<Vec3, 3>& a0,
                                 const std::array<Vec3, 3>& a1, const Triangle& ids_b,
                                 const std::array<Vec3, 3>& b0, const std::array<Vec3, 3>& b1, double reach);
    double drift(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) const;
    void measure_drift_limit(const Triangle& ids_a, const Triangle& ids_b, const SharedVertexReach& reach);

    /// Positions at the start of A's two vertices after the shared one, then
    /// B's, relative to the shared vertex.
    std::array<Vec3, 4> offsets_;
    /// Largest drift (scene units) at which the drift proof holds; negative
    /// when it never does, NaN until measured.
    double drift_limit_ = -1.0;
    /// The last plane that held, not unit (its length is divided out); zero
    /// when there is none.
    float normal_[3] = {0.0f, 0.0f, 0.0f};
    int8_t shared_a_ = 0, shared_b_ = 0;  // index of the shared vertex in A and in B
    /// The triangles share exactly one vertex (a shared edge lies in every
    /// plane through its ends: no plane proof).
    bool plane_possible_ = false;
};

} // namespace usdksl
