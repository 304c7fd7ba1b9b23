#include "usdksl/flightplan/flightplans.hpp"

#include "chord_deviation.hpp"
#include "collinear_merge.hpp"
#include "finite_sample.hpp"
#include "shared_breakpoints.hpp"
#include "sub_frame_samples.hpp"

#include "usdksl/constants.hpp"
#include "usdksl/run_on_threads.hpp"
#include "usdksl/single_precision.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>

namespace usdksl {

/// A run of consecutive vertices of one mesh, built on one thread: first its
/// breakpoints are chosen (how many per vertex), then aligned with those the
/// other vertices keep, then, once every run of the mesh has counted its own,
/// written at their place in the mesh's arrays.
struct Flightplans::VertexRun {
    const MeshAnimation* mesh = nullptr;
    bool merge_collinear = false;
    int32_t plans = 0;  // index of the mesh's Flightplans in build_all's result
    int32_t first = 0, last = 0;  // vertices [first, last)
    /// Merging: the samples kept as breakpoints, vertex after vertex (empty
    /// without merging, where every sample is one).
    std::vector<int32_t> kept_samples;
    std::vector<int64_t> count;  // breakpoints per vertex
    std::vector<double> deviation;  // merging: per vertex, of its dropped samples from its flightplan (scene units)
    /// Stepping over sub-frame samples: per breakpoint (as kept_samples), of the samples after it up to
    /// the next (scene units, rounded up to single precision).
    std::vector<float> key_deviation;
    /// Without merging: per vertex, the largest absolute coordinate over its samples (scene units).
    std::vector<double> magnitude;
    /// Merging, between the passes: how many of the run's vertices keep each sample of the mesh.
    std::vector<int64_t> kept_per_sample;
    double merge_deviation = 0.0;
    int64_t first_key = 0;  // index of the run's first breakpoint among the mesh's
};

void Flightplans::choose_breakpoints(VertexRun& run) {
    const MeshAnimation& mesh = *run.mesh;
    const int64_t sample_count = static_cast<int64_t>(mesh.times.size());
    const size_t run_size = static_cast<size_t>(run.last - run.first);
    if (!run.merge_collinear) {  // every sample a breakpoint: the samples are read in memory order
        run.magnitude.assign(run_size, 0.0);
        for (int64_t k = 0; k < sample_count; ++k) {
            for (int32_t v = run.first; v < run.last; ++v) {
                double& magnitude = run.magnitude[static_cast<size_t>(v - run.first)];
                magnitude = std::max(magnitude, point_magnitude(finite_sample_point(mesh, k, v)));
            }
        }
        run.count.assign(run_size, sample_count);
        return;
    }
    run.count.reserve(run_size);
    run.deviation.reserve(run_size);
    run.kept_per_sample.assign(static_cast<size_t>(sample_count), 0);
    std::vector<int64_t> kept[COLLINEAR_MERGE_LANES];
    double deviation[COLLINEAR_MERGE_LANES];
    for (std::vector<int64_t>& lane : kept) lane.reserve(static_cast<size_t>(sample_count));
    for (int32_t first = run.first; first < run.last; first += COLLINEAR_MERGE_LANES) {
        const int32_t count = std::min(COLLINEAR_MERGE_LANES, run.last - first);
        merge_collinear_samples_of(mesh, first, count, kept, deviation);
        for (int32_t i = 0; i < count; ++i) {
            run.deviation.push_back(deviation[i]);
            run.merge_deviation = std::max(run.merge_deviation, deviation[i]);
            for (int64_t k : kept[i]) {
                run.kept_samples.push_back(static_cast<int32_t>(k));
                ++run.kept_per_sample[static_cast<size_t>(k)];
            }
            run.count.push_back(static_cast<int64_t>(kept[i].size()));
        }
    }
}

void Flightplans::align_breakpoints(VertexRun& run, const int64_t* popularity) {
    if (!run.merge_collinear) return;
    const MeshAnimation& mesh = *run.mesh;
    const int64_t sample_count = static_cast<int64_t>(mesh.times.size());
    std::vector<int32_t> aligned;
    aligned.reserve(run.kept_samples.size());
    std::vector<int64_t> kept;
    kept.reserve(static_cast<size_t>(sample_count));
    run.merge_deviation = 0.0;
    size_t at = 0;  // v's first breakpoint in run.kept_samples
    for (size_t i = 0; i < run.count.size(); ++i) {
        const int32_t v = run.first + static_cast<int32_t>(i);
        kept.assign(run.kept_samples.begin() + static_cast<std::ptrdiff_t>(at),
                    run.kept_samples.begin() + static_cast<std::ptrdiff_t>(at + static_cast<size_t>(run.count[i])));
        at += static_cast<size_t>(run.count[i]);
        run.deviation[i] = align_collinear_samples(mesh, v, popularity, kept, run.deviation[i]);
        run.count[i] = static_cast<int64_t>(kept.size());
        for (int64_t k : kept) aligned.push_back(static_cast<int32_t>(k));
        run.merge_deviation = std::max(run.merge_deviation, run.deviation[i]);
    }
    run.kept_samples = std::move(aligned);
}

void Flightplans::restore_sub_frame_samples(VertexRun& run, const MeshAnimation& mesh,
                                            const std::vector<int64_t>& sample, double slack) {
    run.mesh = &mesh;
    run.merge_deviation = 0.0;
    std::vector<int32_t> restored;
    restored.reserve(run.kept_samples.size());
    run.key_deviation.clear();
    std::vector<int64_t> kept;
    std::vector<double> segment_deviation;
    size_t at = 0;  // v's first breakpoint in run.kept_samples
    for (size_t i = 0; i < run.count.size(); ++i) {
        const int32_t v = run.first + static_cast<int32_t>(i);
        kept.clear();
        for (int64_t j = 0; j < run.count[i]; ++j, ++at) {
            kept.push_back(sample[static_cast<size_t>(run.kept_samples[at])]);
        }
        run.deviation[i] = keep_bent_stretches(mesh, v, slack, kept, &segment_deviation);
        run.merge_deviation = std::max(run.merge_deviation, run.deviation[i]);
        run.count[i] = static_cast<int64_t>(kept.size());
        for (int64_t k : kept) restored.push_back(static_cast<int32_t>(k));
        for (double d : segment_deviation) run.key_deviation.push_back(float_at_least(d));
    }
    run.kept_samples = std::move(restored);
}

void Flightplans::write_breakpoints(const VertexRun& run, Storage& storage) {
    const MeshAnimation& mesh = *run.mesh;
    double* key_times = storage.key_times.get();
    double* key_points = storage.key_points.get();
    int64_t key = run.first_key;
    size_t kept_index = 0;
    for (int32_t v = run.first; v < run.last; ++v) {
        const int64_t count = run.count[static_cast<size_t>(v - run.first)];
        storage.offsets[static_cast<size_t>(v)] = key;
        if (!run.merge_collinear) {  // every sample, read in place
            storage.vertex_magnitude[static_cast<size_t>(v)] = run.magnitude[static_cast<size_t>(v - run.first)];
            key += count;
            continue;
        }
        double magnitude = 0.0;
        for (int64_t i = 0; i < count; ++i, ++key) {
            if (!run.key_deviation.empty()) storage.key_deviation[static_cast<size_t>(key)] = run.key_deviation[kept_index];
            const int64_t k = run.kept_samples[kept_index++];
            const Vec3 p = mesh.sample_point(k, v);
            key_times[key] = mesh.times[static_cast<size_t>(k)];
            key_points[3 * key] = p[0];
            key_points[3 * key + 1] = p[1];
            key_points[3 * key + 2] = p[2];
            magnitude = std::max(magnitude, point_magnitude(p));
        }
        storage.vertex_magnitude[static_cast<size_t>(v)] = magnitude;
    }
}

Flightplans::Flightplans(const MeshAnimation& mesh, bool merge_collinear, int32_t threads)
    : Flightplans(std::move(build_all({FlightplanRequest{&mesh, merge_collinear}}, threads).front())) {}

std::vector<std::vector<int64_t>> Flightplans::sample_popularity(const std::vector<FlightplanRequest>& requests,
                                                                 std::vector<VertexRun>& runs) {
    // Breakpoints are sample times, and the kinetic core steps along their
    // union over every mesh: a time counts for each vertex of any merging
    // mesh that keeps it.
    std::vector<double> times;
    for (const FlightplanRequest& request : requests) {
        if (request.merge_collinear) times.insert(times.end(), request.mesh->times.begin(), request.mesh->times.end());
    }
    std::sort(times.begin(), times.end());
    times.erase(std::unique(times.begin(), times.end()), times.end());
    std::vector<std::vector<size_t>> time_index(requests.size());  // per merging mesh: each sample's place in `times`
    for (size_t r = 0; r < requests.size(); ++r) {
        if (!requests[r].merge_collinear) continue;
        for (double t : requests[r].mesh->times) {
            time_index[r].push_back(static_cast<size_t>(std::lower_bound(times.begin(), times.end(), t) - times.begin()));
        }
    }
    // Integer sums: the same in any order, so for any thread count.
    std::vector<int64_t> kept_at(times.size(), 0);
    for (VertexRun& run : runs) {
        const std::vector<size_t>& index = time_index[static_cast<size_t>(run.plans)];
        for (size_t k = 0; k < run.kept_per_sample.size(); ++k) kept_at[index[k]] += run.kept_per_sample[k];
        run.kept_per_sample = std::vector<int64_t>();
    }
    std::vector<std::vector<int64_t>> popularity(requests.size());
    for (size_t r = 0; r < requests.size(); ++r) {
        for (size_t i : time_index[r]) popularity[r].push_back(kept_at[i]);
    }
    return popularity;
}

std::vector<Flightplans> Flightplans::build_all(const std::vector<FlightplanRequest>& requests, int32_t threads) {
    std::vector<VertexRun> runs;
    // Breakpoints are chosen among the whole frames of a mesh with sub-frame
    // samples to step over, and its runs then see its every sample again.
    std::vector<std::unique_ptr<WholeFrameSamples>> frames(requests.size());
    std::vector<double> slack(requests.size(), 0.0);
    std::vector<FlightplanRequest> choosing = requests;
    for (size_t r = 0; r < requests.size(); ++r) {
        const MeshAnimation& mesh = *requests[r].mesh;
        const int64_t sample_count = static_cast<int64_t>(mesh.times.size());
        const int32_t n = mesh.vertex_count;
        if (sample_count < 1 || n < 0 ||
            mesh.point_value_count() != static_cast<size_t>(sample_count) * static_cast<size_t>(n) * 3) {
            throw std::invalid_argument("flightplans: points do not match times x vertex_count x 3");
        }
        for (int64_t k = 1; k < sample_count; ++k) {
            if (!(mesh.times[k] > mesh.times[k - 1])) {
                throw std::invalid_argument("flightplans: sample times must be strictly increasing");
            }
        }
        if (requests[r].merge_collinear && (frames[r] = whole_frame_samples(mesh, requests[r].frames_per_time_code))) {
            choosing[r].mesh = &frames[r]->mesh;
            slack[r] = sub_frame_slack(mesh);
        }
        // Every vertex's flightplan is its own: runs of vertices are built
        // apart and land in vertex order (the same arrays for any thread count).
        const int64_t samples_total = sample_count * static_cast<int64_t>(n);
        const int32_t run_count = static_cast<int32_t>(std::max<int64_t>(
            1, std::min<int64_t>(static_cast<int64_t>(n), samples_total / FLIGHTPLAN_SAMPLES_PER_RUN)));
        for (int32_t i = 0; i < run_count; ++i) {
            VertexRun run;
            run.mesh = choosing[r].mesh;
            run.merge_collinear = requests[r].merge_collinear;
            run.plans = static_cast<int32_t>(r);
            run.first = static_cast<int32_t>(static_cast<int64_t>(n) * i / run_count);
            run.last = static_cast<int32_t>(static_cast<int64_t>(n) * (i + 1) / run_count);
            runs.push_back(std::move(run));
        }
    }
    const int32_t run_total = static_cast<int32_t>(runs.size());
    parallel_for(std::max(threads, 1), run_total, [&](int32_t i) { choose_breakpoints(runs[static_cast<size_t>(i)]); });
    const std::vector<std::vector<int64_t>> popularity = sample_popularity(choosing, runs);
    parallel_for(std::max(threads, 1), run_total, [&](int32_t i) {
        VertexRun& run = runs[static_cast<size_t>(i)];
        align_breakpoints(run, popularity[static_cast<size_t>(run.plans)].data());
        const size_t r = static_cast<size_t>(run.plans);
        if (frames[r]) restore_sub_frame_samples(run, *requests[r].mesh, frames[r]->sample, slack[r]);
    });

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
        if (requests[r].merge_collinear) {  // flightplans of every sample read the mesh in place
            storage.key_times = make_uninitialized_huge_array<double>(total);
            storage.key_points = make_uninitialized_huge_array<double>(3 * total);
        }
        if (frames[r]) storage.key_deviation.resize(total);
        storage.vertex_magnitude.resize(n);
    }
    parallel_for(std::max(threads, 1), run_total, [&](int32_t i) {
        const VertexRun& run = runs[static_cast<size_t>(i)];
        write_breakpoints(run, *storages[static_cast<size_t>(run.plans)]);
    });
    std::vector<Flightplans> built(requests.size());
    for (const VertexRun& run : runs) {
        Storage& storage = *storages[static_cast<size_t>(run.plans)];
        for (size_t i = 0; i < run.deviation.size(); ++i) {
            if (run.deviation[i] == 0.0) continue;
            if (storage.vertex_deviation.empty()) storage.vertex_deviation.assign(storage.vertex_magnitude.size(), 0.0);
            storage.vertex_deviation[static_cast<size_t>(run.first) + i] = run.deviation[i];
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
        if (!requests[r].merge_collinear) {
            plans.raw_ = &mesh;
            plans.raw_times_ = mesh.times.data();
        }
        plans.vertex_magnitude_ = storage.vertex_magnitude.data();
        plans.vertex_deviation_ = storage.vertex_deviation.empty() ? nullptr : storage.vertex_deviation.data();
        plans.key_deviation_ = storage.key_deviation.empty() ? nullptr : storage.key_deviation.data();
        plans.storage_ = std::move(storages[r]);
    }
    return built;
}

int64_t Flightplans::segment_of(int32_t v, double t) const {
    const int64_t end = offsets_[v + 1];
    int64_t k = segment_hint_[v];
    for (int step = 0; step < 2 && k < end; ++step, ++k) {
        if (key_time(v, k) <= t && (k + 1 == end || key_time(v, k + 1) > t)) return segment_hint_[v] = k;
    }
    return segment_hint_[v] = search_segment(v, t);
}

int64_t Flightplans::peek_segment(int32_t v, double t) const {
    const int64_t end = offsets_[v + 1];
    const int64_t k = segment_hint_[v];
    if (k < end && key_time(v, k) <= t && (k + 1 == end || key_time(v, k + 1) > t)) return k;
    return search_segment(v, t);
}

std::pair<const double*, const double*> Flightplans::breakpoint_times(int32_t v) const {
    if (raw_) return {raw_times_, raw_times_ + (offsets_[v + 1] - offsets_[v])};
    return {key_times_ + offsets_[v], key_times_ + offsets_[v + 1]};
}

int64_t Flightplans::search_segment(int32_t v, double t) const {
    const auto [first, last] = breakpoint_times(v);
    auto it = std::upper_bound(first, last, t);
    if (it == first) return offsets_[v];
    return offsets_[v] + static_cast<int64_t>(it - first) - 1;
}

double Flightplans::next_breakpoint(int32_t v, double t) const {
    const auto [first, last] = breakpoint_times(v);
    auto it = std::upper_bound(first, last, t);
    return it == last ? std::numeric_limits<double>::infinity() : *it;
}

} // namespace usdksl
