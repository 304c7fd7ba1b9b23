#pragma once
/// @file scene.hpp
/// @brief The meshes of one check with their flightplans, shared by every method.

#include "usdksl/mesh_animation.hpp"
#include "usdksl/flightplan/flightplans.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief How the flightplans of one mesh are built.
enum class FlightplanKind {
    /// @brief Every authored sample is a breakpoint (what the contract is about).
    RawSamples,
    /// @brief Collinear samples merge (cheaper; a candidate filter with slack).
    MergedSamples,
    /// @brief Not needed by this check: no flightplans are built.
    Unused,
};

/// @brief Factor from a flightplan's merge deviation (infinity norm, per
///        vertex) to the Euclidean distance by which any point of a triangle
///        may have moved off its sampled trajectory: sqrt(3), rounded up.
constexpr double MERGE_DEVIATION_TO_DISTANCE = 2.0;

/// @brief Meshes plus their flightplans and the slack merging introduced.
struct Scene {
    /// @brief Builds flightplans for every mesh, merging collinear segments
    ///        when asked, on up to `threads` threads; merging, they step over
    ///        sub-frame samples too when `frames_per_time_code` is above 0
    ///        (FlightplanRequest::frames_per_time_code).
    Scene(const std::vector<MeshAnimation>& meshes, bool merge_collinear, int32_t threads = 1,
          double frames_per_time_code = 0.0);

    /// @brief Builds flightplans of the given kind per mesh (kinds.size() ==
    ///        meshes.size()), on up to `threads` threads; merging ones step
    ///        over sub-frame samples when `frames_per_time_code` is above 0.
    Scene(const std::vector<MeshAnimation>& meshes, const std::vector<FlightplanKind>& kinds, int32_t threads = 1,
          double frames_per_time_code = 0.0);

    const std::vector<MeshAnimation>& meshes;
    std::vector<Flightplans> plans;

    /// @brief Largest distance (scene units, infinity norm) by which merging
    ///        moved a vertex of mesh `mesh` off its samples; 0 for raw samples.
    double merge_deviation(int32_t mesh) const { return merge_deviation_[mesh]; }

    /// @brief True when mesh `mesh`'s flightplans dropped samples, so its
    ///        contacts are candidates to confirm on the raw samples.
    bool merged(int32_t mesh) const { return plans[mesh].merged(); }

    /// @brief The contact distance (scene units) the narrow phase uses for a
    ///        triangle of mesh_a against one of mesh_b, so that merged
    ///        flightplans never hide a contact of the sampled ones. The slack
    ///        is local to the two meshes: a curved mesh elsewhere adds nothing.
    double contact_distance(int32_t mesh_a, int32_t mesh_b, double thickness) const {
        return thickness + MERGE_DEVIATION_TO_DISTANCE * (merge_deviation_[mesh_a] + merge_deviation_[mesh_b]);
    }

    /// @brief contact_distance(mesh_a, mesh_b, thickness) for one triangle
    ///        pair, with the slack of its own six vertices: a triangle's points
    ///        leave their sampled trajectories only as far as its vertices do,
    ///        so a pair whose vertices merged only exactly collinear samples
    ///        (or none) is tested at the thickness alone, whatever a vertex
    ///        elsewhere in the mesh merged. Never more than the meshes' value.
    double contact_distance(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b, double thickness) const {
        return thickness + MERGE_DEVIATION_TO_DISTANCE * (triangle_deviation(mesh_a, tri_a) + triangle_deviation(mesh_b, tri_b));
    }

    /// @brief Scene units that no coordinate of triangle `tri` of mesh
    ///        `mesh` exceeds over its whole flightplan (for rounding allowances).
    double triangle_magnitude(int32_t mesh, int32_t tri) const {
        const Flightplans& p = plans[mesh];
        double magnitude = 0.0;
        for (int32_t v : meshes[mesh].triangles[tri]) magnitude = std::max(magnitude, p.vertex_magnitude(v));
        return magnitude;
    }

    /// @brief Largest merge deviation (infinity norm, scene units) of the
    ///        vertices of triangle `tri` of mesh `mesh`.
    double triangle_deviation(int32_t mesh, int32_t tri) const {
        if (merge_deviation_[mesh] == 0.0) return 0.0;
        const Flightplans& p = plans[mesh];
        double deviation = 0.0;
        for (int32_t v : meshes[mesh].triangles[tri]) deviation = std::max(deviation, p.vertex_deviation(v));
        return deviation;
    }

    /// @brief Positions of triangle `tri` of mesh `mesh` at time code t.
    std::array<Vec3, 3> triangle_at(int32_t mesh, int32_t tri, double t) const;

private:
    std::vector<double> merge_deviation_;
};

} // namespace usdksl
