#include "sub_frame_samples.hpp"

#include "chord_deviation.hpp"
#include "finite_sample.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace usdksl {

std::unique_ptr<WholeFrameSamples> whole_frame_samples(const MeshAnimation& mesh, double frames_per_time_code) {
    const int64_t count = static_cast<int64_t>(mesh.times.size());
    if (!(frames_per_time_code > 0.0) || !std::isfinite(frames_per_time_code) || count < 3) return nullptr;
    std::vector<double> frame(static_cast<size_t>(count));
    std::vector<bool> whole(static_cast<size_t>(count));
    for (int64_t k = 0; k < count; ++k) {
        frame[k] = mesh.times[k] * frames_per_time_code;
        whole[k] = std::abs(frame[k] - std::round(frame[k])) <= WHOLE_FRAME_TOLERANCE;
    }
    std::vector<int64_t> kept;
    kept.reserve(static_cast<size_t>(count));
    int64_t last_whole = whole[0] ? 0 : -1;
    int64_t next_whole = -1;  // the first whole-frame sample after k
    for (int64_t k = 0; k < count; ++k) {
        if (whole[k]) last_whole = k;
        if (next_whole <= k) {
            next_whole = k + 1;
            while (next_whole < count && !whole[next_whole]) ++next_whole;
        }
        const bool between_frames = !whole[k] && k > 0 && k + 1 < count && last_whole >= 0 && next_whole < count &&
                                    std::round(frame[next_whole]) - std::round(frame[last_whole]) <= 1.0;
        if (!between_frames) kept.push_back(k);
    }
    if (static_cast<int64_t>(kept.size()) == count) return nullptr;

    auto view = std::make_unique<WholeFrameSamples>();
    view->sample = std::move(kept);
    MeshAnimation& out = view->mesh;
    out.vertex_count = mesh.vertex_count;
    const size_t per_sample = static_cast<size_t>(mesh.vertex_count) * 3;
    const size_t samples = view->sample.size();
    out.times.reserve(samples);
    for (int64_t k : view->sample) out.times.push_back(mesh.times[static_cast<size_t>(k)]);
    if (mesh.borrowed_float_points) {  // kept in single precision, as given
        view->float_points_.resize(samples * per_sample);
        for (size_t i = 0; i < samples; ++i) {
            std::memcpy(view->float_points_.data() + i * per_sample,
                        mesh.borrowed_float_points + mesh.sample_index(view->sample[i], 0), per_sample * sizeof(float));
        }
        out.borrowed_float_points = view->float_points_.data();
        out.borrowed_value_count = view->float_points_.size();
    } else {
        out.points.resize(samples * per_sample);
        for (size_t i = 0; i < samples; ++i) {
            const size_t from = mesh.sample_index(view->sample[i], 0);
            for (size_t j = 0; j < per_sample; ++j) out.points[i * per_sample + j] = mesh.point_value(from + j);
        }
    }
    return view;
}

double sub_frame_slack(const MeshAnimation& mesh) {
    std::vector<double> lengths;
    lengths.reserve(mesh.triangles.size() * 3);
    for (const Triangle& triangle : mesh.triangles) {
        for (int i = 0; i < 3; ++i) {
            const double length = (mesh.sample_point(0, triangle[(i + 1) % 3]) - mesh.sample_point(0, triangle[i])).norm();
            if (std::isfinite(length)) lengths.push_back(length);
        }
    }
    if (lengths.empty()) return 0.0;
    const auto middle = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
    std::nth_element(lengths.begin(), middle, lengths.end());
    return SUB_FRAME_SLACK_PER_EDGE * *middle;
}

double keep_bent_stretches(const MeshAnimation& mesh, int32_t v, double slack, std::vector<int64_t>& kept,
                           std::vector<double>* segment_deviation) {
    const int64_t count = static_cast<int64_t>(mesh.times.size());
    std::vector<int64_t> out;
    out.reserve(kept.size());
    std::vector<double> deviations;  // one per breakpoint in out: of the samples after it
    double worst = 0.0;
    for (size_t i = 0; i < kept.size(); ++i) {
        // The samples after breakpoint i up to the next: off its chord, or after the last, off where it holds.
        const int64_t from = kept[i];
        const bool last = i + 1 == kept.size();
        const int64_t to = last ? count : kept[i + 1];
        double farthest = 0.0;
        if (last) {
            const Vec3 held = mesh.sample_point(from, v);
            for (int64_t j = from + 1; j < to; ++j) {
                farthest = std::max(farthest, point_magnitude(finite_sample_point(mesh, j, v) - held));
            }
        } else {
            const Chord chord(mesh, v, from, to);
            for (int64_t j = from + 1; j < to; ++j) {
                farthest = std::max(farthest, chord.deviation_of(j, finite_sample_point(mesh, j, v)));
            }
        }
        const bool bent = farthest > slack;
        out.push_back(from);
        deviations.push_back(bent ? 0.0 : farthest);
        if (bent) {  // every sample of the stretch a breakpoint: none left out
            for (int64_t j = from + 1; j < to; ++j) {
                out.push_back(j);
                deviations.push_back(0.0);
            }
        } else {
            worst = std::max(worst, farthest);
        }
    }
    kept = std::move(out);
    if (segment_deviation) *segment_deviation = std::move(deviations);
    return worst;
}

} // namespace usdksl
