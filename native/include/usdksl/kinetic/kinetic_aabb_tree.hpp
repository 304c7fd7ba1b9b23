#pragma once
/// @file kinetic_aabb_tree.hpp
/// @brief The kinetic AABB tree (paper section 4): nodes store which vertex is
///        extreme on each side of each axis, not coordinates.

#include "usdksl/broad_phase/bvh_topology.hpp"
#include "usdksl/flightplan/flightplans.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief One side of one axis of a box: slot = 2 * axis + (1 for the maximum).
constexpr int BOX_SLOTS = 6;
inline int slot_axis(int slot) { return slot / 2; }
inline bool slot_is_max(int slot) { return (slot & 1) != 0; }

/// @brief A kinetic AABB tree over one mesh's triangles. A certificate per
///        (node, slot) proves that the stored vertex stays extreme among the
///        node's candidates (its triangle's vertices for a leaf, its children's
///        extreme vertices otherwise); it fails when a candidate overtakes the
///        stored vertex by more than KINETIC_ORDER_TOLERANCE times the larger
///        magnitude of the two vertices (scene units).
class KineticAabbTree {
public:
    /// @brief Builds the topology on the triangles' centroids at time code
    ///        t_build and picks every extreme vertex at that time.
    KineticAabbTree(const Flightplans& plans, const std::vector<Triangle>& triangles, double t_build);

    const BvhTopology& topology() const { return topology_; }
    const Flightplans& plans() const { return *plans_; }

    /// @brief Vertex that is extreme for (node, slot).
    int32_t extreme(int32_t node, int slot) const { return extreme_[node * BOX_SLOTS + slot]; }

    /// @brief Scene units by which the stored box of `node` may be too small
    ///        (certificate slack accumulated over the levels below it) plus the
    ///        rounding padding of its sides; local to the vertices under it.
    double box_margin(int32_t node) const { return box_margin_[node]; }

    /// @brief Time code (> t, never late) at which the certificate of (node,
    ///        slot) fails or must be re-checked; +inf when not before t_limit.
    double certificate_failure(int32_t node, int slot, double t, double t_limit) const;

    /// @brief Re-picks the extreme vertex of (node, slot) at time code t among
    ///        its candidates; returns true when it changed.
    bool repick(int32_t node, int slot, double t);

    /// @brief Coordinate of the box side (node, slot) at time code t.
    double side(int32_t node, int slot, double t) const {
        return plans_->coord(extreme(node, slot), slot_axis(slot), t);
    }

private:
    int candidates(int32_t node, int slot, std::array<int32_t, 3>& out) const;
    bool better(int32_t candidate, int32_t incumbent, int slot, double t) const;

    const Flightplans* plans_;
    const std::vector<Triangle>* triangles_;
    BvhTopology topology_;
    std::vector<int32_t> extreme_;
    std::vector<double> box_margin_;
};

/// @brief Pieces of flightplan a certificate or overlap search walks before
///        it gives up and asks to be re-checked: bounds the cost of one event.
constexpr int KINETIC_SEARCH_PIECES = 16;

} // namespace usdksl
