#pragma once
/// @file aabb_tree.hpp
/// @brief A conventional AABB tree refit bottom-up, and the BVTT traversal
///        that the swept-volume and discrete baselines share.

#include "usdksl/broad_phase/bvh_topology.hpp"
#include "usdksl/scene/scene.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace usdksl {

/// @brief Axis-aligned boxes on a fixed topology, refit bottom-up per query time.
class AabbTree {
public:
    /// @brief Builds the topology on the triangle centroids at time code t_build.
    AabbTree(const Scene& scene, int32_t mesh, double t_build);

    /// @brief Refits every box to enclose each triangle at time codes t0 and t1
    ///        (the swept volume of a linear step when t0 < t1; a static box when
    ///        t0 == t1), grown by `padding` scene units on every side plus
    ///        BOX_PADDING times the magnitude of the triangle's own coordinates.
    void refit(double t0, double t1, double padding);

    const BvhTopology& topology() const { return topology_; }
    const Vec3& lower(int32_t node) const { return lower_[node]; }
    const Vec3& upper(int32_t node) const { return upper_[node]; }

private:
    const Scene& scene_;
    int32_t mesh_;
    BvhTopology topology_;
    std::vector<Vec3> lower_, upper_;
};

/// @brief Calls visit(tri_a, tri_b) for every pair of leaves whose boxes
///        overlap, traversing the BVTT of a and b (or of a with itself when
///        `self`, over unordered pairs, never a leaf with itself). Adds one to
///        *bv_tests per box test.
void for_each_overlapping_leaf_pair(const AabbTree& a, const AabbTree& b, bool self, int64_t* bv_tests,
                                    const std::function<void(int32_t, int32_t)>& visit);

} // namespace usdksl
