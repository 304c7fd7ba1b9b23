/// @file face_index.cpp
/// @brief Counting sort of the triangles by face, then each face's vertices.

#include "usdksl/regions/face_index.hpp"

#include <algorithm>

namespace usdksl {

FaceIndex build_face_index(const MeshView& mesh, int32_t face_count) {
    FaceIndex index;
    face_count = std::max(face_count, 0);
    index.triangle_start.assign(static_cast<size_t>(face_count) + 1, 0);
    for (int32_t t = 0; t < mesh.triangle_count; ++t) {
        const int32_t face = mesh.triangle_face[t];
        if (face >= 0 && face < face_count) ++index.triangle_start[face + 1];
    }
    for (int32_t f = 0; f < face_count; ++f) index.triangle_start[f + 1] += index.triangle_start[f];
    index.triangles.resize(static_cast<size_t>(index.triangle_start[face_count]));
    std::vector<int64_t> next(index.triangle_start.begin(), index.triangle_start.end() - 1);
    for (int32_t t = 0; t < mesh.triangle_count; ++t) {
        const int32_t face = mesh.triangle_face[t];
        if (face >= 0 && face < face_count) index.triangles[static_cast<size_t>(next[face]++)] = t;
    }
    index.vertex_start.assign(static_cast<size_t>(face_count) + 1, 0);
    index.vertices.reserve(index.triangles.size() + 2 * static_cast<size_t>(face_count));
    std::vector<int32_t> corners;
    for (int32_t f = 0; f < face_count; ++f) {
        corners.clear();
        for (int64_t i = index.triangle_start[f]; i < index.triangle_start[f + 1]; ++i) {
            const Triangle ids = mesh.triangle(index.triangles[static_cast<size_t>(i)]);
            corners.insert(corners.end(), ids.begin(), ids.end());
        }
        std::sort(corners.begin(), corners.end());
        corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
        index.vertices.insert(index.vertices.end(), corners.begin(), corners.end());
        index.vertex_start[f + 1] = static_cast<int64_t>(index.vertices.size());
    }
    return index;
}

} // namespace usdksl
