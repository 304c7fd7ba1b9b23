#include "collinear_merge.hpp"

#include "chord_deviation.hpp"
#include "finite_sample.hpp"
#include "shared_breakpoints.hpp"

#include "usdksl/constants.hpp"

#include <algorithm>

namespace usdksl {

void CollinearMergeWalk::start(const MeshAnimation& mesh, int32_t v, const int64_t* popularity,
                               std::vector<int64_t>& kept) {
    kept.assign(1, 0);
    resume(mesh, v, popularity, kept, 0.0);
}

void CollinearMergeWalk::resume(const MeshAnimation& mesh, int32_t v, const int64_t* popularity,
                                std::vector<int64_t>& kept, double deviation) {
    mesh_ = &mesh;
    v_ = v;
    popularity_ = popularity;
    kept_ = &kept;
    sample_count_ = static_cast<int64_t>(mesh.times.size());
    deviation_ = deviation;
    ended_ = false;
    begin_run(kept.back());
}

void CollinearMergeWalk::begin_run(int64_t anchor) {
    const Vec3 anchor_point = finite_sample_point(*mesh_, anchor, v_);
    run_magnitude_ = point_magnitude(anchor_point);
    window_.reset(*mesh_, anchor, anchor_point);
    k_ = anchor + 1;
    if (k_ < sample_count_) {
        point_k_ = finite_sample_point(*mesh_, k_, v_);
        magnitude_k_ = point_magnitude(point_k_);
    }
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
        const Vec3 next = finite_sample_point(mesh, k + 1, v);
        const double magnitude_next = point_magnitude(next);
        const double magnitude = std::max({run_magnitude_, magnitude_k_, magnitude_next});
        window_.add(k, point_k_);
        bool merges = window_.admits_chord_to(k + 1, next, magnitude);
        if (!merges) {
            // From the latest sample back: a chord overshooting a turn at
            // sample k is furthest from the samples nearest it.
            const double merge_tolerance = FLIGHTPLAN_COLLINEAR_TOLERANCE * magnitude;
            const Chord chord(mesh, v, anchor, k + 1);
            merges = true;
            for (int64_t j = k; j > anchor && merges; --j) merges = chord.deviation_of(j) <= merge_tolerance;
        }
        if (merges) {
            run_magnitude_ = std::max(run_magnitude_, magnitude_k_);
            magnitude_k_ = magnitude_next;
            point_k_ = next;
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
    begin_run(k);
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

double align_collinear_samples(const MeshAnimation& mesh, int32_t v, const int64_t* popularity,
                               std::vector<int64_t>& kept, double deviation) {
    const int64_t sample_count = static_cast<int64_t>(mesh.times.size());
    const size_t moved = first_unpreferred_break(kept, sample_count, popularity);
    if (moved == kept.size()) return deviation;
    kept.resize(moved);
    CollinearMergeWalk walk;
    walk.resume(mesh, v, popularity, kept, merge_deviation_of(mesh, v, kept));
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
