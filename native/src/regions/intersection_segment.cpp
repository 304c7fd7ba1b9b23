/// @file intersection_segment.cpp
/// @brief Each triangle cut by the other's plane (exact side tests, then
///        interpolation), and the two cuts overlapped along their common line.

#include "usdksl/regions/intersection_segment.hpp"

#include "usdksl/geometry/exact_predicates.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace usdksl {
namespace {

/// The points of triangle `t` on the plane of `plane` (at most two for a
/// triangle that is not in that plane): its vertices on the plane and the
/// points where an edge crosses it. `side` are the exact signs.
struct PlaneCut {
    int count = 0;
    std::array<Vec3, 2> points;
};

PlaneCut cut_by_plane(const std::array<Vec3, 3>& t, const std::array<int, 3>& side, const Vec3& normal,
                      const Vec3& origin) {
    PlaneCut cut;
    for (int i = 0; i < 3; ++i) {
        if (side[i] == 0 && cut.count < 2) cut.points[cut.count++] = t[i];
    }
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        if (side[i] * side[j] >= 0 || cut.count >= 2) continue;
        const double di = normal.dot(t[i] - origin);
        const double dj = normal.dot(t[j] - origin);
        double w = di / (di - dj);
        if (!std::isfinite(w)) w = 0.5;  // both distances rounded to 0: the middle is as good as any
        w = std::min(1.0, std::max(0.0, w));
        cut.points[cut.count++] = t[i] + w * (t[j] - t[i]);
    }
    if (cut.count == 1) cut.points[1] = cut.points[0];
    return cut;
}

} // namespace

IntersectionSegment triangle_intersection_segment(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
    IntersectionSegment none;
    std::array<int, 3> side_a, side_b;
    for (int i = 0; i < 3; ++i) {
        side_a[i] = orient3d(b[0], b[1], b[2], a[i]);
        side_b[i] = orient3d(a[0], a[1], a[2], b[i]);
    }
    const auto apart = [](const std::array<int, 3>& s) {
        return (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0);
    };
    const auto in_plane = [](const std::array<int, 3>& s) { return s[0] == 0 && s[1] == 0 && s[2] == 0; };
    if (apart(side_a) || apart(side_b) || in_plane(side_a) || in_plane(side_b)) return none;

    const Vec3 normal_a = (a[1] - a[0]).cross(a[2] - a[0]);
    const Vec3 normal_b = (b[1] - b[0]).cross(b[2] - b[0]);
    const PlaneCut cut_a = cut_by_plane(a, side_a, normal_b, b[0]);
    const PlaneCut cut_b = cut_by_plane(b, side_b, normal_a, a[0]);
    if (cut_a.count == 0 || cut_b.count == 0) return none;

    // Both cuts lie on the line where the planes meet: overlap them along it.
    Vec3 direction = normal_a.cross(normal_b);
    if (!(direction.squaredNorm() > 0.0) || !std::isfinite(direction.squaredNorm())) {
        // Nearly parallel planes (the exact signs still say they cross): the
        // axis along which the four points spread most stands in for the line.
        Vec3 lo = cut_a.points[0], hi = lo;
        for (const Vec3& p : {cut_a.points[1], cut_b.points[0], cut_b.points[1]}) {
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        }
        int axis = 0;
        (hi - lo).maxCoeff(&axis);
        direction = Vec3::Unit(axis);
    }
    const auto along = [&](const Vec3& p) { return direction.dot(p); };
    const auto ordered = [&](const PlaneCut& cut) {
        return along(cut.points[0]) <= along(cut.points[1]) ? std::array<Vec3, 2>{cut.points[0], cut.points[1]}
                                                             : std::array<Vec3, 2>{cut.points[1], cut.points[0]};
    };
    const std::array<Vec3, 2> sa = ordered(cut_a), sb = ordered(cut_b);
    const Vec3& start = along(sa[0]) >= along(sb[0]) ? sa[0] : sb[0];
    const Vec3& end = along(sa[1]) <= along(sb[1]) ? sa[1] : sb[1];
    if (along(start) > along(end)) return none;
    const auto zeros = [](const std::array<int, 3>& s) { return (s[0] == 0) + (s[1] == 0) + (s[2] == 0); };
    IntersectionSegment segment;
    segment.meets = true;
    segment.along_edge_of_a = zeros(side_a) == 2;
    segment.along_edge_of_b = zeros(side_b) == 2;
    segment.p = start;
    segment.q = end;
    return segment;
}

} // namespace usdksl
