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
    ///        points[(k * vertex_count + v) * 3 + axis].
    const double* points = nullptr;
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

/// @brief Position of vertex `vertex` of `mesh` under `blend` (scene units).
inline Vec3 point_at(const MeshView& mesh, const SampleBlend& blend, int32_t vertex) {
    const double* p0 = mesh.points + (static_cast<int64_t>(blend.k0) * mesh.vertex_count + vertex) * 3;
    if (blend.w == 0.0) return Vec3(p0[0], p0[1], p0[2]);
    const double* p1 = mesh.points + (static_cast<int64_t>(blend.k1) * mesh.vertex_count + vertex) * 3;
    return Vec3(p0[0] + blend.w * (p1[0] - p0[0]), p0[1] + blend.w * (p1[1] - p0[1]),
                p0[2] + blend.w * (p1[2] - p0[2]));
}

/// @brief Positions of triangle `tri` of `mesh` under `blend`.
inline std::array<Vec3, 3> triangle_at(const MeshView& mesh, const SampleBlend& blend, int32_t tri) {
    const Triangle ids = mesh.triangle(tri);
    return {point_at(mesh, blend, ids[0]), point_at(mesh, blend, ids[1]), point_at(mesh, blend, ids[2])};
}

} // namespace usdksl
