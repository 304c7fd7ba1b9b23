/// @file contact_rows.cpp
/// @brief Checks of the rows against the meshes, and their shared indexes.

#include "usdksl/regions/contact_rows.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace usdksl {
namespace {

std::vector<char> meshes_named(const std::vector<MeshView>& meshes, const ContactRows& rows) {
    std::vector<char> named(meshes.size(), 0);
    for (int64_t r = 0; r < rows.count; ++r) {
        named[static_cast<size_t>(rows.mesh_a[r])] = 1;
        named[static_cast<size_t>(rows.mesh_b[r])] = 1;
    }
    return named;
}

int32_t face_count_of(const MeshView& mesh) {
    int32_t largest = -1;
    for (int32_t t = 0; t < mesh.triangle_count; ++t) largest = std::max(largest, mesh.triangle_face[t]);
    return largest + 1;
}

} // namespace

void check_contact_rows(const std::vector<MeshView>& meshes, const ContactRows& rows) {
    const int32_t mesh_count = static_cast<int32_t>(meshes.size());
    std::vector<int32_t> face_count(meshes.size(), -1);
    for (int64_t r = 0; r < rows.count; ++r) {
        for (int side = 0; side < 2; ++side) {
            const int32_t mesh = side == 0 ? rows.mesh_a[r] : rows.mesh_b[r];
            const int32_t face = side == 0 ? rows.face_a[r] : rows.face_b[r];
            if (mesh < 0 || mesh >= mesh_count)
                throw std::invalid_argument("contact row " + std::to_string(r) + " names mesh " + std::to_string(mesh) +
                                            " of " + std::to_string(mesh_count));
            const MeshView& view = meshes[static_cast<size_t>(mesh)];
            if (face_count[mesh] < 0) {
                if (view.sample_count < 1) throw std::invalid_argument("mesh " + std::to_string(mesh) + " has no samples");
                for (int32_t i = 0; i < 3 * view.triangle_count; ++i) {
                    if (view.triangles[i] < 0 || view.triangles[i] >= view.vertex_count)
                        throw std::invalid_argument("mesh " + std::to_string(mesh) + " has a vertex index out of range");
                }
                face_count[mesh] = face_count_of(view);
            }
            if (face < 0 || face >= face_count[mesh])
                throw std::invalid_argument("contact row " + std::to_string(r) + " names face " + std::to_string(face) +
                                            " of mesh " + std::to_string(mesh) + ", which has " +
                                            std::to_string(face_count[mesh]) + " faces with triangles");
        }
    }
}

std::vector<FaceIndex> face_indexes_of_rows(const std::vector<MeshView>& meshes, const ContactRows& rows) {
    const std::vector<char> named = meshes_named(meshes, rows);
    std::vector<FaceIndex> indexes(meshes.size());
    for (size_t m = 0; m < meshes.size(); ++m) {
        indexes[m] = named[m] ? build_face_index(meshes[m], face_count_of(meshes[m])) : build_face_index(meshes[m], 0);
    }
    return indexes;
}

std::vector<std::vector<SampleBlend>> sample_blends_of_rows(const std::vector<MeshView>& meshes,
                                                            const ContactRows& rows,
                                                            const std::vector<double>& sample_times) {
    const std::vector<char> named = meshes_named(meshes, rows);
    std::vector<std::vector<SampleBlend>> blends(meshes.size());
    for (size_t m = 0; m < meshes.size(); ++m) {
        if (!named[m]) continue;
        blends[m].reserve(sample_times.size());
        for (double t : sample_times) blends[m].push_back(blend_at(meshes[m], t));
    }
    return blends;
}

int32_t first_sample_at_or_after(const std::vector<double>& sample_times, double t) {
    return static_cast<int32_t>(std::lower_bound(sample_times.begin(), sample_times.end(), t) - sample_times.begin());
}

int32_t last_sample_at_or_before(const std::vector<double>& sample_times, double t) {
    const int32_t after = static_cast<int32_t>(std::upper_bound(sample_times.begin(), sample_times.end(), t) -
                                               sample_times.begin());
    return std::max(after - 1, 0);
}

} // namespace usdksl
