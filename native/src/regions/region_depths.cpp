/// @file region_depths.cpp
/// @brief Regions laid out per measured sample, each sample measured on one
///        thread: closed meshes placed and refit, then each active region's
///        segments and depth.

#include "usdksl/regions/region_depths.hpp"

#include "usdksl/regions/closed_surface.hpp"
#include "usdksl/regions/inside_depth.hpp"
#include "usdksl/regions/intersection_segment.hpp"
#include "usdksl/run_on_threads.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace usdksl {
namespace {

constexpr double NOT_A_NUMBER = std::numeric_limits<double>::quiet_NaN();

/// Compressed rows: items of list i are items[start[i] .. start[i + 1]).
struct Lists {
    std::vector<int64_t> start;
    std::vector<int32_t> items;
};

/// What a region needs, gathered once.
struct RegionPlan {
    int32_t mesh_a = 0;
    int32_t mesh_b = 0;
    int32_t first = 0;  // sample indices
    int32_t last = 0;
    int64_t output = 0;  // its first output row
    int64_t measured_count = 0;
    bool into_a = false;  // penetration into closed side a (of side b's faces)
    bool into_b = false;
};

int shared_corners(const Triangle& a, const Triangle& b) {
    int shared = 0;
    for (int32_t x : a)
        for (int32_t y : b) shared += x == y;
    return shared;
}

struct Box {
    bool any = false;
    Vec3 lo = Vec3::Zero();
    Vec3 hi = Vec3::Zero();
    void add(const Vec3& p) {
        lo = any ? lo.cwiseMin(p) : p;
        hi = any ? hi.cwiseMax(p) : p;
        any = true;
    }
};

/// The part of a segment's length one triangle pair counts: a segment along
/// an edge that lies in the other triangle's plane is found again with the
/// triangle across that edge, so each of the two counts half of it (a quarter
/// when it runs along an edge of each).
double edge_share(const IntersectionSegment& segment) {
    return (segment.along_edge_of_a ? 0.5 : 1.0) * (segment.along_edge_of_b ? 0.5 : 1.0);
}

bool boxes_apart(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
    const Vec3 a_lo = a[0].cwiseMin(a[1]).cwiseMin(a[2]), a_hi = a[0].cwiseMax(a[1]).cwiseMax(a[2]);
    const Vec3 b_lo = b[0].cwiseMin(b[1]).cwiseMin(b[2]), b_hi = b[0].cwiseMax(b[1]).cwiseMax(b[2]);
    return (a_lo.array() > b_hi.array()).any() || (b_lo.array() > a_hi.array()).any();
}

} // namespace

RegionDepthSamples measure_region_depths(const std::vector<MeshView>& meshes, const ContactRows& rows,
                                         const RowRegions& grouping, const std::vector<double>& sample_times,
                                         const std::vector<char>& measured, const std::vector<char>& closed,
                                         int32_t threads) {
    check_contact_rows(meshes, rows);
    if (closed.size() != meshes.size()) throw std::invalid_argument("closed needs one flag per mesh");
    if (measured.size() != sample_times.size())
        throw std::invalid_argument("measured needs one flag per sample time");
    const int32_t region_count = grouping.region_count;
    const int32_t sample_count = static_cast<int32_t>(sample_times.size());
    RegionDepthSamples out;
    if (region_count <= 0 || rows.count == 0) return out;
    if (sample_count == 0) throw std::invalid_argument("no sample times");
    if (rows.count > std::numeric_limits<int32_t>::max()) throw std::invalid_argument("too many contact rows");
    for (int64_t r = 0; r < rows.count; ++r) {
        if (grouping.row_region[r] < 0 || grouping.row_region[r] >= region_count)
            throw std::invalid_argument("row " + std::to_string(r) + " has no region in 0.." +
                                        std::to_string(region_count - 1));
    }

    // flagged_before[s]: flagged samples before s, so a region's row count and each sample's output row
    // are a difference of two entries.
    std::vector<int64_t> flagged_before(static_cast<size_t>(sample_count) + 1, 0);
    for (int32_t s = 0; s < sample_count; ++s) flagged_before[s + 1] = flagged_before[s] + (measured[s] != 0);

    const std::vector<FaceIndex> faces = face_indexes_of_rows(meshes, rows);
    const std::vector<std::vector<SampleBlend>> blends = sample_blends_of_rows(meshes, rows, sample_times);

    // Each region's rows, in table order.
    Lists region_rows;
    region_rows.start.assign(static_cast<size_t>(region_count) + 1, 0);
    for (int64_t r = 0; r < rows.count; ++r) ++region_rows.start[grouping.row_region[r] + 1];
    for (int32_t g = 0; g < region_count; ++g) region_rows.start[g + 1] += region_rows.start[g];
    region_rows.items.resize(static_cast<size_t>(rows.count));
    {
        std::vector<int64_t> next(region_rows.start.begin(), region_rows.start.end() - 1);
        for (int64_t r = 0; r < rows.count; ++r)
            region_rows.items[static_cast<size_t>(next[grouping.row_region[r]]++)] = static_cast<int32_t>(r);
    }

    std::vector<RegionPlan> plans(static_cast<size_t>(region_count));
    int64_t total = 0;
    for (int32_t g = 0; g < region_count; ++g) {
        RegionPlan& plan = plans[g];
        if (region_rows.start[g] == region_rows.start[g + 1])
            throw std::invalid_argument("region " + std::to_string(g) + " has no rows");
        const int32_t head = region_rows.items[static_cast<size_t>(region_rows.start[g])];
        plan.mesh_a = rows.mesh_a[head];
        plan.mesh_b = rows.mesh_b[head];
        plan.first = sample_count - 1;
        plan.last = 0;
        for (int64_t i = region_rows.start[g]; i < region_rows.start[g + 1]; ++i) {
            const int32_t r = region_rows.items[static_cast<size_t>(i)];
            if (rows.mesh_a[r] != plan.mesh_a || rows.mesh_b[r] != plan.mesh_b)
                throw std::invalid_argument("region " + std::to_string(g) + " holds rows of two mesh pairs");
            plan.first = std::min(plan.first, std::min(first_sample_at_or_after(sample_times, rows.time[r]), sample_count - 1));
            plan.last = std::max(plan.last, std::min(std::max(grouping.row_span_last[r], 0), sample_count - 1));
        }
        plan.last = std::max(plan.last, plan.first);
        const bool self = plan.mesh_a == plan.mesh_b;
        plan.into_a = !self && closed[plan.mesh_a];
        plan.into_b = !self && closed[plan.mesh_b];
        plan.output = total;
        // its first and last samples, whatever their flags, and the flagged samples strictly between
        plan.measured_count = (plan.last > plan.first ? 2 : 1) +
                              std::max<int64_t>(0, flagged_before[plan.last] - flagged_before[plan.first + 1]);
        total += plan.measured_count;
    }
    const auto is_measured = [&](const RegionPlan& plan, int32_t s) {
        return s == plan.first || s == plan.last || measured[s] != 0;
    };
    // The output row of a measured sample s of a plan: rows run over its measured samples in order.
    const auto output_row = [&](const RegionPlan& plan, int32_t s) -> int64_t {
        if (s == plan.first) return plan.output;
        if (s == plan.last) return plan.output + plan.measured_count - 1;
        return plan.output + 1 + (flagged_before[s] - flagged_before[plan.first + 1]);
    };

    // The penetrating side's faces of each region: side b's faces go into a, side a's into b.
    const auto side_faces = [&](int32_t g, bool side_a) {
        std::vector<int32_t> list;
        for (int64_t i = region_rows.start[g]; i < region_rows.start[g + 1]; ++i) {
            const int32_t r = region_rows.items[static_cast<size_t>(i)];
            list.push_back(side_a ? rows.face_a[r] : rows.face_b[r]);
        }
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
        return list;
    };
    std::vector<std::vector<int32_t>> into_a_faces(static_cast<size_t>(region_count));
    std::vector<std::vector<int32_t>> into_b_faces(static_cast<size_t>(region_count));
    for (int32_t g = 0; g < region_count; ++g) {
        if (plans[g].into_a) into_a_faces[g] = side_faces(g, false);
        if (plans[g].into_b) into_b_faces[g] = side_faces(g, true);
    }

    // Regions active at each sample.
    Lists active;
    active.start.assign(static_cast<size_t>(sample_count) + 1, 0);
    for (const RegionPlan& plan : plans)
        for (int32_t s = plan.first; s <= plan.last; ++s) active.start[s + 1] += is_measured(plan, s);
    for (int32_t s = 0; s < sample_count; ++s) active.start[s + 1] += active.start[s];
    active.items.resize(static_cast<size_t>(total));
    {
        std::vector<int64_t> next(active.start.begin(), active.start.end() - 1);
        for (int32_t g = 0; g < region_count; ++g)
            for (int32_t s = plans[g].first; s <= plans[g].last; ++s)
                if (is_measured(plans[g], s)) active.items[static_cast<size_t>(next[s]++)] = g;
    }

    // Closed meshes some region goes into: their topology, on their positions at the first sample needed.
    std::vector<int32_t> closed_first(meshes.size(), -1);
    for (const RegionPlan& plan : plans) {
        for (int side = 0; side < 2; ++side) {
            if (!(side == 0 ? plan.into_a : plan.into_b)) continue;
            int32_t& first = closed_first[side == 0 ? plan.mesh_a : plan.mesh_b];
            first = first < 0 ? plan.first : std::min(first, plan.first);
        }
    }
    std::vector<ClosedMeshTopology> topologies(meshes.size());
    for (size_t m = 0; m < meshes.size(); ++m) {
        if (closed_first[m] < 0) continue;
        std::vector<Vec3> points(static_cast<size_t>(meshes[m].vertex_count));
        for (int32_t v = 0; v < meshes[m].vertex_count; ++v) points[v] = point_at(meshes[m], blends[m][closed_first[m]], v);
        topologies[m] = build_closed_mesh_topology(meshes[m], points.data());
    }

    out.region.resize(static_cast<size_t>(total));
    out.sample.resize(static_cast<size_t>(total));
    out.penetration.assign(static_cast<size_t>(total), NOT_A_NUMBER);
    out.intersection_length.assign(static_cast<size_t>(total), 0.0);
    out.box_min.assign(3 * static_cast<size_t>(total), NOT_A_NUMBER);
    out.box_max.assign(3 * static_cast<size_t>(total), NOT_A_NUMBER);
    std::atomic<int64_t> evaluations{0};

    parallel_for(std::max(threads, 1), sample_count, [&](int32_t s) {
        if (active.start[s] == active.start[s + 1]) return;
        // The closed meshes this sample's regions go into, placed and refit.
        std::vector<std::vector<Vec3>> points(meshes.size());
        std::vector<ClosedSurface> surfaces(meshes.size());
        const auto surface_of = [&](int32_t m) -> const ClosedSurface& {
            if (points[m].empty() && meshes[m].vertex_count > 0) {
                points[m].resize(static_cast<size_t>(meshes[m].vertex_count));
                for (int32_t v = 0; v < meshes[m].vertex_count; ++v) points[m][v] = point_at(meshes[m], blends[m][s], v);
                surfaces[m].update(meshes[m], topologies[m], points[m].data());
            }
            return surfaces[m];
        };
        std::vector<std::array<Vec3, 3>> penetrating;
        int64_t evaluated = 0;
        for (int64_t k = active.start[s]; k < active.start[s + 1]; ++k) {
            const int32_t g = active.items[static_cast<size_t>(k)];
            const RegionPlan& plan = plans[g];
            const MeshView& mesh_a = meshes[plan.mesh_a];
            const MeshView& mesh_b = meshes[plan.mesh_b];
            const SampleBlend& blend_a = blends[plan.mesh_a][s];
            const SampleBlend& blend_b = blends[plan.mesh_b][s];
            const bool self = plan.mesh_a == plan.mesh_b;
            Box box;
            double length = 0.0;
            for (int64_t i = region_rows.start[g]; i < region_rows.start[g + 1]; ++i) {
                const int32_t r = region_rows.items[static_cast<size_t>(i)];
                const FaceIndex& fa = faces[plan.mesh_a];
                const FaceIndex& fb = faces[plan.mesh_b];
                for (int64_t ia = fa.triangle_begin(rows.face_a[r]); ia < fa.triangle_end(rows.face_a[r]); ++ia) {
                    const int32_t ta = fa.triangles[static_cast<size_t>(ia)];
                    const std::array<Vec3, 3> a = triangle_at(mesh_a, blend_a, ta);
                    for (int64_t ib = fb.triangle_begin(rows.face_b[r]); ib < fb.triangle_end(rows.face_b[r]); ++ib) {
                        const int32_t tb = fb.triangles[static_cast<size_t>(ib)];
                        const std::array<Vec3, 3> b = triangle_at(mesh_b, blend_b, tb);
                        if (boxes_apart(a, b)) continue;
                        const int shared = self ? shared_corners(mesh_a.triangle(ta), mesh_b.triangle(tb)) : 0;
                        if (shared >= 2) continue;
                        const IntersectionSegment segment = triangle_intersection_segment(a, b);
                        if (!segment.meets) continue;
                        const double piece = segment.length();
                        if (shared == 1 && !(piece > 0.0)) continue;
                        length += edge_share(segment) * piece;
                        box.add(segment.p);
                        box.add(segment.q);
                    }
                }
            }
            double penetration = NOT_A_NUMBER;
            for (int side = 0; side < 2; ++side) {
                if (!(side == 0 ? plan.into_a : plan.into_b)) continue;
                const int32_t into = side == 0 ? plan.mesh_a : plan.mesh_b;
                const int32_t from = side == 0 ? plan.mesh_b : plan.mesh_a;
                const std::vector<int32_t>& from_faces = side == 0 ? into_a_faces[g] : into_b_faces[g];
                penetrating.clear();
                for (int32_t face : from_faces) {
                    for (int64_t i = faces[from].triangle_begin(face); i < faces[from].triangle_end(face); ++i)
                        penetrating.push_back(triangle_at(meshes[from], blends[from][s], faces[from].triangles[static_cast<size_t>(i)]));
                }
                const InsideDepth depth = deepest_inside(surface_of(into), penetrating);
                evaluated += depth.evaluations;
                penetration = std::isnan(penetration) ? depth.depth : std::max(penetration, depth.depth);
                if (depth.any_inside) {
                    box.add(depth.inside_min);
                    box.add(depth.inside_max);
                }
            }
            const size_t at = static_cast<size_t>(output_row(plan, s));
            out.region[at] = g;
            out.sample[at] = s;
            out.penetration[at] = penetration;
            out.intersection_length[at] = length;
            if (box.any) {
                for (int k3 = 0; k3 < 3; ++k3) {
                    out.box_min[3 * at + k3] = box.lo[k3];
                    out.box_max[3 * at + k3] = box.hi[k3];
                }
            }
        }
        evaluations += evaluated;
    });
    out.depth_evaluations = evaluations.load();
    return out;
}

} // namespace usdksl
