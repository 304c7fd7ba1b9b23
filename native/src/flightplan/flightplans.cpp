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

/// A run of consecutive vertices of one mesh, built on one thread: first its
/// breakpoints are chosen (how many per vertex), then, once every run of the
/// mesh has counted its own, written at their place in the mesh's arrays.
struct Flightplans::VertexRun {
    const MeshAnimation* mesh = nullptr;
    bool merge_collinear = false;
    int32_t plans = 0;  // index of the mesh's Flightplans in build_all's result
    int32_t first = 0, last = 0;  // vertices [first, last)
    /// Merging: the samples kept as breakpoints, vertex after vertex (empty
    /// without merging, where every sample is one).
    std::vector<int32_t> kept_samples;
    std::vector<int64_t> count;  // breakpoints per vertex
    std::vector<std::pair<int32_t, double>> deviations;  // vertices whose dropped samples lie off their flightplan
    double merge_deviation = 0.0;
    int64_t first_key = 0;  // index of the run's first breakpoint among the mesh's
};

void Flightplans::choose_breakpoints(VertexRun& run) {
    const MeshAnimation& mesh = *run.mesh;
    const int64_t sample_count = static_cast<int64_t>(mesh.times.size());
    const size_t n = static_cast<size_t>(mesh.vertex_count);
    const bool merge_collinear = run.merge_collinear;
    run.count.reserve(static_cast<size_t>(run.last - run.first));
    std::vector<int64_t> kept;
    kept.reserve(static_cast<size_t>(sample_count));
    for (int32_t v = run.first; v < run.last; ++v) {
        for (int64_t k = 0; k < sample_count; ++k) {
            const double* p = &mesh.points[(static_cast<size_t>(k) * n + static_cast<size_t>(v)) * 3];
            if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
                throw std::invalid_argument("flightplans: non-finite point coordinate");
            }
        }
        if (!merge_collinear) {
            run.count.push_back(sample_count);
            continue;
        }
        kept.clear();
        kept.push_back(0);
        double deviation = 0.0;  // of vertex v
        double run_deviation = 0.0;  // of the samples dropped since the last kept one
        double run_magnitude = sample_magnitude(mesh, v, 0);  // of the samples since the last kept one
        for (int64_t k = 1; k < sample_count; ++k) {
            if (k + 1 < sample_count) {
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
        if (deviation > 0.0) run.deviations.emplace_back(v, deviation);
        run.merge_deviation = std::max(run.merge_deviation, deviation);
        // A vertex that never moves keeps a single breakpoint.
        if (kept.size() == 2) {
            bool still = true;
            for (int axis = 0; axis < 3; ++axis) {
                still = still && mesh.points[(static_cast<size_t>(kept[0]) * n + v) * 3 + axis] ==
                                     mesh.points[(static_cast<size_t>(kept[1]) * n + v) * 3 + axis];
            }
            if (still) kept.pop_back();
        }
        for (int64_t k : kept) run.kept_samples.push_back(static_cast<int32_t>(k));
        run.count.push_back(static_cast<int64_t>(kept.size()));
    }
}

void Flightplans::write_breakpoints(const VertexRun& run, Storage& storage) {
    const MeshAnimation& mesh = *run.mesh;
    const size_t n = static_cast<size_t>(mesh.vertex_count);
    double* key_times = storage.key_times.get();
    double* key_points = storage.key_points.get();
    int64_t key = run.first_key;
    size_t kept_index = 0;
    for (int32_t v = run.first; v < run.last; ++v) {
        const int64_t count = run.count[static_cast<size_t>(v - run.first)];
        storage.offsets[static_cast<size_t>(v)] = key;
        double magnitude = 0.0;
        for (int64_t i = 0; i < count; ++i, ++key) {
            const int64_t k = run.merge_collinear ? run.kept_samples[kept_index++] : i;
            const double* p = &mesh.points[(static_cast<size_t>(k) * n + static_cast<size_t>(v)) * 3];
            key_times[key] = mesh.times[static_cast<size_t>(k)];
            key_points[3 * key] = p[0];
            key_points[3 * key + 1] = p[1];
            key_points[3 * key + 2] = p[2];
            magnitude = std::max(magnitude, sample_magnitude(mesh, v, k));
        }
        storage.vertex_magnitude[static_cast<size_t>(v)] = magnitude;
    }
}

Flightplans::Flightplans(const MeshAnimation& mesh, bool merge_collinear, int32_t threads)
    : Flightplans(std::move(build_all({FlightplanRequest{&mesh, merge_collinear}}, threads).front())) {}

std::vector<Flightplans> Flightplans::build_all(const std::vector<FlightplanRequest>& requests, int32_t threads) {
    std::vector<VertexRun> runs;
    for (size_t r = 0; r < requests.size(); ++r) {
        const MeshAnimation& mesh = *requests[r].mesh;
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
        // Every vertex's flightplan is its own: runs of vertices are built
        // apart and land in vertex order (the same arrays for any thread count).
        const int64_t samples_total = sample_count * static_cast<int64_t>(n);
        const int32_t run_count = static_cast<int32_t>(std::max<int64_t>(
            1, std::min<int64_t>(static_cast<int64_t>(n), samples_total / FLIGHTPLAN_SAMPLES_PER_RUN)));
        for (int32_t i = 0; i < run_count; ++i) {
            VertexRun run;
            run.mesh = &mesh;
            run.merge_collinear = requests[r].merge_collinear;
            run.plans = static_cast<int32_t>(r);
            run.first = static_cast<int32_t>(static_cast<int64_t>(n) * i / run_count);
            run.last = static_cast<int32_t>(static_cast<int64_t>(n) * (i + 1) / run_count);
            runs.push_back(std::move(run));
        }
    }
    const int32_t run_total = static_cast<int32_t>(runs.size());
    parallel_for(std::max(threads, 1), run_total, [&](int32_t i) { choose_breakpoints(runs[static_cast<size_t>(i)]); });

    std::vector<int64_t> keys(requests.size(), 0);  // breakpoints per mesh
    for (VertexRun& run : runs) {
        run.first_key = keys[static_cast<size_t>(run.plans)];
        for (int64_t count : run.count) keys[static_cast<size_t>(run.plans)] += count;
    }
    // Allocated here, filled by the runs' threads: no array is zeroed or copied first.
    std::vector<std::shared_ptr<Storage>> storages(requests.size());
    for (size_t r = 0; r < requests.size(); ++r) {
        const size_t n = static_cast<size_t>(requests[r].mesh->vertex_count);
        const size_t total = static_cast<size_t>(keys[r]);
        Storage& storage = *(storages[r] = std::make_shared<Storage>());
        storage.offsets.resize(n + 1);
        storage.offsets[n] = static_cast<int64_t>(total);
        storage.key_times = make_uninitialized_huge_array<double>(total);
        storage.key_points = make_uninitialized_huge_array<double>(3 * total);
        storage.vertex_magnitude.resize(n);
    }
    parallel_for(std::max(threads, 1), run_total, [&](int32_t i) {
        const VertexRun& run = runs[static_cast<size_t>(i)];
        write_breakpoints(run, *storages[static_cast<size_t>(run.plans)]);
    });
    std::vector<Flightplans> built(requests.size());
    for (const VertexRun& run : runs) {
        Storage& storage = *storages[static_cast<size_t>(run.plans)];
        for (const auto& [v, deviation] : run.deviations) {
            if (storage.vertex_deviation.empty()) storage.vertex_deviation.assign(storage.vertex_magnitude.size(), 0.0);
            storage.vertex_deviation[static_cast<size_t>(v)] = deviation;
        }
        Flightplans& plans = built[static_cast<size_t>(run.plans)];
        plans.merge_deviation_ = std::max(plans.merge_deviation_, run.merge_deviation);
    }
    for (size_t r = 0; r < requests.size(); ++r) {
        const MeshAnimation& mesh = *requests[r].mesh;
        Flightplans& plans = built[r];
        const Storage& storage = *storages[r];
        plans.vertex_count_ = mesh.vertex_count;
        plans.merged_ = static_cast<size_t>(keys[r]) < static_cast<size_t>(mesh.vertex_count) * mesh.times.size();
        for (double magnitude : storage.vertex_magnitude) plans.max_abs_coordinate_ = std::max(plans.max_abs_coordinate_, magnitude);
        plans.segment_hint_.assign(storage.offsets.begin(), storage.offsets.end() - 1);
        plans.offsets_ = storage.offsets.data();
        plans.key_times_ = storage.key_times.get();
        plans.key_points_ = storage.key_points.get();
        plans.vertex_magnitude_ = storage.vertex_magnitude.data();
        plans.vertex_deviation_ = storage.vertex_deviation.empty() ? nullptr : storage.vertex_deviation.data();
        plans.storage_ = std::move(storages[r]);
    }
    return built;
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
