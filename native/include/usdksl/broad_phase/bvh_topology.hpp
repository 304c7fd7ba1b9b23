#pragma once
/// @file bvh_topology.hpp
/// @brief The shape of a binary bounding volume hierarchy over triangles,
///        without any boxes: kinetic and swept trees both hang their bounds on it.

#include "usdksl/types.hpp"

#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief A binary tree with one triangle per leaf. Node 0 is the root.
struct BvhTopology {
    std::vector<int32_t> left;      ///< @brief Left child, -1 for a leaf.
    std::vector<int32_t> right;     ///< @brief Right child, -1 for a leaf.
    std::vector<int32_t> parent;    ///< @brief Parent, -1 for the root.
    std::vector<int32_t> depth;     ///< @brief Root has depth 0.
    std::vector<int32_t> triangle;  ///< @brief Triangle of a leaf, -1 for an inner node.
    int32_t max_depth = 0;

    int32_t node_count() const { return static_cast<int32_t>(left.size()); }
    bool is_leaf(int32_t node) const { return triangle[node] >= 0; }
};

/// @brief Top-down median split on the longest axis of the centroids' bounds.
///        Deterministic: ties are broken by triangle index. Empty input gives
///        an empty topology.
BvhTopology build_bvh_topology(const std::vector<Vec3>& centroids);

} // namespace usdksl
