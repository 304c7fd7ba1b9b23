#pragma once
/// @file collinear_merge.hpp
/// @brief The breakpoints of one vertex: its samples, less those it passes
///        through on a straight line at constant speed.

#include "chord_velocity_window.hpp"

#include "usdksl/mesh_animation.hpp"

#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief Fills `kept` with vertex v's breakpoints (sample indices,
///        ascending): walking forward from the last kept sample, a sample is
///        dropped while every sample since the last kept one lies on the
///        chord from the last kept sample to the next sample, within
///        FLIGHTPLAN_COLLINEAR_TOLERANCE times the largest absolute coordinate
///        of those samples (local to the vertex and to that stretch of time:
///        one vertex far away, a simulation blow-up, loosens nothing
///        elsewhere). Every sample is read, and a coordinate that is not
///        finite throws std::invalid_argument. Where a merge fails the run ends at the sample
///        aligned_run_end() picks with `popularity` (how many vertices keep
///        each sample; null: where it failed). A vertex that never moves
///        keeps its first sample alone.
/// @return The largest distance (infinity norm, scene units) of a dropped
///         sample from v's merged flightplan, computed for the runs kept.
double merge_collinear_samples(const MeshAnimation& mesh, int32_t v, const int64_t* popularity,
                               std::vector<int64_t>& kept);

/// @brief merge_collinear_samples(mesh, v, popularity, kept), given in `kept`
///        and `deviation` what merge_collinear_samples(mesh, v, nullptr, kept)
///        keeps and returns: the walk with `popularity` takes the same steps
///        up to the first break that popularity moves
///        (first_unpreferred_break), so it goes on from the break before that
///        one; with none, the breakpoints stay.
/// @return As merge_collinear_samples() returns (scene units).
double align_collinear_samples(const MeshAnimation& mesh, int32_t v, const int64_t* popularity,
                               std::vector<int64_t>& kept, double deviation);

/// @brief merge_collinear_samples() of one vertex as a walk that goes a
///        sample at a time, so that the walks of several vertices can take
///        turns on one thread: a walk along one vertex waits on each step's
///        divisions and on loading the next sample, a whole sample of the
///        mesh further on, and the other walks' independent work fills that
///        time. Each walk does exactly what merge_collinear_samples() does.
class CollinearMergeWalk {
public:
    /// @brief Begins vertex v's walk, filling `kept` (which must outlive the walk).
    void start(const MeshAnimation& mesh, int32_t v, const int64_t* popularity, std::vector<int64_t>& kept);
    /// @brief Goes on with vertex v's walk from the breakpoints in `kept` (its
    ///        last the anchor of the run to walk), as start() would have
    ///        reached them, `deviation` the largest of their runs (scene units).
    void resume(const MeshAnimation& mesh, int32_t v, const int64_t* popularity, std::vector<int64_t>& kept,
                double deviation);
    /// @brief Takes the walk past its next sample; false once it has ended,
    ///        when `kept` and deviation() are final (then it does nothing).
    bool advance();
    /// @brief As merge_collinear_samples() returns (scene units), once advance() returned false.
    double deviation() const { return deviation_; }

private:
    /// Starts the run from sample `anchor`, the walk's last breakpoint.
    void begin_run(int64_t anchor);
    void finish();

    const MeshAnimation* mesh_ = nullptr;
    int32_t v_ = 0;
    const int64_t* popularity_ = nullptr;
    std::vector<int64_t>* kept_ = nullptr;
    int64_t sample_count_ = 0;
    int64_t k_ = 0;  // the sample the next advance() looks at
    bool ended_ = true;
    double deviation_ = 0.0;      // scene units
    double run_magnitude_ = 0.0;  // of the samples since the last kept one (scene units)
    Vec3 point_k_ = Vec3::Zero();  // the vertex at sample k_ (scene units), read once per step
    double magnitude_k_ = 0.0;    // point_magnitude() of point_k_ (scene units)
    ChordVelocityWindow window_;
};

/// @brief Walks (vertices) that take turns on one thread in
///        merge_collinear_samples_of(): enough to cover a step's latency.
constexpr int32_t COLLINEAR_MERGE_LANES = 8;

/// @brief merge_collinear_samples(mesh, v, nullptr, kept[i]) for v = first + i,
///        i < count <= COLLINEAR_MERGE_LANES, the walks taking turns; returns
///        each deviation in `deviation`.
void merge_collinear_samples_of(const MeshAnimation& mesh, int32_t first, int32_t count,
                                std::vector<int64_t> (&kept)[COLLINEAR_MERGE_LANES],
                                double (&deviation)[COLLINEAR_MERGE_LANES]);

} // namespace usdksl
