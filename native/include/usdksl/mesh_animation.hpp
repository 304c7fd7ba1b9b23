#pragma once
/// @file mesh_animation.hpp
/// @brief One mesh as the core sees it: fixed triangles, sampled world-space points.

#include "usdksl/types.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief A triangle mesh whose vertices move piecewise-linearly between samples.
struct MeshAnimation {
    /// @brief Sample times in time codes, strictly increasing (K >= 1).
    std::vector<double> times;
    /// @brief World-space positions (scene units), sample-major:
    ///        points[(k * vertex_count + v) * 3 + axis]. Empty when the mesh
    ///        borrows them (borrowed_points, borrowed_float_points).
    std::vector<double> points;
    /// @brief Number of vertices N.
    int32_t vertex_count = 0;
    /// @brief Triangles indexing [0, vertex_count).
    std::vector<Triangle> triangles;
    /// @brief Authored face of each triangle; triangle pairs of one face are never tested.
    std::vector<int32_t> triangle_face;

    /// @brief The caller's positions, laid out as `points` and read in place
    ///        instead of it (at most one of the two set): a shot's samples are
    ///        the largest array of a check, so a binding lends them rather than
    ///        copies them. Floats are read as the same doubles. They must
    ///        outlive every use of the mesh and of flightplans built from it.
    const double* borrowed_points = nullptr;
    const float* borrowed_float_points = nullptr;
    /// @brief How many coordinates the borrowed positions hold.
    size_t borrowed_value_count = 0;

    /// @brief How many coordinates the positions hold (K * N * 3 when well formed).
    size_t point_value_count() const {
        return borrowed_points || borrowed_float_points ? borrowed_value_count : points.size();
    }

    /// @brief Coordinate at index i of the sample-major positions (scene units).
    double point_value(size_t i) const {
        if (borrowed_float_points) return static_cast<double>(borrowed_float_points[i]);
        return borrowed_points ? borrowed_points[i] : points[i];
    }

    /// @brief Index of vertex v's x coordinate at sample k among the positions.
    size_t sample_index(int64_t k, int32_t v) const {
        return (static_cast<size_t>(k) * static_cast<size_t>(vertex_count) + static_cast<size_t>(v)) * 3;
    }

    /// @brief Coordinate `axis` of vertex v at sample k (scene units).
    double sample_coord(int64_t k, int32_t v, int axis) const {
        return point_value(sample_index(k, v) + static_cast<size_t>(axis));
    }

    /// @brief Position of vertex v at sample k (scene units).
    Vec3 sample_point(int64_t k, int32_t v) const {
        const size_t at = sample_index(k, v);
        return Vec3(point_value(at), point_value(at + 1), point_value(at + 2));
    }
};

} // namespace usdksl
