#pragma once
/// @file shared_vertex_clearance.hpp
/// @brief PairClearance's drift proof for two triangles of one mesh that share
///        a vertex, kept small: a cloth holds several such pairs per
///        triangle, and each carries its certificate for the whole check.

#include "usdksl/types.hpp"

#include <array>

namespace usdksl {

/// @brief Proves that no primitive pair of two triangles of one mesh that
///        share a vertex (only pairs sharing no vertex are tested) comes within
///        reach between the certificate's start and a later time, as
///        PairClearance's drift proof does, with the shared vertex as the
///        reference (it drifts from neither triangle) and the same reach
///        (PAIR_CLEARANCE_* constants). The rounding allowance is taken from
///        a bound on every coordinate the six vertices ever reach, so the
///        whole proof comes down to one number: the drift it tolerates.
///        Ask it at every breakpoint of the six vertices since the start, in
///        time order: the drift's maximum over a linear step is at one of its
///        ends.
class SharedVertexClearance {
public:
    /// @brief Starts at the positions of both triangles at one instant. The
    ///        triangles must share a vertex. `magnitude`: scene units that no
    ///        absolute coordinate of the six vertices ever exceeds.
    void start(const Triangle& ids_a, const std::array<Vec3, 3>& a, const Triangle& ids_b,
               const std::array<Vec3, 3>& b, double contact_distance, double tolerance, double magnitude);

    /// @brief True while no tested primitive pair can have come within reach
    ///        at the positions a and b (a later breakpoint), given that it
    ///        held at every earlier one since the start.
    bool holds_at(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) const;

private:
    /// Positions at the start of A's two vertices after the shared one, then
    /// B's, relative to the shared vertex.
    std::array<Vec3, 4> offsets_;
    /// Largest drift (scene units) at which the proof holds; negative when
    /// it never does.
    double drift_limit_ = -1.0;
    int8_t shared_a_ = 0, shared_b_ = 0;  // index of the shared vertex in A and in B
};

} // namespace usdksl
