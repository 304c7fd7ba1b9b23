#pragma once
/// @file step_box_tree.hpp
/// @brief An AABB tree whose boxes move linearly across one step between
///        consecutive breakpoints of the scene, so the separation list can ask
///        whether two boxes meet at any time of the step.

#include "usdksl/broad_phase/bvh_topology.hpp"
#include "usdksl/flightplan/flightplans.hpp"
#include "usdksl/huge_page_allocator.hpp"

#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace usdksl {

/// @brief Rounding allowance per tree level, relative to the largest absolute
///        coordinate of the vertices under a node: interpolating positions and
///        box sides inside a step rounds by a few ulps.
constexpr double STEP_BOX_ROUNDING_PER_LEVEL = 1e-12;

/// @brief Steps after the fitted one for which the tree knows where each
///        node's vertices move (StepBoxTree::shift): how long a pair of
///        boxes apart can be left alone is judged on its own nodes' motion
///        over these steps, on its meshes' fastest vertex beyond.
constexpr int64_t NODE_TRAVEL_AHEAD_STEPS = 8;

/// @brief Relative allowance by which a node's shift is widened (as the
///        per-mesh travel is, and for storing it in single precision).
constexpr double NODE_TRAVEL_ROUNDING = 1e-6;

/// @brief Most triangles under either node for which a separating plane is
///        sought (kinetic/node_plane.hpp): looking costs a pass over their
///        vertices every step, which beyond this many costs more than the
///        leaf pairs it could spare. The tree lists the distinct vertices of
///        nodes up to this size (StepBoxTree::vertices_under).
constexpr int32_t NODE_PLANE_MAX_TRIANGLES = 128;

/// @brief Largest distance between two displacements of one NodeShift (a
///        cube of half-width `radius` per axis), in multiples of its radius:
///        the cube's diagonal, 2 sqrt(3), rounded up.
constexpr double SHIFT_CUBE_DIAGONAL_PER_RADIUS = 3.5;

/// @brief Where the vertices under a node move during one recorded step
///        (scene units): along each axis every vertex's displacement lies
///        within [center - radius, center + radius]. Two nodes that move
///        together (a card falling onto a falling card, a fold carried by the
///        cloth) close their gap only by the difference of their centers plus
///        both radii, however far they travel.
struct NodeShift {
    float center[3];
    float radius;
};

/// @brief A box at both ends of a step (scene units), grown by its node's
///        rounding margin. Between the ends each
///        side moves linearly (`lo` and `hi` interpolated with the same
///        fraction of the step), which encloses the node's vertices
///        throughout: they move linearly inside a step, and the largest (or
///        smallest) of linear functions lies below (above) its chord.
struct StepBox {
    double lo[2][3];  ///< [0]: at the step's begin, [1]: at its end.
    double hi[2][3];
};

/// @brief A bounding volume hierarchy over one mesh's triangles (topology built
///        on the centroids at one time code) whose boxes are refitted to each
///        step.
class StepBoxTree {
public:
    StepBoxTree(const Flightplans& plans, const std::vector<Triangle>& triangles, double t_build);

    const BvhTopology& topology() const { return topology_; }

    /// @brief Fits every box to the step [t0, t1] (time codes), on which
    ///        every vertex of the mesh must move linearly (no breakpoint of
    ///        any vertex strictly inside). Steps must come in time order.
    void fit(double t0, double t1);

    const StepBox& box(int32_t node) const { return boxes_[node]; }

    /// @brief Positions (scene units, x y z per vertex) at the fitted step's begin
    ///        and at its end, as the flightplans give them there.
    const double* begin_points() const { return begin_points_.data(); }
    const double* end_points() const { return end_points_.data(); }

    /// @brief Scene units by which every box is grown beyond its vertices to
    ///        cover rounding; local to the magnitudes of the vertices under it.
    double box_margin(int32_t node) const { return box_margin_[node]; }

    /// @brief Largest side of the node's vertices' box at the step's begin
    ///        (scene units, before the rounding margin).
    double extent(int32_t node) const { return extent_[node]; }

    /// @brief Records step number `step` = [t0, t1] (time codes; steps come
    ///        in order, every vertex linear on each) for shift(): where the
    ///        vertices under each node move during it. A tree keeps
    ///        NODE_TRAVEL_AHEAD_STEPS steps: recording step s forgets step
    ///        s - NODE_TRAVEL_AHEAD_STEPS.
    void record_travel(int64_t step, double t0, double t1);

    /// @brief The shift of the vertices under `node` during recorded step
    ///        `step` (one of the last NODE_TRAVEL_AHEAD_STEPS recorded).
    const NodeShift& shift(int32_t node, int64_t step) const {
        static constexpr NodeShift kStill{{0.0f, 0.0f, 0.0f}, 0.0f};
        return still_ ? kStill : node_shift_[static_cast<size_t>(node) * NODE_TRAVEL_AHEAD_STEPS +
                                             static_cast<size_t>(step % NODE_TRAVEL_AHEAD_STEPS)];
    }

    /// @brief Lists the triangles under every node, and the distinct
    ///        vertices under every node of at most NODE_PLANE_MAX_TRIANGLES
    ///        triangles (once; triangles_under() and vertices_under() need
    ///        it): only trees whose nodes are asked for separating planes pay
    ///        for it. The triangles cost one int32 per triangle and two per
    ///        node. The vertices cost one int32 per vertex and inner node of
    ///        at most NODE_PLANE_MAX_TRIANGLES triangles it lies under, plus
    ///        one per node: a vertex lies under seven levels of such nodes,
    ///        on a level under more than one node where their triangles meet,
    ///        so a triangulated grid (two triangles per vertex) takes about
    ///        16.5 int32 per vertex (66 bytes), plus about 4 (16 bytes) for
    ///        the nodes. Leaves cost nothing: their triangle is their list.
    void index_triangles_under();

    /// @brief The triangles under `node`, as [first, last) pointers into
    ///        one array (after index_triangles_under()).
    std::pair<const int32_t*, const int32_t*> triangles_under(int32_t node) const {
        const int32_t* all = leaf_triangles_.data();
        return {all + leaf_first_[node], all + leaf_last_[node]};
    }

    /// @brief The distinct vertices under `node`, as [first, last) pointers
    ///        (after index_triangles_under()), in ascending order except at a
    ///        leaf (its triangle's corners); empty for a node of more than
    ///        NODE_PLANE_MAX_TRIANGLES triangles. A mesh vertex is a corner of
    ///        about six triangles: heights over these take a sixth of the
    ///        work of a walk over the corners of triangles_under().
    std::pair<const int32_t*, const int32_t*> vertices_under(int32_t node) const {
        const int32_t* all = node_vertices_.data();
        const int32_t first = vertices_first_[node], last = vertices_first_[node + 1];
        if (first == last && topology_.is_leaf(node)) {
            const int32_t* corners = (*triangles_)[static_cast<size_t>(topology_.triangle[node])].data();
            return {corners, corners + 3};
        }
        return {all + first, all + last};
    }

    /// @brief Area-weighted mean normal of the triangles under `node` at the
    ///        fitted step's end, unit; zero when they cancel out. Computed once
    ///        a fitted step (after index_triangles_under(), which makes room
    ///        for it: 32 bytes a node): a node is asked once for every node of
    ///        another mesh it nears.
    const Vec3& end_mean_normal(int32_t node) const;

    /// @brief Triangle ids of the mesh (what topology().triangle indexes).
    const std::vector<Triangle>& triangles() const { return *triangles_; }

private:
    const Flightplans* plans_;
    const std::vector<Triangle>* triangles_;
    BvhTopology topology_;
    HugeVector<StepBox> boxes_;
    std::vector<double> box_margin_;
    std::vector<double> extent_;
    /// Vertex positions (x, y, z per vertex) at the begin and end of the
    /// step; the end of one step is the begin of the next.
    HugeVector<double> begin_points_, end_points_;
    double fitted_end_;
    /// record_travel(): positions at the end of the last recorded step, each
    /// vertex's cursor and displacement (x y z) over the step being recorded,
    /// and per node (NODE_TRAVEL_AHEAD_STEPS slots each, by step modulo) its shift.
    std::vector<double> ahead_points_;
    std::vector<int64_t> ahead_segment_;
    std::vector<double> ahead_moved_;
    double ahead_end_ = -std::numeric_limits<double>::infinity();
    HugeVector<NodeShift> node_shift_;
    /// index_triangles_under(): triangles in leaf order, and per node the
    /// range of them under it.
    std::vector<int32_t> leaf_triangles_, leaf_first_, leaf_last_;
    /// index_triangles_under(): the distinct vertices of every inner node of
    /// at most NODE_PLANE_MAX_TRIANGLES triangles (and of every leaf whose
    /// triangle repeats a vertex), node after node; node n's run is
    /// [vertices_first_[n], vertices_first_[n + 1]), empty for the others.
    std::vector<int32_t> node_vertices_, vertices_first_;
    /// end_mean_normal(): per node, the normal and the fit it was computed at
    /// (fits_ counts the fits that moved the points; -1: none yet).
    mutable std::vector<Vec3> end_mean_normal_;
    mutable std::vector<int64_t> end_mean_normal_fit_;
    int64_t fits_ = 0;
    bool still_;  // no vertex ever moves: the first fit holds for every step
    bool fitted_ = false;
};

} // namespace usdksl
