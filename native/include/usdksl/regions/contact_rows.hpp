#pragma once
/// @file contact_rows.hpp
/// @brief The rows of a check's contact table as the regions read them (one
///        per contacting face pair, in the table's order), and what every
///        measurement of them first builds: the faces of the meshes they name
///        and where each sample time falls in each mesh.

#include "usdksl/regions/face_index.hpp"
#include "usdksl/regions/mesh_view.hpp"

#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief Columns of contact rows, read in place (the caller owns them).
///        Row r: face face_a[r] of mesh mesh_a[r] first touches face
///        face_b[r] of mesh mesh_b[r] at time[r] (time codes).
struct ContactRows {
    int64_t count = 0;
    const double* time = nullptr;
    const int32_t* mesh_a = nullptr;
    const int32_t* face_a = nullptr;
    const int32_t* mesh_b = nullptr;
    const int32_t* face_b = nullptr;

    bool is_self(int64_t row) const { return mesh_a[row] == mesh_b[row]; }
};

/// @brief Throws std::invalid_argument when a row names a mesh not in
///        `meshes` or a face outside 0 .. the largest face of its mesh's
///        triangles, or when a mesh a row names has no samples or a triangle
///        vertex out of range.
void check_contact_rows(const std::vector<MeshView>& meshes, const ContactRows& rows);

/// @brief The face index of every mesh a row names (an empty one for the
///        others), faces 0 .. largest triangle_face.
std::vector<FaceIndex> face_indexes_of_rows(const std::vector<MeshView>& meshes, const ContactRows& rows);

/// @brief blends[mesh][s]: where sample_times[s] falls in each mesh a row names
///        (empty for the others).
std::vector<std::vector<SampleBlend>> sample_blends_of_rows(const std::vector<MeshView>& meshes,
                                                            const ContactRows& rows,
                                                            const std::vector<double>& sample_times);

/// @brief First sample index s with sample_times[s] >= t (sample_times.size()
///        when there is none).
int32_t first_sample_at_or_after(const std::vector<double>& sample_times, double t);

/// @brief Last sample index s with sample_times[s] <= t (0 when there is none).
int32_t last_sample_at_or_before(const std::vector<double>& sample_times, double t);

} // namespace usdksl
