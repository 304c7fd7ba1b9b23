#pragma once
/// @file node_plane.hpp
/// @brief A plane that separates every vertex under one tree node from every
///        vertex under another throughout a step, beyond the narrow phase's
///        reach: every triangle pair beneath is then cleared at once, however
///        their boxes overlap (a card resting on another, tilted against the
///        axes, overlaps it in box but not in fact); and for how many steps
///        after, judged on the nodes' recorded motion, it is sure to.

#include "usdksl/kinetic/step_box_tree.hpp"
#include "usdksl/types.hpp"

#include <cstdint>

namespace usdksl {

/// @brief The distance (scene units) a plane must keep the two nodes' vertices
///        apart over the fitted step so that the narrow phase finds no
///        contact between any triangle pair beneath: the clearance
///        certificate's reach (PairClearance) for a pair as large as both
///        nodes' boxes together, at the list's contact distance.
double node_pair_reach(const StepBoxTree& tree_a, int32_t a, const StepBoxTree& tree_b, int32_t b,
                       double contact_distance, double tolerance);

/// @brief Allowance (relative to the largest absolute coordinate the two
///        nodes' boxes may reach) by which a plane's gap bound is lowered for
///        each step it is carried over without a look: the heights' dot
///        products, the sums of the recorded shifts, and a vertex's position
///        evaluated on either flightplan segment at a breakpoint (the shifts
///        are measured on one, the step boxes on the other) each round by a
///        few ulps of that coordinate. BOX_PADDING's size: far above those
///        ulps, far below any reach.
constexpr double NODE_PLANE_ROUNDING = 1e-10;

/// @brief Least and most height (scene units) along a direction of the
///        vertices under a node, at the fitted step's begin ([0]) and end ([1]).
struct NodeHeights {
    double low[2], high[2];
};

/// @brief The heights of the vertices under `node` along `direction`: over
///        StepBoxTree::vertices_under() when the tree lists the node's
///        vertices, else over its triangles' corners (the same values,
///        each vertex seen once per triangle it is a corner of).
NodeHeights node_heights(const StepBoxTree& tree, int32_t node, const Vec3& direction);

/// @brief Looks for a unit normal along which the vertices under node b lie
///        above those under node a by more than `reach` (scene units) at both
///        ends of the trees' fitted step; the gap between them is concave in
///        time, so it then holds throughout. Tries `previous` (when not zero),
///        then the mean normals of a's and of b's triangles at the step's end,
///        either way round. Both trees must have index_triangles_under(), and
///        both nodes at most NODE_PLANE_MAX_TRIANGLES triangles to be fast.
///        Given `end_gap`, sets it to the gap (scene units) along the found
///        normal at the step's end: the least height of b's vertices minus
///        the most of a's. Given `previous_begin_gap`, the gap along
///        `previous` at the step's begin (its end_gap on the step before,
///        whose end positions are this step's begin), only the heights at
///        the step's end are measured for `previous`: the same answer.
bool find_node_plane(const StepBoxTree& tree_a, int32_t a, const StepBoxTree& tree_b, int32_t b, double reach,
                     const Vec3& previous, Vec3& normal, double* end_gap = nullptr,
                     const double* previous_begin_gap = nullptr);

/// @brief For nodes a plane keeps apart over the trees' fitted step `step`
///        (find_node_plane: unit `normal`, `end_gap` at the step's end, scene
///        units): the first step after it on which the plane may no longer
///        keep them apart beyond node_pair_reach(..., contact_distance,
///        tolerance), so that every step before it needs no look (at most
///        `steps`, the number of steps).
///
///        During a later step the vertices under a node move by
///        displacements that lie, along each axis, within its recorded shift
///        (center c, radius r): the heights along `normal` of a's vertices
///        rise by at most n.c_a + |n|_1 r_a, b's sink by at most
///        -n.c_b + |n|_1 r_b (|n|_1: the sum of |n|'s components, as the
///        shift bounds each axis alone). Heights are linear across a step,
///        so the gap is concave and its bound at the step's two ends bounds
///        it throughout. The reach it must exceed grows with the nodes'
///        boxes: it is taken over the boxes at the fitted step's end grown
///        by the same displacement bounds. Past the steps the trees recorded
///        (NODE_TRAVEL_AHEAD_STEPS after `step`), each mesh's fastest vertex
///        bounds every displacement: `travel_a[k]` (`travel_b[k]`) bounds
///        how far any vertex of a's (b's) mesh moves along any axis during
///        steps 0..k-1 together; null stops at the recorded steps.
int64_t node_plane_quiet_until(const StepBoxTree& tree_a, int32_t a, const StepBoxTree& tree_b, int32_t b,
                               const Vec3& normal, double end_gap, double contact_distance, double tolerance,
                               int64_t step, int64_t steps, const double* travel_a, const double* travel_b);

} // namespace usdksl
