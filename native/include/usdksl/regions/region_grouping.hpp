#pragma once
/// @file region_grouping.hpp
/// @brief Contact rows grouped into regions: the face pairs of one mesh pair
///        that are connected on the meshes and overlap in time.
///
/// A row's span in sample steps is [i0, i1]: i0 the last sample at or before
/// its time (0 when none), i1 = max(i0 + 1, the sample of its last sampled
/// contact), at most the last sample. Its last sampled contact: when its two
/// faces are in contact (any triangle of one within `thickness` of any
/// triangle of the other, triangle_pair_intersect_static, which leaves out
/// the primitives two faces of one mesh share) at s0, the first sample at or
/// after its time, the last sample of the run of samples from s0 on at which
/// they stay in contact; otherwise (a graze, gone by the next sample) its own
/// time. Two rows of one mesh pair are in one region when a face of one and a
/// face of the other share a vertex (on side a, on side b, or for a mesh with
/// itself on any side) and their spans intersect; regions are the connected
/// components. Connection through shared vertices means that one large face
/// (a table top of two triangles) joins every contact on it that overlaps in
/// time, however far apart.
///
/// Cost: the contact test walks each row's samples while it stays in contact;
/// the grouping is linear in the rows' vertices (per vertex, its rows in span
/// order, each joined to the one reaching furthest so far), with no pair of
/// rows compared directly.

#include "usdksl/regions/contact_rows.hpp"

#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief Regions of contact rows and the spans they were grouped by.
struct RegionGrouping {
    /// @brief Region of each row, 0 .. region_count - 1, numbered in the order
    ///        of each region's first row.
    std::vector<int32_t> row_region;
    int32_t region_count = 0;
    /// @brief Each row's last sampled contact (time codes; its own time for a graze).
    std::vector<double> row_last_sampled;
    /// @brief Each row's span: first and last sample index.
    std::vector<int32_t> row_span_first;
    std::vector<int32_t> row_span_last;
};

/// @brief Groups `rows` of `meshes` into regions (see the file comment), the
///        contact tests at `sample_times` (sorted time codes, at least one) on
///        up to `threads` threads; the answer does not depend on the count.
///        Throws std::invalid_argument on rows the meshes do not have
///        (check_contact_rows).
RegionGrouping group_regions(const std::vector<MeshView>& meshes, const ContactRows& rows,
                             const std::vector<double>& sample_times, double thickness, int32_t threads);

} // namespace usdksl
