#pragma once
/// @file flightplans.hpp
/// @brief Piecewise-linear vertex trajectories of one mesh, stored per vertex.

#include "usdksl/huge_page_allocator.hpp"
#include "usdksl/mesh_animation.hpp"
#include "usdksl/types.hpp"

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace usdksl {

/// @brief One mesh whose flightplans Flightplans::build_all builds.
struct FlightplanRequest {
    const MeshAnimation* mesh = nullptr;
    /// @brief See Flightplans(mesh, merge_collinear, threads).
    bool merge_collinear = false;
    /// @brief Merging, when above 0 (frames per time code, the stage's
    ///        clock): each sample between two whole frames (a simulator's
    ///        sub-frame samples; whole_frame_samples()) is dropped whatever its
    ///        distance from the flightplan, which counts in its vertex's
    ///        deviation as any dropped sample's does (the slack its contacts
    ///        are searched with before the raw samples confirm them); the
    ///        whole frames merge as they would alone.
    double frames_per_time_code = 0.0;
};

/// @brief The flightplans of every vertex of one mesh. Each vertex keeps its
///        own breakpoints (time codes) because consecutive collinear segments
///        merge: a keyframe animation densely resampled costs what its
///        keyframes cost. Before the first and after the last breakpoint a
///        vertex holds still (USD's value clamping). Flightplans that keep
///        every sample (built without merging) copy nothing: they read the
///        mesh's times and points in place, so the mesh must outlive them.
class Flightplans {
public:
    Flightplans() = default;

    /// @brief Builds the flightplans of `mesh`. With `merge_collinear`, a
    ///        breakpoint is dropped when the vertex passes through it on a
    ///        straight line at constant speed, within
    ///        FLIGHTPLAN_COLLINEAR_TOLERANCE times the largest absolute
    ///        coordinate of the samples that merge (local to the vertex and to
    ///        that stretch of time). Where a vertex must break somewhere in a
    ///        stretch of samples, it breaks at a sample most vertices keep, so
    ///        breakpoints line up across vertices (a first pass counts them):
    ///        the kinetic core steps along their union. Up to `threads`
    ///        threads build runs of vertices (the same flightplans for any count).
    Flightplans(const MeshAnimation& mesh, bool merge_collinear, int32_t threads = 1);

    /// @brief The flightplans of several meshes, one per request, built
    ///        together on up to `threads` threads: runs of vertices of every
    ///        mesh are handed out as one pool of work, so a few large meshes
    ///        and many small ones keep every thread busy (the same
    ///        flightplans for any count). The merging meshes line their
    ///        breakpoints up together: a vertex that must break prefers a time
    ///        that the vertices of every merging mesh keep, so a mesh's merged
    ///        flightplans may differ from those it gets built alone (each
    ///        within the same tolerance of its samples).
    static std::vector<Flightplans> build_all(const std::vector<FlightplanRequest>& requests, int32_t threads);

    int32_t vertex_count() const { return vertex_count_; }

    /// @brief Index range [key_begin(v), key_end(v)) of vertex v's breakpoints.
    int64_t key_begin(int32_t v) const { return offsets_[v]; }
    int64_t key_end(int32_t v) const { return offsets_[v + 1]; }

    /// @brief Time code of breakpoint k of vertex v.
    double key_time(int32_t v, int64_t k) const { return raw_ ? raw_times_[k - offsets_[v]] : key_times_[k]; }
    /// @brief Coordinate `axis` of breakpoint k of vertex v (scene units).
    double key_coord(int32_t v, int64_t k, int axis) const {
        return raw_ ? raw_->sample_coord(k - offsets_[v], v, axis) : key_points_[3 * k + axis];
    }
    /// @brief Position of breakpoint k of vertex v (scene units).
    Vec3 key_point(int32_t v, int64_t k) const {
        return raw_ ? raw_->sample_point(k - offsets_[v], v)
                    : Vec3(key_points_[3 * k], key_points_[3 * k + 1], key_points_[3 * k + 2]);
    }

    /// @brief Breakpoint index of v's segment containing time t: the last k with
    ///        key_time(k) <= t, or key_begin(v) when t is before every breakpoint.
    int64_t segment_of(int32_t v, double t) const;

    /// @brief segment_of(v, t) without moving the cursor: for a caller about to
    ///        walk ahead of the others with a cursor of its own.
    int64_t peek_segment(int32_t v, double t) const;

    /// @brief Coordinate `axis` of vertex v at time code t.
    double coord(int32_t v, int axis, double t) const { return coord_in_segment(v, segment_of(v, t), axis, t); }

    /// @brief Coordinate `axis` of vertex v at time code t, given the segment k
    ///        that contains t (as segment_of(v, t) returns it).
    double coord_in_segment(int32_t v, int64_t k, int axis, double t) const {
        const double t0 = key_time(v, k);
        if (k + 1 >= offsets_[v + 1] || t <= t0) return key_coord(v, k, axis);
        const double t1 = key_time(v, k + 1);
        const double p0 = key_coord(v, k, axis), p1 = key_coord(v, k + 1, axis);
        const double w = (t - t0) / (t1 - t0);
        return p0 + w * (p1 - p0);
    }

    /// @brief Position of vertex v at time code t.
    Vec3 position(int32_t v, double t) const { return position_in_segment(v, segment_of(v, t), t); }

    /// @brief Position of vertex v at time code t, given the segment k that
    ///        contains t (as segment_of(v, t) returns it); bit-identical to position().
    Vec3 position_in_segment(int32_t v, int64_t k, double t) const {
        const double t0 = key_time(v, k);
        const Vec3 p0 = key_point(v, k);
        if (k + 1 >= offsets_[v + 1] || t <= t0) return p0;
        const Vec3 p1 = key_point(v, k + 1);
        const double w = (t - t0) / (key_time(v, k + 1) - t0);
        // Same arithmetic as coord_in_segment(), so positions and single coordinates agree bit for bit.
        return Vec3(p0[0] + w * (p1[0] - p0[0]), p0[1] + w * (p1[1] - p0[1]), p0[2] + w * (p1[2] - p0[2]));
    }

    /// @brief Moves segment index k of vertex v forward to the segment that
    ///        contains time code t (as segment_of(v, t) would return it), for
    ///        callers that walk forward in time with their own cursor. k must
    ///        be a segment of v at or before t's.
    int64_t advance_segment(int32_t v, int64_t k, double t) const {
        while (k + 1 < offsets_[v + 1] && key_time(v, k + 1) <= t) ++k;
        return k;
    }

    /// @brief Earliest breakpoint of v strictly after time code t (+inf when none).
    double next_breakpoint(int32_t v, double t) const;

    /// @brief Largest absolute coordinate over every breakpoint (scene units).
    double max_abs_coordinate() const { return max_abs_coordinate_; }

    /// @brief Largest absolute coordinate vertex v reaches over its whole
    ///        flightplan (scene units): the size that rounding-error bounds of
    ///        anything computed from v's positions scale with.
    double vertex_magnitude(int32_t v) const { return vertex_magnitude_[v]; }

    /// @brief Largest distance (infinity norm, scene units) between a dropped
    ///        sample and the merged flightplan; 0 when nothing merged.
    double merge_deviation() const { return merge_deviation_; }

    /// @brief merge_deviation() of vertex v alone: 0 when none of v's
    ///        dropped samples lies off its merged flightplan.
    double vertex_deviation(int32_t v) const { return vertex_deviation_ ? vertex_deviation_[v] : 0.0; }

    /// @brief The largest distance (infinity norm, scene units) of v's
    ///        dropped samples on its segment k (from breakpoint k to the next,
    ///        or on after the last) from the flightplan: known per segment
    ///        where sub-frame samples were stepped over
    ///        (FlightplanRequest::frames_per_time_code), else
    ///        vertex_deviation(v). Never less than the truth.
    double segment_deviation(int32_t v, int64_t k) const {
        return key_deviation_ ? static_cast<double>(key_deviation_[k]) : vertex_deviation(v);
    }

    /// @brief True when segment_deviation() is known per segment.
    bool deviation_per_segment() const { return key_deviation_ != nullptr; }

    /// @brief True when some sample was dropped, so steps between breakpoints
    ///        may span several sample intervals.
    bool merged() const { return merged_; }


private:
    struct VertexRun;
    /// Picks the breakpoints of the run's vertices among their samples
    /// (all of them unless merging), checking that those samples are finite,
    /// and counts how many of its vertices keep each sample.
    static void choose_breakpoints(VertexRun& run);
    /// Per request, how many vertices of every merging mesh keep each of its
    /// samples' times, from the runs' counts (empty for a mesh not merging).
    static std::vector<std::vector<int64_t>> sample_popularity(const std::vector<FlightplanRequest>& requests,
                                                               std::vector<VertexRun>& runs);
    /// Merging again, each vertex whose breaks are not where the others
    /// break (shared_breakpoints.hpp), `popularity` indexed by the mesh's samples.
    static void align_breakpoints(VertexRun& run, const int64_t* popularity);
    /// For a run whose breakpoints were chosen among `mesh`'s whole frames
    /// alone (`sample`: each one's index among mesh's samples): the
    /// breakpoints as indices of mesh's samples, with the samples of every
    /// stretch that lies farther than `slack` from them added back
    /// (keep_bent_stretches), and each vertex's deviation from every sample
    /// of mesh left out, its sub-frame ones included.
    static void restore_sub_frame_samples(VertexRun& run, const MeshAnimation& mesh,
                                          const std::vector<int64_t>& sample, double slack);
    struct Storage;
    /// Writes the run's breakpoints, offsets and vertex magnitudes into the
    /// mesh's arrays, from its first breakpoint on.
    static void write_breakpoints(const VertexRun& run, Storage& storage);
    int64_t search_segment(int32_t v, double t) const;
    /// The times of v's breakpoints, [first, last).
    std::pair<const double*, const double*> breakpoint_times(int32_t v) const;

    /// The breakpoints, shared by copies: a copy costs one cursor per vertex,
    /// so each thread can walk its own.
    struct Storage {
        std::vector<int64_t> offsets;
        HugeArray<double> key_times;
        HugeArray<double> key_points;
        std::vector<double> vertex_magnitude;
        /// Per vertex, kept only when some vertex deviates.
        std::vector<double> vertex_deviation;
        /// Per breakpoint, kept only when sub-frame samples were stepped over.
        std::vector<float> key_deviation;
    };
    std::shared_ptr<const Storage> storage_;
    /// Flightplans that keep every sample: the mesh whose times and points
    /// they read in place (key_times_ and key_points_ are then null), and its
    /// times; breakpoint k of vertex v is its sample k - offsets_[v].
    const MeshAnimation* raw_ = nullptr;
    const double* raw_times_ = nullptr;
    int32_t vertex_count_ = -1;
    const int64_t* offsets_ = nullptr;
    const double* key_times_ = nullptr;
    const double* key_points_ = nullptr;
    const double* vertex_magnitude_ = nullptr;
    const double* vertex_deviation_ = nullptr;
    const float* key_deviation_ = nullptr;
    /// Last segment found per vertex: queries mostly move forward in time, so
    /// the answer is usually this segment or the next (a cache, not state;
    /// each copy has its own, so copies may be used from different threads).
    mutable std::vector<int64_t> segment_hint_;
    double max_abs_coordinate_ = 0.0;
    double merge_deviation_ = 0.0;
    bool merged_ = false;
};

} // namespace usdksl
