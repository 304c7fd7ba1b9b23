/// @file primitive_distance.cpp
/// @brief Closest-point distances; every candidate configuration is tried so
///        degenerate shapes (parallel, zero length, zero area) need no branch.

#include "usdksl/geometry/primitive_distance.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <limits>

namespace usdksl {

double point_segment_distance_squared(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double length_squared = ab.squaredNorm();
    double s = 0.0;
    if (length_squared > 0.0) s = std::clamp((p - a).dot(ab) / length_squared, 0.0, 1.0);
    return (p - (a + s * ab)).squaredNorm();
}

double point_triangle_interior_distance_squared(const Vec3& p, const Vec3& a, const Vec3& b,
                                                const Vec3& c) {
    const Vec3 normal = (b - a).cross(c - a);
    const double normal_squared = normal.squaredNorm();
    if (!(normal_squared > 0.0)) return std::numeric_limits<double>::infinity();
    const Vec3 ap = p - a;
    const double along_normal = ap.dot(normal);
    const Vec3 projected = p - (along_normal / normal_squared) * normal;
    const bool inside = (b - a).cross(projected - a).dot(normal) >= 0.0 &&
                        (c - b).cross(projected - b).dot(normal) >= 0.0 &&
                        (a - c).cross(projected - c).dot(normal) >= 0.0;
    return inside ? along_normal * along_normal / normal_squared : std::numeric_limits<double>::infinity();
}

double point_triangle_distance_squared(const Vec3& p, const Vec3& a, const Vec3& b,
                                       const Vec3& c) {
    return std::min({point_segment_distance_squared(p, a, b),
                     point_segment_distance_squared(p, b, c),
                     point_segment_distance_squared(p, c, a),
                     point_triangle_interior_distance_squared(p, a, b, c)});
}

double segment_segment_interior_distance_squared(const Vec3& p, const Vec3& q, const Vec3& r,
                                                 const Vec3& s) {
    // The 2x2 normal equations of the closest points.
    const Vec3 d1 = q - p, d2 = s - r, w = p - r;
    const double a = d1.dot(d1), b = d1.dot(d2), c = d2.dot(d2);
    const double d = d1.dot(w), e = d2.dot(w);
    const double denominator = a * c - b * b;
    if (!(denominator > 0.0)) return std::numeric_limits<double>::infinity();
    const double u = (b * e - c * d) / denominator;
    const double v = (a * e - b * d) / denominator;
    if (!(u > 0.0 && u < 1.0 && v > 0.0 && v < 1.0)) return std::numeric_limits<double>::infinity();
    return ((p + u * d1) - (r + v * d2)).squaredNorm();
}

double segment_segment_distance_squared(const Vec3& p, const Vec3& q, const Vec3& r,
                                        const Vec3& s) {
    return std::min({point_segment_distance_squared(p, r, s),
                     point_segment_distance_squared(q, r, s),
                     point_segment_distance_squared(r, p, q),
                     point_segment_distance_squared(s, p, q),
                     segment_segment_interior_distance_squared(p, q, r, s)});
}

} // namespace usdksl
