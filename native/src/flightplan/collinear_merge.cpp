#include "collinear_merge.hpp"

#include "chord_deviation.hpp"
#include "shared_breakpoints.hpp"

#include "usdksl/constants.hpp"

#include <algorithm>

namespace usdksl {

void CollinearMergeWalk::start(const MeshAnimation& mesh, int32_t v, const int64_t* popularity,
                               std::vector<int64_t>& kept) {
    mesh_ = &mesh;
    v_ = v;
    popularity_ = popularity;
    kept_ = &kept;
    sample_count_ = static_cast<int64_t>(mesh.times.size());
    kept.clear();
    kept.push_back(0);
    deviation_ = 0.0;
    run_magnitude_ = sample_magnitude(mesh, v, 0);
    // sample_magnitude(mesh, v, k) for the k of the step, carried from the step before
    magnitude_k_ = sample_count_ > 1 ? sample_magnitude(mesh, v, 1) : 0.0;
    window_.reset(mesh, v, 0);
    k_ = 1;
    ended_ = false;
}

bool CollinearMergeWalk::advance() {
    if (ended_) return false;
    if (k_ >= sample_count_) {
        finish();
        return false;
    }
    const MeshAnimation& mesh = *mesh_;
    const int32_t v = v_;
    std::vector<int64_t>& kept = *kept_;
    int64_t k = k_;
    if (k + 1 < sample_count_) {
        // Drop sample k when every sample since the last kept one lies on
        // the chord from the last kept sample to sample k + 1.
        const int64_t anchor = kept.back();
        const double magnitude_next = sample_magnitude(mesh, v, k + 1);
        const double magnitude = std::max({run_magnitude_, magnitude_k_, magnitude_next});
        window_.add(k);
        bool merges = window_.admits_chord_to(k + 1, magnitude);
        if (!merges) {
            const double merge_tolerance = FLIGHTPLAN_COLLINEAR_TOLERANCE * magnitude;
            double worst = 0.0;
            for (int64_t j = anchor + 1; j <= k && worst <= merge_tolerance; ++j) {
                worst = std::max(worst, deviation_from_chord(mesh, v, anchor, j, k + 1));
            }
            merges = worst <= merge_tolerance;
        }
        if (merges) {
            run_magnitude_ = std::max(run_magnitude_, magnitude_k_);
            magnitude_k_ = magnitude_next;
            k_ = k + 1;
            return true;
        }
        // The run ends at or before k; the walk goes on from its end.
        const RunEnd end = aligned_run_end(mesh, v, anchor, k, popularity_);
        deviation_ = std::max(deviation_, end.deviation);
        k = end.sample;
    } else {
        deviation_ = std::max(deviation_, run_deviation(mesh, v, kept.back(), k));
    }
    kept.push_back(k);
    run_magnitude_ = sample_magnitude(mesh, v, k);
    if (k + 1 < sample_count_) magnitude_k_ = sample_magnitude(mesh, v, k + 1);
    window_.reset(mesh, v, k);
    k_ = k + 1;
    return true;
}

void CollinearMergeWalk::finish() {
    ended_ = true;
    std::vector<int64_t>& kept = *kept_;
    if (kept.size() == 2) {
        bool still = true;
        for (int axis = 0; axis < 3; ++axis) {
            still = still && mesh_->sample_coord(kept[0], v_, axis) == mesh_->sample_coord(kept[1], v_, axis);
        }
        if (still) kept.pop_back();
    }
}

double merge_collinear_samples(const MeshAnimation& mesh, int32_t v, const int64_t* popularity,
                               std::vector<int64_t>& kept) {
    CollinearMergeWalk walk;
    walk.start(mesh, v, popularity, kept);
    while (walk.advance()) {
    }
    return walk.deviation();
}

void merge_collinear_samples_of(const MeshAnimation& mesh, int32_t first, int32_t count,
                                std::vector<int64_t> (&kept)[COLLINEAR_MERGE_LANES],
                                double (&deviation)[COLLINEAR_MERGE_LANES]) {
    CollinearMergeWalk walks[COLLINEAR_MERGE_LANES];
    for (int32_t i = 0; i < count; ++i) walks[i].start(mesh, first + i, nullptr, kept[i]);
    for (bool going = true; going;) {
        going = false;
        for (int32_t i = 0; i < count; ++i) going = walks[i].advance() || going;
    }
    for (int32_t i = 0; i < count; ++i) deviation[i] = walks[i].deviation();
}

} // namespace usdksl
