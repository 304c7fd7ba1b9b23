#pragma once
/// @file region_depths.hpp
/// @brief How deep each region goes at the measured samples of its span: the
///        length of the intersection curve of its face pairs, the penetration
///        depth into a closed side, and the box of both.
///
/// A region's span runs from the first sample at or after its earliest row
/// to the last sample of its rows' spans (region_grouping.hpp). Of those
/// samples it is measured at the first, at the last, and at every one
/// between them that the caller flags in `measured` (the check flags the
/// samples on whole frames of the stage's clock, and a sub-frame sample only
/// where the frame before it has no sample: docs/contracts.md, Regions).
/// Sub-frame samples (motion blur) cost as much as frames each without
/// changing what a person fixes, while the first and last samples keep a
/// contact that begins or ends between frames measured there. A deeper
/// moment strictly between two measured samples is not seen. At each
/// measured sample:
/// - intersection length: the summed lengths of the segments where a
///   triangle of a row's face_a crosses a triangle of its face_b
///   (intersection_segment.hpp; thickness plays no part, coplanar overlaps
///   add 0; a segment along an edge lying in the other triangle's plane is
///   found by both triangles of that edge, and each counts half). For faces
///   of one mesh, triangles that share an edge are left out, and triangles
///   that share a corner count only a segment of non-zero length (they always
///   meet at that corner);
/// - penetration, for a region of two meshes of which at least one is closed:
///   for a closed side X and the other side Y, the largest distance to X's
///   whole surface of a point of Y's region faces (the faces of Y its rows
///   name) inside X (inside_depth.hpp, within DEPTH_RELATIVE_ACCURACY); the
///   larger of the two when both are closed; NaN for a self region and when
///   neither side is closed;
/// - box: the world-space box of the intersection segments' endpoints and of
///   the inside points the depth search found; NaN when there are none.
/// Only these regions and their measured samples are evaluated, on threads,
/// one sample at a time (the closed meshes' trees are refit once per sample).

#include "usdksl/regions/contact_rows.hpp"

#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief The depth samples, one per (region, measured sample), sorted by
///        region then sample. Lengths in scene units.
struct RegionDepthSamples {
    std::vector<int32_t> region;
    std::vector<int32_t> sample;  ///< @brief Index into the sample times.
    std::vector<double> penetration;
    std::vector<double> intersection_length;
    std::vector<double> box_min;  ///< @brief 3 per sample (x, y, z).
    std::vector<double> box_max;
    /// @brief Signed distances the penetration search evaluated (its work).
    int64_t depth_evaluations = 0;
};

/// @brief What a grouping says of the rows (region_grouping.hpp).
struct RowRegions {
    const int32_t* row_region = nullptr;  ///< @brief 0 .. region_count - 1 per row
    const int32_t* row_span_last = nullptr;
    int32_t region_count = 0;
};

/// @brief The depth samples of every region of `grouping` at its measured
///        samples (see the file comment). `sample_times` in time codes,
///        sorted; `measured[s]`: sample s is measured inside a region's span
///        (one flag per sample time; a region's first and last samples are
///        measured whatever their flags). `closed[m]`: mesh m is closed
///        (watertight, consistently oriented). On up to `threads` threads;
///        the answer does not depend on the count. Throws
///        std::invalid_argument on rows the meshes do not have and on a flag
///        count other than the sample count.
RegionDepthSamples measure_region_depths(const std::vector<MeshView>& meshes, const ContactRows& rows,
                                         const RowRegions& grouping, const std::vector<double>& sample_times,
                                         const std::vector<char>& measured, const std::vector<char>& closed,
                                         int32_t threads);

} // namespace usdksl
