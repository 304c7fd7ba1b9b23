/// @file closest_feature.cpp
/// @brief Voronoi regions of a triangle's features, tested corner, edge, then interior.

#include "usdksl/regions/closest_feature.hpp"

#include <algorithm>

namespace usdksl {

ClosestOnTriangle closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    ClosestOnTriangle out;
    const auto finish = [&](const Vec3& point, TriangleFeature feature) {
        out.point = point;
        out.feature = feature;
        out.distance_squared = (p - point).squaredNorm();
        return out;
    };
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0.0 && d2 <= 0.0) return finish(a, TriangleFeature::Corner0);
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0.0 && d4 <= d3) return finish(b, TriangleFeature::Corner1);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double v = d1 / (d1 - d3);
        return finish(a + v * ab, TriangleFeature::Edge01);
    }
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0.0 && d5 <= d6) return finish(c, TriangleFeature::Corner2);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double w = d2 / (d2 - d6);
        return finish(a + w * ac, TriangleFeature::Edge20);
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return finish(b + w * (c - b), TriangleFeature::Edge12);
    }
    const double sum = va + vb + vc;
    if (!(sum > 0.0)) {
        // A zero-area triangle that no corner or edge test claimed (rounding):
        // the nearest of its three edges stands for it.
        const auto on_edge = [&](const Vec3& s, const Vec3& e) {
            const Vec3 d = e - s;
            const double len2 = d.squaredNorm();
            const double t = len2 > 0.0 ? std::min(1.0, std::max(0.0, d.dot(p - s) / len2)) : 0.0;
            return Vec3(s + t * d);
        };
        const Vec3 q0 = on_edge(a, b), q1 = on_edge(b, c), q2 = on_edge(c, a);
        const double e0 = (p - q0).squaredNorm(), e1 = (p - q1).squaredNorm(), e2 = (p - q2).squaredNorm();
        if (e0 <= e1 && e0 <= e2) return finish(q0, TriangleFeature::Edge01);
        if (e1 <= e2) return finish(q1, TriangleFeature::Edge12);
        return finish(q2, TriangleFeature::Edge20);
    }
    const double v = vb / sum, w = vc / sum;
    return finish(a + ab * v + ac * w, TriangleFeature::Interior);
}

} // namespace usdksl
