#include "collinear_merge.hpp"

#include "chord_deviation.hpp"
#include "chord_velocity_window.hpp"
#include "shared_breakpoints.hpp"

#include "usdksl/constants.hpp"

#include <algorithm>

namespace usdksl {

double merge_collinear_samples(const MeshAnimation& mesh, int32_t v, const int64_t* popularity,
                               std::vector<int64_t>& kept) {
    const int64_t sample_count = static_cast<int64_t>(mesh.times.size());
    kept.clear();
    kept.push_back(0);
    double deviation = 0.0;  // of vertex v
    double run_magnitude = sample_magnitude(mesh, v, 0);  // of the samples since the last kept one
    // sample_magnitude(mesh, v, k) for the k of the loop, carried from the iteration before
    double magnitude_k = sample_count > 1 ? sample_magnitude(mesh, v, 1) : 0.0;
    ChordVelocityWindow window;
    window.reset(mesh, v, 0);
    for (int64_t k = 1; k < sample_count; ++k) {
        if (k + 1 < sample_count) {
            // Drop sample k when every sample since the last kept one lies on
            // the chord from the last kept sample to sample k + 1.
            const int64_t anchor = kept.back();
            const double magnitude_next = sample_magnitude(mesh, v, k + 1);
            const double magnitude = std::max({run_magnitude, magnitude_k, magnitude_next});
            window.add(k);
            bool merges = window.admits_chord_to(k + 1, magnitude);
            if (!merges) {
                const double merge_tolerance = FLIGHTPLAN_COLLINEAR_TOLERANCE * magnitude;
                double worst = 0.0;
                for (int64_t j = anchor + 1; j <= k && worst <= merge_tolerance; ++j) {
                    worst = std::max(worst, deviation_from_chord(mesh, v, anchor, j, k + 1));
                }
                merges = worst <= merge_tolerance;
            }
            if (merges) {
                run_magnitude = std::max(run_magnitude, magnitude_k);
                magnitude_k = magnitude_next;
                continue;
            }
            // The run ends at or before k; the walk goes on from its end.
            const RunEnd end = aligned_run_end(mesh, v, anchor, k, popularity);
            deviation = std::max(deviation, end.deviation);
            k = end.sample;
        } else {
            deviation = std::max(deviation, run_deviation(mesh, v, kept.back(), k));
        }
        kept.push_back(k);
        run_magnitude = sample_magnitude(mesh, v, k);
        if (k + 1 < sample_count) magnitude_k = sample_magnitude(mesh, v, k + 1);
        window.reset(mesh, v, k);
    }
    if (kept.size() == 2) {
        bool still = true;
        for (int axis = 0; axis < 3; ++axis) {
            still = still && mesh.sample_coord(kept[0], v, axis) == mesh.sample_coord(kept[1], v, axis);
        }
        if (still) kept.pop_back();
    }
    return deviation;
}

} // namespace usdksl
