#pragma once
/// @file sub_frame_samples.hpp
/// @brief A simulator's sub-frame samples (written for motion blur): merged
///        flightplans may step over them from whole frame to whole frame,
///        with their distance from the frames' chords as slack.

#include "usdksl/mesh_animation.hpp"

#include <cstdint>
#include <memory>
#include <vector>

namespace usdksl {

/// @brief Largest distance (in frames) of a time's frame from an integer for
///        the time to be a whole frame: the regions' WHOLE_FRAME_TOLERANCE.
constexpr double WHOLE_FRAME_TOLERANCE = 1e-6;

/// @brief Largest distance (infinity norm) of a vertex's sub-frame samples from
///        its flightplan between two whole frames, in multiples of the mesh's
///        median edge length: a stretch whose samples lie farther keeps them
///        as breakpoints. Each triangle's contact distance grows by four
///        times its vertices' slack at most (MERGE_DEVIATION_TO_DISTANCE), a
///        sixteenth of an edge: the frames a simulator's sub-frame samples
///        bend least step over them, those of an impact or a fast turn keep them.
constexpr double SUB_FRAME_SLACK_PER_EDGE = 1.0 / 64.0;

/// @brief The most slack (scene units) a vertex of `mesh` may take from its
///        sub-frame samples: SUB_FRAME_SLACK_PER_EDGE times the median length
///        of its triangles' edges at its first sample (0 without triangles).
double sub_frame_slack(const MeshAnimation& mesh);

/// @brief The samples of a mesh that merged flightplans step along, as a mesh
///        of their own, and where each sits among the mesh's samples.
struct WholeFrameSamples {
    /// @brief The mesh's samples but those between whole frames: times and
    ///        positions copied (no triangles).
    MeshAnimation mesh;
    /// @brief Sample index in the whole mesh of each of mesh's samples (ascending).
    std::vector<int64_t> sample;

private:
    friend std::unique_ptr<WholeFrameSamples> whole_frame_samples(const MeshAnimation&, double);
    std::vector<float> float_points_;
};

/// @brief The samples of `mesh` left when each sample between two whole
///        frames is left out (a sub-frame sample: its frame, time code x
///        `frames_per_time_code`, is not within WHOLE_FRAME_TOLERANCE of an
///        integer, and samples on the whole frames before and after it are
///        at most one frame apart); the first and the last sample always
///        stay. Null when no sample is left out (frames_per_time_code <= 0 or
///        not finite, a sample a frame or sparser, samples only between frames).
std::unique_ptr<WholeFrameSamples> whole_frame_samples(const MeshAnimation& mesh, double frames_per_time_code);

/// @brief Vertex v's breakpoints `kept` (sample indices of `mesh`, ascending,
///        the first 0), chosen among whole frames, with every sample of each
///        stretch between two of them (or after the last one, where the vertex
///        holds still) that lies farther than `slack` (scene units, infinity
///        norm) from the flightplan added back. Throws std::invalid_argument
///        for a coordinate that is not finite.
///        `segment_deviation`, when given, gets for each breakpoint left in
///        `kept` the largest such distance of the samples after it up to the
///        next one (or to the last sample).
/// @return The largest distance (infinity norm, scene units) of a sample
///         left out from the flightplan: at most `slack`.
double keep_bent_stretches(const MeshAnimation& mesh, int32_t v, double slack, std::vector<int64_t>& kept,
                           std::vector<double>* segment_deviation = nullptr);

} // namespace usdksl
