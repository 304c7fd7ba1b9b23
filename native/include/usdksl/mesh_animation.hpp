#pragma once
/// @file mesh_animation.hpp
/// @brief One mesh as the core sees it: fixed triangles, sampled world-space points.

#include "usdksl/types.hpp"

#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief A triangle mesh whose vertices move piecewise-linearly between samples.
struct MeshAnimation {
    /// @brief Sample times in time codes, strictly increasing (K >= 1).
    std::vector<double> times;
    /// @brief World-space positions, sample-major: points[(k * vertex_count + v) * 3 + axis].
    std::vector<double> points;
    /// @brief Number of vertices N.
    int32_t vertex_count = 0;
    /// @brief Triangles indexing [0, vertex_count).
    std::vector<Triangle> triangles;
    /// @brief Authored face of each triangle; triangle pairs of one face are never tested.
    std::vector<int32_t> triangle_face;
};

} // namespace usdksl
