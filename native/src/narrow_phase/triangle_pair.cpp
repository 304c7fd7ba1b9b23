/// @file triangle_pair.cpp
/// @brief Triangle pair = 6 vertex-face + 9 edge-edge primitive pairs; a swept
///        box filter runs before each primitive CCD, and each CCD only looks
///        for contacts earlier than the best one found so far.

#include "usdksl/narrow_phase/triangle_pair.hpp"

#include "usdksl/ccd/ccd_constants.hpp"
#include "usdksl/ccd/edge_edge_ccd.hpp"
#include "usdksl/geometry/exact_geometry.hpp"
#include "usdksl/geometry/primitive_distance.hpp"
#include "usdksl/geometry/triangle_triangle_static.hpp"
#include "usdksl/ccd/vertex_face_ccd.hpp"
#include "usdksl/narrow_phase/vertex_sharing.hpp"

#include <algorithm>
#include <cmath>

namespace usdksl {
namespace {

struct Box {
    Vec3 lo;
    Vec3 hi;
    Box merged(const Box& other) const { return {lo.cwiseMin(other.lo), hi.cwiseMax(other.hi)}; }
};

/// Per-axis gap test; `reach` already includes thickness and rounding slack.
bool boxes_within(const Box& a, const Box& b, double reach) {
    for (int k = 0; k < 3; ++k) {
        if (a.lo[k] > b.hi[k] + reach || b.lo[k] > a.hi[k] + reach) return false;
    }
    return true;
}

/// Largest absolute coordinate of a set of boxes (for rounding slack).
double magnitude_of(const Box* boxes, int count) {
    double magnitude = 0.0;
    for (int i = 0; i < count; ++i)
        magnitude = std::max({magnitude, boxes[i].lo.cwiseAbs().maxCoeff(), boxes[i].hi.cwiseAbs().maxCoeff()});
    return magnitude;
}

} // namespace

bool edge_pierces_triangle(const Triangle& ids_a, const std::array<Vec3, 3>& a, const Triangle& ids_b,
                           const std::array<Vec3, 3>& b) {
    for (int i = 0; i < 3; ++i) {
        const int i1 = (i + 1) % 3;
        if (!triangle_holds_vertex(ids_b, ids_a[i]) && !triangle_holds_vertex(ids_b, ids_a[i1]) &&
            segment_intersects_triangle(a[i], a[i1], b[0], b[1], b[2]))
            return true;
    }
    return false;
}

namespace {

/// Four points of a primitive pair at the step's start and end, in the
/// argument order of vertex_face_ccd / edge_edge_ccd.
struct PrimitivePoints {
    bool edge_edge;
    std::array<Vec3, 4> s, e;
};

/// The primitive pairs of triangle_pair_ccd in their fixed order, each asked
/// of `query(index, points, t_max, reused)` (index 0-2: vertices of A
/// against B, 3-5: vertices of B against A, 6-14: edge i of A against edge j
/// of B at 6 + 3 i + j), which answers as vertex_face_ccd / edge_edge_ccd
/// would.
template <class Query>
TrianglePairContact search_triangle_pair(const MovingTriangle& a, const MovingTriangle& b, bool same_mesh,
                                         const CCDSettings& settings, Query&& query) {
    TrianglePairContact contact;
    // Swept boxes of the six vertices: a linear trajectory stays inside the box
    // of its two end positions.
    Box swept_a[3], swept_b[3];
    for (int i = 0; i < 3; ++i) {
        swept_a[i] = {a.t0[i].cwiseMin(a.t1[i]), a.t0[i].cwiseMax(a.t1[i])};
        swept_b[i] = {b.t0[i].cwiseMin(b.t1[i]), b.t0[i].cwiseMax(b.t1[i])};
    }
    const Box triangle_a = swept_a[0].merged(swept_a[1]).merged(swept_a[2]);
    const Box triangle_b = swept_b[0].merged(swept_b[1]).merged(swept_b[2]);
    const Box both[2] = {triangle_a, triangle_b};
    const double reach = std::max(settings.thickness, 0.0) +
                         CCD_CORNER_ERROR_FACTOR * magnitude_of(both, 2) + CCD_MIN_ABSOLUTE_ERROR;
    if (!boxes_within(triangle_a, triangle_b, reach)) return contact;

    double best_toi = 1.0;
    auto consider = [&](const CCDResult& result, ContactFeature feature) {
        ++contact.queries;
        if (!result.hit) return;
        contact.undecided = contact.undecided || result.undecided;
        if (!contact.hit || result.toi < best_toi) {
            contact.hit = true;
            contact.toi = result.toi;
            contact.feature = feature;
            best_toi = result.toi;
        }
    };

    auto ask = [&](int index, const PrimitivePoints& points) {
        bool reused = false;
        const CCDResult result = query(index, points, best_toi, reused);
        contact.reused_queries += reused ? 1 : 0;
        return result;
    };

    // Vertices of A against triangle B.
    for (int i = 0; i < 3 && best_toi > 0.0; ++i) {
        if (same_mesh && triangle_holds_vertex(b.ids, a.ids[i])) continue;
        if (!boxes_within(swept_a[i], triangle_b, reach)) continue;
        consider(ask(i, {false, {a.t0[i], b.t0[0], b.t0[1], b.t0[2]}, {a.t1[i], b.t1[0], b.t1[1], b.t1[2]}}),
                 ContactFeature::VertexFace);
    }
    // Vertices of B against triangle A.
    for (int j = 0; j < 3 && best_toi > 0.0; ++j) {
        if (same_mesh && triangle_holds_vertex(a.ids, b.ids[j])) continue;
        if (!boxes_within(swept_b[j], triangle_a, reach)) continue;
        consider(ask(3 + j, {false, {b.t0[j], a.t0[0], a.t0[1], a.t0[2]}, {b.t1[j], a.t1[0], a.t1[1], a.t1[2]}}),
                 ContactFeature::FaceVertex);
    }
    // Edges of A against edges of B.
    for (int i = 0; i < 3 && best_toi > 0.0; ++i) {
        const int i1 = (i + 1) % 3;
        const Box edge_a = swept_a[i].merged(swept_a[i1]);
        if (!boxes_within(edge_a, triangle_b, reach)) continue;
        for (int j = 0; j < 3 && best_toi > 0.0; ++j) {
            const int j1 = (j + 1) % 3;
            if (same_mesh && edges_share_vertex(a.ids[i], a.ids[i1], b.ids[j], b.ids[j1])) continue;
            if (!boxes_within(edge_a, swept_b[j].merged(swept_b[j1]), reach)) continue;
            consider(ask(6 + 3 * i + j,
                         {true, {a.t0[i], a.t0[i1], b.t0[j], b.t0[j1]}, {a.t1[i], a.t1[i1], b.t1[j], b.t1[j1]}}),
                     ContactFeature::EdgeEdge);
        }
    }
    if (!contact.hit) contact.toi = 1.0;
    return contact;
}

/// vertex_face_ccd / edge_edge_ccd of `p` up to t_max, the vertex-face ones
/// through `memo` when given, filling `fork` when given.
CCDResult primitive_ccd(const PrimitivePoints& p, const CCDSettings& settings, double t_max, VertexFaceMemo* memo,
                        bool& reused, FinerSearchFork* fork) {
    const auto& s = p.s;
    const auto& e = p.e;
    if (p.edge_edge) {
        return fork ? edge_edge_ccd(s[0], s[1], s[2], s[3], e[0], e[1], e[2], e[3], settings, t_max, *fork)
                    : edge_edge_ccd(s[0], s[1], s[2], s[3], e[0], e[1], e[2], e[3], settings, t_max);
    }
    if (memo) return memo->vertex_face_ccd(s[0], s[1], s[2], s[3], e[0], e[1], e[2], e[3], settings, t_max, reused, fork);
    return fork ? vertex_face_ccd(s[0], s[1], s[2], s[3], e[0], e[1], e[2], e[3], settings, t_max, *fork)
                : vertex_face_ccd(s[0], s[1], s[2], s[3], e[0], e[1], e[2], e[3], settings, t_max);
}

/// The finer search of `p` from where `fork` parted.
CCDResult resumed_primitive_ccd(const PrimitivePoints& p, const CCDSettings& finer_settings, double t_max,
                                const FinerSearchFork& fork) {
    const auto& s = p.s;
    const auto& e = p.e;
    return p.edge_edge ? edge_edge_ccd_resumed(s[0], s[1], s[2], s[3], e[0], e[1], e[2], e[3], finer_settings, t_max, fork)
                       : vertex_face_ccd_resumed(s[0], s[1], s[2], s[3], e[0], e[1], e[2], e[3], finer_settings, t_max, fork);
}

} // namespace

TrianglePairContact triangle_pair_ccd(const MovingTriangle& a, const MovingTriangle& b, bool same_mesh,
                                      const CCDSettings& settings, VertexFaceMemo* memo, FinerReplay* replay) {
    if (replay) replay->start(settings);
    return search_triangle_pair(a, b, same_mesh, settings,
                                [&](int index, const PrimitivePoints& points, double t_max, bool& reused) {
                                    FinerSearchFork* fork = replay ? replay->fork_for(index, t_max) : nullptr;
                                    const CCDResult result = primitive_ccd(points, settings, t_max, memo, reused, fork);
                                    if (replay) replay->keep(index, result, reused);
                                    return result;
                                });
}

TrianglePairContact finer_triangle_pair_ccd(const MovingTriangle& a, const MovingTriangle& b, bool same_mesh,
                                            const CCDSettings& finer_settings, const FinerReplay& replay,
                                            VertexFaceMemo* memo) {
    return search_triangle_pair(a, b, same_mesh, finer_settings,
                                [&](int index, const PrimitivePoints& points, double t_max, bool& reused) {
                                    const FinerReplay::Record* kept = replay.record_for(index, t_max, finer_settings);
                                    if (kept && !kept->fork.diverged) return kept->result;
                                    const auto& s = points.s;
                                    const auto& e = points.e;
                                    const bool memoized = memo && !points.edge_edge;
                                    if (memoized) {
                                        const CCDResult* known = memo->find(s[0], s[1], s[2], s[3], e[0], e[1], e[2],
                                                                            e[3], finer_settings, t_max);
                                        if (known) {
                                            reused = true;
                                            return *known;
                                        }
                                    }
                                    const CCDResult result =
                                        kept ? resumed_primitive_ccd(points, finer_settings, t_max, kept->fork)
                                             : primitive_ccd(points, finer_settings, t_max, nullptr, reused, nullptr);
                                    if (memoized && result.iterations >= FINER_MEMO_MIN_ITERATIONS)
                                        memo->keep(s[0], s[1], s[2], s[3], e[0], e[1], e[2], e[3], finer_settings,
                                                   t_max, result);
                                    return result;
                                });
}

void FinerReplay::start(const CCDSettings& settings) {
    settings_ = settings;
    for (Record& record : records_) record.asked = false;
}

FinerSearchFork* FinerReplay::fork_for(int index, double t_max) {
    Record& record = records_[static_cast<size_t>(index)];
    record.asked = true;
    record.t_max = t_max;
    record.fork.finer_tolerance = finer_tolerance_;
    record.fork.diverged = false;
    return &record.fork;
}

void FinerReplay::keep(int index, const CCDResult& result, bool reused) {
    Record& record = records_[static_cast<size_t>(index)];
    record.result = result;
    // A memo answer comes without a fork: its finer answer is not known.
    record.known = !reused;
}

const FinerReplay::Record* FinerReplay::record_for(int index, double t_max, const CCDSettings& finer) const {
    const Record& record = records_[static_cast<size_t>(index)];
    if (!record.asked || !record.known || record.t_max != t_max) return nullptr;
    if (finer.tolerance != finer_tolerance_ || finer.thickness != settings_.thickness ||
        finer.max_iterations != settings_.max_iterations)
        return nullptr;
    return &record;
}

bool triangle_pair_intersect_static(const Triangle& ids_a, const std::array<Vec3, 3>& a,
                                    const Triangle& ids_b, const std::array<Vec3, 3>& b,
                                    bool same_mesh, double thickness) {
    bool any_shared = false;
    if (same_mesh) {
        for (int i = 0; i < 3; ++i) any_shared = any_shared || triangle_holds_vertex(ids_b, ids_a[i]);
    }
    if (!any_shared) return triangles_intersect_static(a, b, thickness);

    thickness = std::max(thickness, 0.0);
    Box box_a{a[0], a[0]}, box_b{b[0], b[0]};
    for (int i = 1; i < 3; ++i) {
        box_a = box_a.merged(Box{a[i], a[i]});
        box_b = box_b.merged(Box{b[i], b[i]});
    }
    const Box both[2] = {box_a, box_b};
    const double reach = thickness + STATIC_DISTANCE_RELATIVE_SLACK * magnitude_of(both, 2);
    if (!boxes_within(box_a, box_b, reach)) return false;
    const double reach_squared = reach * reach;
    const bool use_distance = thickness > 0.0;

    for (int i = 0; i < 3; ++i) {
        if (!triangle_holds_vertex(ids_b, ids_a[i])) {
            if (use_distance ? point_triangle_distance_squared(a[i], b[0], b[1], b[2]) <= reach_squared
                             : point_in_triangle(a[i], b[0], b[1], b[2]))
                return true;
        }
        if (!triangle_holds_vertex(ids_a, ids_b[i])) {
            if (use_distance ? point_triangle_distance_squared(b[i], a[0], a[1], a[2]) <= reach_squared
                             : point_in_triangle(b[i], a[0], a[1], a[2]))
                return true;
        }
    }
    if (edge_pierces_triangle(ids_a, a, ids_b, b) || edge_pierces_triangle(ids_b, b, ids_a, a)) return true;
    for (int i = 0; i < 3; ++i) {
        const int i1 = (i + 1) % 3;
        for (int j = 0; j < 3; ++j) {
            const int j1 = (j + 1) % 3;
            if (edges_share_vertex(ids_a[i], ids_a[i1], ids_b[j], ids_b[j1])) continue;
            if (use_distance
                    ? segment_segment_distance_squared(a[i], a[i1], b[j], b[j1]) <= reach_squared
                    : segments_intersect(a[i], a[i1], b[j], b[j1]))
                return true;
        }
    }
    return false;
}

} // namespace usdksl
