#pragma once
/// @file face_index.hpp
/// @brief A mesh's authored faces as lists: the triangles of each face (a face
///        is fan-triangulated into several) and the vertices they use.

#include "usdksl/regions/mesh_view.hpp"

#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief Faces to triangles and to vertices, compressed rows: face f owns
///        triangles[triangle_start[f] .. triangle_start[f + 1]) (in triangle
///        order) and vertices[vertex_start[f] .. vertex_start[f + 1]) (sorted,
///        each once). A face without triangles owns neither.
struct FaceIndex {
    std::vector<int64_t> triangle_start;
    std::vector<int32_t> triangles;
    std::vector<int64_t> vertex_start;
    std::vector<int32_t> vertices;

    int32_t face_count() const { return static_cast<int32_t>(triangle_start.size()) - 1; }
    int64_t triangle_begin(int32_t face) const { return triangle_start[face]; }
    int64_t triangle_end(int32_t face) const { return triangle_start[face + 1]; }
    int64_t vertex_begin(int32_t face) const { return vertex_start[face]; }
    int64_t vertex_end(int32_t face) const { return vertex_start[face + 1]; }
};

/// @brief The index of `mesh`'s faces 0 .. face_count - 1 (triangles of a face
///        outside that range are left out).
FaceIndex build_face_index(const MeshView& mesh, int32_t face_count);

} // namespace usdksl
