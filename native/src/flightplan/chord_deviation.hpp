#pragma once
/// @file chord_deviation.hpp
/// @brief How far a vertex's samples lie from the chord that would replace
///        them when they merge, and the size that the merge tolerance scales with.

#include "usdksl/mesh_animation.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief The straight constant-speed path of vertex v from its sample i to
///        its sample k, to measure samples between against: what all of them
///        share is read once.
class Chord {
public:
    Chord(const MeshAnimation& mesh, int32_t v, int64_t i, int64_t k)
        : mesh_(mesh), v_(v), start_time_(mesh.times[i]), span_(mesh.times[k] - start_time_) {
        const Vec3 start = mesh.sample_point(i, v);
        const Vec3 end = mesh.sample_point(k, v);
        for (int axis = 0; axis < 3; ++axis) {
            start_[axis] = start[axis];
            change_[axis] = end[axis] - start[axis];
        }
    }

    /// @brief Distance (infinity norm, scene units) of sample j from the path.
    double deviation_of(int64_t j) const { return deviation_of(j, mesh_.sample_point(j, v_)); }

    /// @brief deviation_of(j) given the vertex's position `p` at sample j, read already.
    double deviation_of(int64_t j, const Vec3& p) const {
        const double w = (mesh_.times[j] - start_time_) / span_;
        double worst = 0.0;
        for (int axis = 0; axis < 3; ++axis) worst = std::max(worst, std::abs(start_[axis] + w * change_[axis] - p[axis]));
        return worst;
    }

private:
    const MeshAnimation& mesh_;
    int32_t v_;
    double start_time_;  // time code
    double span_;        // time codes
    double start_[3];    // scene units
    double change_[3];   // scene units
};

/// @brief Distance (infinity norm, scene units) of sample j of vertex v from
///        the straight constant-speed path between its samples i and k.
inline double deviation_from_chord(const MeshAnimation& mesh, int32_t v, int64_t i, int64_t j, int64_t k) {
    return Chord(mesh, v, i, k).deviation_of(j);
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
    const Chord chord(mesh, v, anchor, end);
    double worst = 0.0;
    for (int64_t j = anchor + 1; j < end; ++j) worst = std::max(worst, chord.deviation_of(j));
    return worst;
}

/// @brief Largest run_deviation() (scene units) of vertex v's runs between
///        consecutive breakpoints in `kept` (sample indices, ascending).
inline double merge_deviation_of(const MeshAnimation& mesh, int32_t v, const std::vector<int64_t>& kept) {
    double worst = 0.0;
    for (size_t i = 1; i < kept.size(); ++i) worst = std::max(worst, run_deviation(mesh, v, kept[i - 1], kept[i]));
    return worst;
}

/// @brief Largest sample_magnitude() of vertex v over samples first..last, ends included.
inline double run_magnitude(const MeshAnimation& mesh, int32_t v, int64_t first, int64_t last) {
    double magnitude = 0.0;
    for (int64_t k = first; k <= last; ++k) magnitude = std::max(magnitude, sample_magnitude(mesh, v, k));
    return magnitude;
}

} // namespace usdksl
