#pragma once
/// @file scene.hpp
/// @brief The meshes of one check with their flightplans, shared by every method.

#include "usdksl/collision/mesh_animation.hpp"
#include "usdksl/flightplan/flightplans.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief Meshes plus their flightplans and scale-derived tolerances.
struct Scene {
    /// @brief Builds flightplans for every mesh (merging collinear segments when asked).
    Scene(const std::vector<MeshAnimation>& meshes, bool merge_collinear);

    const std::vector<MeshAnimation>& meshes;
    std::vector<Flightplans> plans;
    /// @brief Largest absolute coordinate of the scene (scene units), at least 1.
    double scale = 1.0;
    /// @brief Largest distance (scene units, infinity norm) by which merging
    ///        collinear segments moved any vertex of any mesh off its samples.
    double merge_deviation = 0.0;

    /// @brief The contact distance the narrow phase must use so that merged
    ///        flightplans never hide a contact of the sampled ones: two
    ///        primitives may each have moved by sqrt(3) * merge_deviation.
    double contact_distance(double thickness) const { return thickness + 4.0 * merge_deviation; }

    /// @brief Positions of triangle `tri` of mesh `mesh` at time code t.
    std::array<Vec3, 3> triangle_at(int32_t mesh, int32_t tri, double t) const;
};

/// @brief Relative (to Scene::scale) slack by which a kinetic certificate lets
///        one vertex overtake another before it fails; boxes grow by the
///        accumulated slack so nothing is missed.
constexpr double KINETIC_ORDER_TOLERANCE = 1e-12;

/// @brief Relative (to Scene::scale) padding added to every box overlap test on
///        top of the thickness, covering rounding in box evaluation.
constexpr double BOX_PADDING = 1e-10;

} // namespace usdksl
