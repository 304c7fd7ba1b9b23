#pragma once
/// @file mesh_view.hpp
/// @brief One mesh's samples read in place: the measurement of contact
///        regions looks at a few faces at a few samples, so it reads the
///        caller's arrays instead of copying a shot's points.

#include "usdksl/types.hpp"

#include <array>
#include <cstdint>

namespace usdksl {

/// @brief Non-owning view of one mesh whose vertices move linearly between
///        samples and hold still before the first and after the last. The
///        arrays belong to the caller and must outlive every use of the view.
struct MeshView {
    /// @brief Sample times (time codes), strictly increasing, sample_count >= 1.
    const double* times = nullptr;
    int32_t sample_count = 0;
    /// @brief World-space positions (scene units), sample-major:
    ///        points[(k * vertex_count + v) * 3 + axis]; in double, or, when
    ///        `points` is null, in float (`points_float`: a loader keeps a
    ///        shot's authored float points as they are where they are already
    ///        in world space, half the memory, read here as the same doubles).
    const double* points = nullptr;
    const float* points_float = nullptr;
    int32_t vertex_count = 0;
    /// @brief Triangles as vertex index triplets, triangle_count of them.
    const int32_t* triangles = nullptr;
    int32_t triangle_count = 0;
    /// @brief Authored face of each triangle.
    const int32_t* triangle_face = nullptr;

    Triangle triangle(int32_t t) const {
        return {triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]};
    }
};

/// @brief Where a time falls among a mesh's samples: positions are
///        p[k0] + w * (p[k1] - p[k0]), w in [0, 1] (k0 == k1, w == 0 outside
///        the samples and exactly at one).
struct SampleBlend {
    int32_t k0 = 0;
    int32_t k1 = 0;
    double w = 0.0;
};

/// @brief The blend of mesh `mesh` at time code t.
SampleBlend blend_at(const MeshView& mesh, double t);

/// @brief Coordinate `axis` of vertex `vertex` at sample `k` (scene units).
inline double sample_coord(const MeshView& mesh, int32_t k, int32_t vertex, int axis) {
    const int64_t at = (static_cast<int64_t>(k) * mesh.vertex_count + vertex) * 3 + axis;
    return mesh.points ? mesh.points[at] : static_cast<double>(mesh.points_float[at]);
}
/// @brief Position of vertex `vertex` of `mesh` under `blend` (scene units).
inline Vec3 point_at(const MeshView& mesh, const SampleBlend& blend, int32_t vertex) {
    const double x0 = sample_coord(mesh, blend.k0, vertex, 0), y0 = sample_coord(mesh, blend.k0, vertex, 1),
                 z0 = sample_coord(mesh, blend.k0, vertex, 2);
    if (blend.w == 0.0) return Vec3(x0, y0, z0);
    const double x1 = sample_coord(mesh, blend.k1, vertex, 0), y1 = sample_coord(mesh, blend.k1, vertex, 1),
                 z1 = sample_coord(mesh, blend.k1, vertex, 2);
    return Vec3(x0 + blend.w * (x1 - x0), y0 + blend.w * (y1 - y0), z0 + blend.w * (z1 - z0));
}
/// @brief Positions of triangle `tri` of `mesh` under `blend`.
inline std::array<Vec3, 3> triangle_at(const MeshView& mesh, const SampleBlend& blend, int32_t tri) {
    const Triangle ids = mesh.triangle(tri);
    return {point_at(mesh, blend, ids[0]), point_at(mesh, blend, ids[1]), point_at(mesh, blend, ids[2])};
}

} // namespace usdksl
