/// @file inside_depth.cpp
/// @brief Best-first branch and bound over midpoint subdivisions.

#include "usdksl/regions/inside_depth.hpp"

#include "usdksl/geometry/primitive_distance.hpp"

#include <algorithm>
#include <cmath>
#include <queue>

namespace usdksl {
namespace {

struct Piece {
    std::array<Vec3, 3> corners;
    /// Upper bound of f on the piece, less the accuracy of its triangle:
    /// the piece can beat the best depth only while this exceeds it.
    double key;
    double accuracy;
    int32_t nearest;  // surface triangle closest to the centroid (a hint for the children)
    int32_t splits;
    int64_t order;    // ties broken by creation order, for determinism
};

struct ByKey {
    bool operator()(const Piece& x, const Piece& y) const {
        return x.key < y.key || (x.key == y.key && x.order > y.order);
    }
};

class Search {
public:
    explicit Search(const ClosedSurface& surface) : surface_(surface) {}

    /// f at p (signed distance), counted, recorded when inside.
    double evaluate(const Vec3& p, int32_t hint, int32_t* nearest) {
        const double g = surface_.signed_distance(p, nearest, hint);
        ++result.evaluations;
        if (g > 0.0) {
            if (!result.any_inside) {
                result.any_inside = true;
                result.inside_min = result.inside_max = p;
            } else {
                result.inside_min = result.inside_min.cwiseMin(p);
                result.inside_max = result.inside_max.cwiseMax(p);
            }
            if (g > result.depth) {
                result.depth = g;
                result.deepest = p;
            }
        }
        return g;
    }

    /// Bounds a piece and queues it when it could still beat the best depth.
    /// `crosses_known`: whether the piece meets the surface (1) or not (0),
    /// when already known (-1 otherwise).
    void consider(const std::array<Vec3, 3>& corners, double accuracy, int32_t hint, int32_t splits,
                  int crosses_known = -1) {
        const Vec3 centroid = (corners[0] + corners[1] + corners[2]) / 3.0;
        int32_t nearest = -1;
        const double g = evaluate(centroid, hint, &nearest);
        double reach = 0.0;
        for (const Vec3& v : corners) reach = std::max(reach, (v - centroid).norm());
        double bound = g + reach;
        if (nearest >= 0) {
            const std::array<Vec3, 3> s = surface_.triangle(nearest);
            double farthest = 0.0;
            for (const Vec3& v : corners)
                farthest = std::max(farthest, point_triangle_distance_squared(v, s[0], s[1], s[2]));
            bound = std::min(bound, std::sqrt(farthest));
        }
        const double key = bound - accuracy;
        if (!(key > result.depth) || splits >= DEPTH_MAX_SPLITS) return;
        // A piece that meets no surface triangle lies wholly on its centroid's side: with the centroid
        // outside, f is 0 on all of it (asked only here, where the bound alone keeps the piece).
        if (!(g > 0.0) && !(crosses_known >= 0 ? crosses_known == 1 : surface_.meets(corners))) return;
        queue_.push({corners, key, accuracy, nearest, splits, next_order_++});
    }

    void run() {
        while (!queue_.empty() && queue_.top().key > result.depth) {
            const Piece piece = queue_.top();
            queue_.pop();
            const std::array<Vec3, 3>& c = piece.corners;
            const Vec3 m01 = 0.5 * (c[0] + c[1]), m12 = 0.5 * (c[1] + c[2]), m20 = 0.5 * (c[2] + c[0]);
            const int32_t splits = piece.splits + 1;
            consider({c[0], m01, m20}, piece.accuracy, piece.nearest, splits);
            consider({m01, c[1], m12}, piece.accuracy, piece.nearest, splits);
            consider({m20, m12, c[2]}, piece.accuracy, piece.nearest, splits);
            consider({m12, m20, m01}, piece.accuracy, piece.nearest, splits);
        }
    }

    InsideDepth result;

private:
    const ClosedSurface& surface_;
    std::priority_queue<Piece, std::vector<Piece>, ByKey> queue_;
    int64_t next_order_ = 0;
};

} // namespace

InsideDepth deepest_inside(const ClosedSurface& surface, const std::vector<std::array<Vec3, 3>>& triangles) {
    Search search(surface);
    if (surface.empty()) return search.result;
    // Corners first: most of the deepest points of flat pieces are corners,
    // and a good early depth prunes everything after.
    std::vector<char> crosses(triangles.size(), 0);
    for (size_t i = 0; i < triangles.size(); ++i) {
        const std::array<Vec3, 3>& t = triangles[i];
        if (!surface.meets(t)) continue;
        crosses[i] = 1;
        int32_t hint = -1;
        for (const Vec3& v : t) search.evaluate(v, hint, &hint);
    }
    for (size_t i = 0; i < triangles.size(); ++i) {
        const std::array<Vec3, 3>& t = triangles[i];
        const double longest = std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
        search.consider(t, DEPTH_RELATIVE_ACCURACY * longest, -1, 0, crosses[i]);
    }
    search.run();
    return search.result;
}

} // namespace usdksl
