#pragma once
/// @file node_plane.hpp
/// @brief A plane that separates every vertex under one tree node from every
///        vertex under another throughout a step, beyond the narrow phase's
///        reach: every triangle pair beneath is then cleared at once, however
///        their boxes overlap (a card resting on another, tilted against the
///        axes, overlaps it in box but not in fact).

#include "usdksl/kinetic/step_box_tree.hpp"
#include "usdksl/types.hpp"

#include <cstdint>

namespace usdksl {

/// @brief Most triangles under either node for which a separating plane is
///        sought: looking costs a pass over their corners every step, which
///        beyond this many costs more than the leaf pairs it could spare.
constexpr int32_t NODE_PLANE_MAX_TRIANGLES = 128;

/// @brief The distance (scene units) a plane must keep the two nodes' vertices
///        apart over the fitted step so that the narrow phase finds no
///        contact between any triangle pair beneath: the clearance
///        certificate's reach (PairClearance) for a pair as large as both
///        nodes' boxes together, at the list's contact distance.
double node_pair_reach(const StepBoxTree& tree_a, int32_t a, const StepBoxTree& tree_b, int32_t b,
                       double contact_distance, double tolerance);

/// @brief Looks for a unit normal along which the vertices under node b lie
///        above those under node a by more than `reach` (scene units) at both
///        ends of the trees' fitted step; the gap between them is concave in
///        time, so it then holds throughout. Tries `previous` (when not zero),
///        then the mean normals of a's and of b's triangles at the step's end,
///        either way round. Both trees must have index_triangles_under().
bool find_node_plane(const StepBoxTree& tree_a, int32_t a, const StepBoxTree& tree_b, int32_t b, double reach,
                     const Vec3& previous, Vec3& normal);

} // namespace usdksl
