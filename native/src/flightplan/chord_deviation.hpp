#pragma once
/// @file chord_deviation.hpp
/// @brief How far a vertex's samples lie from the chord that would replace
///        them when they merge, and the size that the merge tolerance scales with.

#include "usdksl/mesh_animation.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace usdksl {

/// @brief Distance (infinity norm, scene units) of sample j of vertex v from
///        the straight constant-speed path between its samples i and k.
inline double deviation_from_chord(const MeshAnimation& mesh, int32_t v, int64_t i, int64_t j, int64_t k) {
    const double ti = mesh.times[i], tj = mesh.times[j], tk = mesh.times[k];
    const double w = (tj - ti) / (tk - ti);
    double worst = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        const double pi = mesh.sample_coord(i, v, axis);
        const double pj = mesh.sample_coord(j, v, axis);
        const double pk = mesh.sample_coord(k, v, axis);
        worst = std::max(worst, std::abs(pi + w * (pk - pi) - pj));
    }
    return worst;
}

/// @brief Largest absolute coordinate of a position (scene units): the size
///        that rounding bounds of anything computed from it scale with.
inline double point_magnitude(const Vec3& p) { return std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2])}); }

/// @brief Largest absolute coordinate of vertex v at sample k (scene units).
inline double sample_magnitude(const MeshAnimation& mesh, int32_t v, int64_t k) {
    return point_magnitude(mesh.sample_point(k, v));
}

/// @brief Largest deviation_from_chord() (scene units) of the samples strictly
///        between `anchor` and `end` from the chord anchor..end: what a
///        flightplan segment from anchor to end adds to the merge deviation.
inline double run_deviation(const MeshAnimation& mesh, int32_t v, int64_t anchor, int64_t end) {
    double worst = 0.0;
    for (int64_t j = anchor + 1; j < end; ++j) worst = std::max(worst, deviation_from_chord(mesh, v, anchor, j, end));
    return worst;
}

/// @brief Largest sample_magnitude() of vertex v over samples first..last, ends included.
inline double run_magnitude(const MeshAnimation& mesh, int32_t v, int64_t first, int64_t last) {
    double magnitude = 0.0;
    for (int64_t k = first; k <= last; ++k) magnitude = std::max(magnitude, sample_magnitude(mesh, v, k));
    return magnitude;
}

} // namespace usdksl
