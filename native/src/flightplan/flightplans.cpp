#include "usdksl/flightplan/flightplans.hpp"

#include "usdksl/constants.hpp"
#include "usdksl/run_on_threads.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>

namespace usdksl {
namespace {

/// Distance (infinity norm) of sample j from the straight constant-speed path
/// between samples i and k.
double deviation_from_chord(const MeshAnimation& mesh, int32_t v, int64_t i, int64_t j, int64_t k) {
    const double ti = mesh.times[i], tj = mesh.times[j], tk = mesh.times[k];
    const double w = (tj - ti) / (tk - ti);
    const size_t n = static_cast<size_t>(mesh.vertex_count);
    double worst = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        const double pi = mesh.points[(i * n + v) * 3 + axis];
        const double pj = mesh.points[(j * n + v) * 3 + axis];
        const double pk = mesh.points[(k * n + v) * 3 + axis];
        worst = std::max(worst, std::abs(pi + w * (pk - pi) - pj));
    }
    return worst;
}

/// Largest absolute coordinate of vertex v at sample k (scene units).
double sample_magnitude(const MeshAnimation& mesh, int32_t v, int64_t k) {
    const double* p = &mesh.points[(static_cast<size_t>(k) * static_cast<size_t>(mesh.vertex_count) + v) * 3];
    return std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2])});
}

} // namespace

/// The breakpoints of one run of consecutive vertices, built on their own
/// (on one thread) and then appended to the mesh's in vertex order.
struct Flightplans::VertexRange {
    std::vector<int64_t> count;  // breakpoints per vertex
    std::vector<double> key_times;
    std::vector<double> key_points;
    std::vector<std::pair<int32_t, double>> deviations;  // vertices whose dropped samples lie off their flightplan
    double merge_deviation = 0.0;
    double max_abs_coordinate = 0.0;
};

void Flightplans::build_range(const MeshAnimation& mesh, bool merge_collinear, int32_t first, int32_t last,
                              std::vector<double>& vertex_magnitude, VertexRange& range) {
    const int64_t sample_count = static_cast<int64_t>(mesh.times.size());
    const int32_t n = mesh.vertex_count;
    std::vector<int64_t> kept;
    kept.reserve(static_cast<size_t>(sample_count));
    for (int32_t v = first; v < last; ++v) {
        kept.clear();
        kept.push_back(0);
        double deviation = 0.0;  // of vertex v
        double run_deviation = 0.0;  // of the samples dropped since the last kept one
        double run_magnitude = sample_magnitude(mesh, v, 0);  // of the samples since the last kept one
        for (int64_t k = 1; k < sample_count; ++k) {
            if (merge_collinear && k + 1 < sample_count) {
                // Drop sample k when every sample since the last kept one lies on
                // the chord from the last kept sample to sample k + 1, within a
                // tolerance relative to those samples alone: one vertex far away
                // (a simulation blow-up) loosens nothing elsewhere.
                const int64_t anchor = kept.back();
                const double magnitude = std::max({run_magnitude, sample_magnitude(mesh, v, k),
                                                   sample_magnitude(mesh, v, k + 1)});
                const double merge_tolerance = FLIGHTPLAN_COLLINEAR_TOLERANCE * magnitude;
                double worst = 0.0;
                for (int64_t j = anchor + 1; j <= k && worst <= merge_tolerance; ++j) {
                    worst = std::max(worst, deviation_from_chord(mesh, v, anchor, j, k + 1));
                }
                if (worst <= merge_tolerance) {
                    run_magnitude = std::max(run_magnitude, sample_magnitude(mesh, v, k));
                    run_deviation = worst;
                    continue;
                }
                deviation = std::max(deviation, run_deviation);
                run_deviation = 0.0;
            }
            kept.push_back(k);
            run_magnitude = sample_magnitude(mesh, v, k);
        }
        deviation = std::max(deviation, run_deviation);
        if (deviation > 0.0) range.deviations.emplace_back(v, deviation);
        range.merge_deviation = std::max(range.merge_deviation, deviation);
        // A vertex that never moves keeps a single breakpoint.
        if (merge_collinear && kept.size() == 2) {
            bool still = true;
            for (int axis = 0; axis < 3; ++axis) {
                still = still && mesh.points[(static_cast<size_t>(kept[0]) * n + v) * 3 + axis] ==
                                     mesh.points[(static_cast<size_t>(kept[1]) * n + v) * 3 + axis];
            }
            if (still) kept.pop_back();
        }
        for (int64_t k : kept) {
            vertex_magnitude[v] = std::max(vertex_magnitude[v], sample_magnitude(mesh, v, k));
            range.key_times.push_back(mesh.times[k]);
            for (int axis = 0; axis < 3; ++axis) {
                range.key_points.push_back(mesh.points[(static_cast<size_t>(k) * n + v) * 3 + axis]);
            }
        }
        range.count.push_back(static_cast<int64_t>(kept.size()));
        range.max_abs_coordinate = std::max(range.max_abs_coordinate, vertex_magnitude[v]);
    }
}

Flightplans::Flightplans(const MeshAnimation& mesh, bool merge_collinear, int32_t threads) {
    const int64_t sample_count = static_cast<int64_t>(mesh.times.size());
    const int32_t n = mesh.vertex_count;
    if (sample_count < 1 || n < 0 ||
        mesh.points.size() != static_cast<size_t>(sample_count) * static_cast<size_t>(n) * 3) {
        throw std::invalid_argument("flightplans: points do not match times x vertex_count x 3");
    }
    for (int64_t k = 1; k < sample_count; ++k) {
        if (!(mesh.times[k] > mesh.times[k - 1])) {
            throw std::invalid_argument("flightplans: sample times must be strictly increasing");
        }
    }
    for (double c : mesh.points) {
        if (!std::isfinite(c)) throw std::invalid_argument("flightplans: non-finite point coordinate");
    }

    auto storage = std::make_shared<Storage>();
    std::vector<double>& vertex_magnitude = storage->vertex_magnitude;
    vertex_magnitude.assign(static_cast<size_t>(n), 0.0);
    // Every vertex's flightplan is its own: runs of vertices are built on as
    // many threads, then joined in vertex order (the same arrays for any count).
    const int64_t samples_total = sample_count * static_cast<int64_t>(n);
    const int32_t ranges = static_cast<int32_t>(std::max<int64_t>(
        1, std::min<int64_t>({static_cast<int64_t>(std::max(threads, 1)), static_cast<int64_t>(n),
                              samples_total / FLIGHTPLAN_SAMPLES_PER_THREAD})));
    std::vector<VertexRange> parts(static_cast<size_t>(ranges));
    const auto range_begin = [&](int32_t r) { return static_cast<int32_t>(static_cast<int64_t>(n) * r / ranges); };
    parallel_for(ranges, ranges, [&](int32_t r) {
        build_range(mesh, merge_collinear, range_begin(r), range_begin(r + 1), vertex_magnitude,
                    parts[static_cast<size_t>(r)]);
    });
    std::vector<int64_t>& offsets = storage->offsets;
    std::vector<double>& key_times = storage->key_times;
    std::vector<double>& key_points = storage->key_points;
    std::vector<double>& vertex_deviation = storage->vertex_deviation;
    size_t total = 0;
    for (const VertexRange& part : parts) total += part.key_times.size();
    offsets.reserve(static_cast<size_t>(n) + 1);
    offsets.push_back(0);
    // The first run's arrays become the mesh's (on one thread, the only copy); the others follow them.
    key_times = std::move(parts[0].key_times);
    key_points = std::move(parts[0].key_points);
    key_times.reserve(total);
    key_points.reserve(3 * total);
    for (size_t r = 0; r < parts.size(); ++r) {
        const VertexRange& part = parts[r];
        for (int64_t count : part.count) offsets.push_back(offsets.back() + count);
        if (r > 0) {
            key_times.insert(key_times.end(), part.key_times.begin(), part.key_times.end());
            key_points.insert(key_points.end(), part.key_points.begin(), part.key_points.end());
        }
        for (const auto& [v, deviation] : part.deviations) {
            if (vertex_deviation.empty()) vertex_deviation.assign(static_cast<size_t>(n), 0.0);
            vertex_deviation[static_cast<size_t>(v)] = deviation;
        }
        merge_deviation_ = std::max(merge_deviation_, part.merge_deviation);
        max_abs_coordinate_ = std::max(max_abs_coordinate_, part.max_abs_coordinate);
    }
    merged_ = key_times.size() < static_cast<size_t>(n) * static_cast<size_t>(sample_count);
    segment_hint_.assign(offsets.begin(), offsets.end() - 1);
    vertex_count_ = n;
    offsets_ = offsets.data();
    key_times_ = key_times.data();
    key_points_ = key_points.data();
    vertex_magnitude_ = vertex_magnitude.data();
    vertex_deviation_ = vertex_deviation.empty() ? nullptr : vertex_deviation.data();
    storage_ = std::move(storage);
}

int64_t Flightplans::segment_of(int32_t v, double t) const {
    const int64_t end = offsets_[v + 1];
    int64_t k = segment_hint_[v];
    for (int step = 0; step < 2 && k < end; ++step, ++k) {
        if (key_times_[k] <= t && (k + 1 == end || key_times_[k + 1] > t)) return segment_hint_[v] = k;
    }
    return segment_hint_[v] = search_segment(v, t);
}

int64_t Flightplans::peek_segment(int32_t v, double t) const {
    const int64_t end = offsets_[v + 1];
    const int64_t k = segment_hint_[v];
    if (k < end && key_times_[k] <= t && (k + 1 == end || key_times_[k + 1] > t)) return k;
    return search_segment(v, t);
}

int64_t Flightplans::search_segment(int32_t v, double t) const {
    const auto first = key_times_ + offsets_[v];
    const auto last = key_times_ + offsets_[v + 1];
    auto it = std::upper_bound(first, last, t);
    if (it == first) return offsets_[v];
    return static_cast<int64_t>(it - key_times_) - 1;
}

double Flightplans::next_breakpoint(int32_t v, double t) const {
    const auto first = key_times_ + offsets_[v];
    const auto last = key_times_ + offsets_[v + 1];
    auto it = std::upper_bound(first, last, t);
    return it == last ? std::numeric_limits<double>::infinity() : *it;
}

} // namespace usdksl
