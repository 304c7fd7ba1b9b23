#pragma once
/// @file finite_sample.hpp
/// @brief A vertex's sampled position, refused when not finite: flightplans
///        are built from finite samples only.

#include "usdksl/mesh_animation.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace usdksl {

/// @brief Vertex v's position at sample k of `mesh` (scene units); throws
///        std::invalid_argument when a coordinate is not finite.
inline Vec3 finite_sample_point(const MeshAnimation& mesh, int64_t k, int32_t v) {
    const Vec3 p = mesh.sample_point(k, v);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
        throw std::invalid_argument("flightplans: non-finite point coordinate");
    }
    return p;
}

} // namespace usdksl
