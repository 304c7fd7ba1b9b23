#pragma once
/// @file chord_velocity_window.hpp
/// @brief The chords from one kept sample that pass close to every sample
///        after it so far, as a window of velocities per axis: a merge test
///        in constant time where measuring each sample's distance from every
///        new chord costs the square of the run's length.

#include "chord_deviation.hpp"

#include "usdksl/constants.hpp"
#include "usdksl/mesh_animation.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>

namespace usdksl {

/// @brief Share (dimensionless) of the merge tolerance that the window
///        leaves out, so that what rounding adds to its test and to
///        deviation_from_chord() never turns a chord it admits into one
///        beyond the tolerance (rounding there is about 2^-49 of the largest
///        coordinate; this margin is 2^-30 of the anchor's).
constexpr double CHORD_WINDOW_MARGIN = 0x1p-8;

/// @brief Largest ratio (dimensionless) of a run's largest absolute
///        coordinate to its anchor's for which the window decides: beyond it
///        the margin, sized by the anchor, might not cover rounding sized by
///        the run (a vertex leaving the origin), and the merge is measured
///        sample by sample.
constexpr double CHORD_WINDOW_MAGNITUDE_RATIO = 0x1p10;

/// @brief Velocities (scene units per time code, per axis) of the chords
///        from an anchor sample of one vertex that pass within
///        (1 - CHORD_WINDOW_MARGIN) * FLIGHTPLAN_COLLINEAR_TOLERANCE times the
///        anchor's largest absolute coordinate of every sample added: sample
///        j at time offset tau and offset d from the anchor bounds the
///        velocity u by |u tau - d| <= tolerance. A chord inside the window
///        merges; one outside may still merge (its tolerance grows with the
///        run's coordinates) and is measured sample by sample.
class ChordVelocityWindow {
public:
    /// @brief Starts an empty window (every chord) at sample `anchor` of
    ///        vertex v, which lies at `anchor_point`.
    void reset(const MeshAnimation& mesh, int64_t anchor, const Vec3& anchor_point) {
        times_ = mesh.times.data();
        anchor_time_ = times_[anchor];
        anchor_point_ = anchor_point;
        anchor_magnitude_ = point_magnitude(anchor_point_);
        tolerance_ = (1.0 - CHORD_WINDOW_MARGIN) * FLIGHTPLAN_COLLINEAR_TOLERANCE * anchor_magnitude_;
        for (int axis = 0; axis < 3; ++axis) {
            low_[axis] = -std::numeric_limits<double>::infinity();
            high_[axis] = std::numeric_limits<double>::infinity();
        }
    }

    /// @brief Narrows the window to the chords that pass close to sample j
    ///        (after the anchor), where the vertex lies at `p`. One division:
    ///        a product with the reciprocal is within two roundings of the
    ///        quotient, far inside CHORD_WINDOW_MARGIN.
    void add(int64_t j, const Vec3& p) {
        const double per_tau = 1.0 / (times_[j] - anchor_time_);
        for (int axis = 0; axis < 3; ++axis) {
            const double d = p[axis] - anchor_point_[axis];
            low_[axis] = std::max(low_[axis], (d - tolerance_) * per_tau);
            high_[axis] = std::min(high_[axis], (d + tolerance_) * per_tau);
        }
    }

    /// @brief True when the chord from the anchor to sample `end`, where the
    ///        vertex lies at `p`, passes within the merge tolerance of every
    ///        sample added, given the largest absolute coordinate `magnitude`
    ///        of the samples from the anchor to `end` (false: not decided here).
    bool admits_chord_to(int64_t end, const Vec3& p, double magnitude) const {
        if (magnitude > CHORD_WINDOW_MAGNITUDE_RATIO * anchor_magnitude_) return false;
        const double per_span = 1.0 / (times_[end] - anchor_time_);
        for (int axis = 0; axis < 3; ++axis) {
            const double u = (p[axis] - anchor_point_[axis]) * per_span;
            if (!(u >= low_[axis] && u <= high_[axis])) return false;
        }
        return true;
    }

private:
    const double* times_ = nullptr;  // the mesh's sample times (time codes)
    double anchor_time_ = 0.0;  // time code
    Vec3 anchor_point_ = Vec3::Zero();  // scene units
    double anchor_magnitude_ = 0.0;  // scene units
    double tolerance_ = 0.0;  // scene units
    double low_[3] = {0.0, 0.0, 0.0}, high_[3] = {0.0, 0.0, 0.0};  // scene units per time code
};

} // namespace usdksl
