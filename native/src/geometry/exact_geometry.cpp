/// @file exact_geometry.cpp
/// @brief Closed point/segment/triangle incidence from exact orientations.
///
/// Coplanar configurations are decided in a coordinate plane: a projection
/// that drops axis k is a bijection on any plane whose normal has a nonzero
/// k component, and dropping coordinates is exact, so the 2-D answer equals
/// the 3-D one there. When no such single projection is known (degenerate
/// input) all three projections must agree, which is still exact because at
/// least one of them is injective on the common line or plane.

#include "usdksl/geometry/exact_geometry.hpp"

#include "usdksl/geometry/exact_predicates.hpp"

#include <algorithm>

namespace usdksl {
namespace {

bool within_box_2d(const Point2& p, const Point2& a, const Point2& b) {
    return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
           p.y <= std::max(a.y, b.y);
}

bool segments_intersect_2d(const Point2& p, const Point2& q, const Point2& r, const Point2& s) {
    const int o1 = orient2d(p, q, r);
    const int o2 = orient2d(p, q, s);
    const int o3 = orient2d(r, s, p);
    const int o4 = orient2d(r, s, q);
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;
    if (o1 == 0 && within_box_2d(r, p, q)) return true;
    if (o2 == 0 && within_box_2d(s, p, q)) return true;
    if (o3 == 0 && within_box_2d(p, r, s)) return true;
    if (o4 == 0 && within_box_2d(q, r, s)) return true;
    return false;
}

/// Closed 2-D triangle containment, zero-area triangles included.
bool point_in_triangle_2d(const Point2& p, const Point2& a, const Point2& b, const Point2& c) {
    const int orientation = orient2d(a, b, c);
    if (orientation == 0) {
        return segments_intersect_2d(p, p, a, b) || segments_intersect_2d(p, p, b, c) ||
               segments_intersect_2d(p, p, c, a);
    }
    const int s1 = orient2d(a, b, p), s2 = orient2d(b, c, p), s3 = orient2d(c, a, p);
    return s1 * orientation >= 0 && s2 * orientation >= 0 && s3 * orientation >= 0;
}

/// An axis whose removal keeps triangle abc non-degenerate, or -1.
int injective_drop_axis(const Vec3& a, const Vec3& b, const Vec3& c) {
    for (int axis = 2; axis >= 0; --axis) {
        if (orient2d(project_dropping_axis(a, axis), project_dropping_axis(b, axis),
                     project_dropping_axis(c, axis)) != 0)
            return axis;
    }
    return -1;
}

} // namespace

bool triangle_is_degenerate(const Vec3& a, const Vec3& b, const Vec3& c) {
    return injective_drop_axis(a, b, c) < 0;
}

bool segments_intersect(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) {
    if (orient3d(p, q, r, s) != 0) return false;
    for (int axis = 0; axis < 3; ++axis) {
        if (!segments_intersect_2d(project_dropping_axis(p, axis), project_dropping_axis(q, axis),
                                   project_dropping_axis(r, axis), project_dropping_axis(s, axis)))
            return false;
    }
    return true;
}

bool point_in_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const int axis = injective_drop_axis(a, b, c);
    if (axis < 0) {
        return segments_intersect(p, p, a, b) || segments_intersect(p, p, b, c) ||
               segments_intersect(p, p, c, a);
    }
    if (orient3d(a, b, c, p) != 0) return false;
    return point_in_triangle_2d(project_dropping_axis(p, axis), project_dropping_axis(a, axis),
                                project_dropping_axis(b, axis), project_dropping_axis(c, axis));
}

bool segment_intersects_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                                 const Vec3& c) {
    const int axis = injective_drop_axis(a, b, c);
    if (axis < 0) {
        return segments_intersect(p, q, a, b) || segments_intersect(p, q, b, c) ||
               segments_intersect(p, q, c, a);
    }
    const int side_p = orient3d(a, b, c, p);
    const int side_q = orient3d(a, b, c, q);
    if (side_p * side_q > 0) return false;
    if (side_p == 0 && side_q == 0) {
        const Point2 p2 = project_dropping_axis(p, axis), q2 = project_dropping_axis(q, axis);
        const Point2 a2 = project_dropping_axis(a, axis), b2 = project_dropping_axis(b, axis),
                     c2 = project_dropping_axis(c, axis);
        return point_in_triangle_2d(p2, a2, b2, c2) || point_in_triangle_2d(q2, a2, b2, c2) ||
               segments_intersect_2d(p2, q2, a2, b2) || segments_intersect_2d(p2, q2, b2, c2) ||
               segments_intersect_2d(p2, q2, c2, a2);
    }
    // The segment meets the plane in exactly one point; it lies in the closed
    // triangle iff the line pq sees the three edges with one orientation.
    const int s1 = orient3d(p, q, a, b);
    const int s2 = orient3d(p, q, b, c);
    const int s3 = orient3d(p, q, c, a);
    return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

} // namespace usdksl
