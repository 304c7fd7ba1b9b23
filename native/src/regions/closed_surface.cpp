/// @file closed_surface.cpp
/// @brief Edges matched by sorting, boxes refit bottom-up, nearest-first
///        descent for the closest point, and pseudonormals on demand.

#include "usdksl/regions/closed_surface.hpp"

#include "usdksl/geometry/triangle_triangle_static.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace usdksl {
namespace {

double box_distance_squared(const Vec3& p, const Vec3& lo, const Vec3& hi) {
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double d = p[k] < lo[k] ? lo[k] - p[k] : (p[k] > hi[k] ? p[k] - hi[k] : 0.0);
        sum += d * d;
    }
    return sum;
}

/// Angle (radians) between u and v, robust for small and obtuse angles.
double angle_between(const Vec3& u, const Vec3& v) {
    return std::atan2(u.cross(v).norm(), u.dot(v));
}

/// Multiple of the largest coordinate magnitude m times (|e1| |e2| + (|e1| +
/// |e2|) |offset|) beyond which a floating-point side-of-plane value cannot
/// have the wrong sign: its rounding error is below about 20 units of
/// roundoff (2e-15) times that, so 1e-12 leaves a wide margin.
constexpr double PLANE_SIDE_SLACK = 1e-12;

/// True when every corner of `t` lies strictly on one side of the plane of
/// `s` by more than rounding can explain: the two cannot meet. A filter in
/// front of the exact test, which decides every other case.
bool plainly_apart(const std::array<Vec3, 3>& t, const std::array<Vec3, 3>& s) {
    const Vec3 e1 = s[1] - s[0], e2 = s[2] - s[0];
    const Vec3 normal = e1.cross(e2);
    double magnitude = 0.0;
    for (int i = 0; i < 3; ++i)
        magnitude = std::max({magnitude, t[i].cwiseAbs().maxCoeff(), s[i].cwiseAbs().maxCoeff()});
    const double l1 = e1.norm(), l2 = e2.norm();
    int above = 0, below = 0;
    for (const Vec3& p : t) {
        const Vec3 offset = p - s[0];
        const double side = normal.dot(offset);
        const double slack = PLANE_SIDE_SLACK * magnitude * (l1 * l2 + (l1 + l2) * offset.norm());
        above += side > slack;
        below += side < -slack;
    }
    return above == 3 || below == 3;
}

/// Deepest the descent goes: a tree over 2^31 triangles is no deeper than this
/// with a median split.
constexpr int TRAVERSAL_STACK = 128;

} // namespace

ClosedMeshTopology build_closed_mesh_topology(const MeshView& mesh, const Vec3* points) {
    ClosedMeshTopology topology;
    const int32_t count = mesh.triangle_count;
    std::vector<Vec3> centroids(static_cast<size_t>(count));
    for (int32_t t = 0; t < count; ++t) {
        const Triangle ids = mesh.triangle(t);
        centroids[t] = (points[ids[0]] + points[ids[1]] + points[ids[2]]) / 3.0;
    }
    topology.tree = build_bvh_topology(centroids);

    // Directed edges sorted by (from, to): the reverse of an edge is found by
    // binary search.
    struct Directed {
        uint64_t key;
        int32_t corner;  // 3 * triangle + corner
    };
    const uint64_t n = static_cast<uint64_t>(std::max(mesh.vertex_count, 1));
    std::vector<Directed> edges;
    edges.reserve(3 * static_cast<size_t>(count));
    for (int32_t t = 0; t < count; ++t) {
        const Triangle ids = mesh.triangle(t);
        for (int i = 0; i < 3; ++i)
            edges.push_back({static_cast<uint64_t>(ids[i]) * n + static_cast<uint64_t>(ids[(i + 1) % 3]), 3 * t + i});
    }
    std::sort(edges.begin(), edges.end(), [](const Directed& x, const Directed& y) {
        return x.key < y.key || (x.key == y.key && x.corner < y.corner);
    });
    topology.neighbour.assign(static_cast<size_t>(count), {-1, -1, -1});
    for (int32_t t = 0; t < count; ++t) {
        const Triangle ids = mesh.triangle(t);
        for (int i = 0; i < 3; ++i) {
            const uint64_t reverse = static_cast<uint64_t>(ids[(i + 1) % 3]) * n + static_cast<uint64_t>(ids[i]);
            const auto found = std::lower_bound(edges.begin(), edges.end(), reverse,
                                                [](const Directed& e, uint64_t key) { return e.key < key; });
            if (found != edges.end() && found->key == reverse) topology.neighbour[t][i] = found->corner / 3;
        }
    }

    topology.vertex_start.assign(static_cast<size_t>(mesh.vertex_count) + 1, 0);
    for (int32_t t = 0; t < count; ++t)
        for (int32_t v : mesh.triangle(t)) ++topology.vertex_start[static_cast<size_t>(v) + 1];
    for (int32_t v = 0; v < mesh.vertex_count; ++v) topology.vertex_start[v + 1] += topology.vertex_start[v];
    topology.vertex_triangles.resize(static_cast<size_t>(topology.vertex_start[mesh.vertex_count]));
    std::vector<int64_t> next(topology.vertex_start.begin(), topology.vertex_start.end() - 1);
    for (int32_t t = 0; t < count; ++t) {
        const Triangle ids = mesh.triangle(t);
        for (int i = 0; i < 3; ++i) {
            // a vertex used twice by one (degenerate) triangle is listed once per use
            topology.vertex_triangles[static_cast<size_t>(next[ids[i]]++)] = t;
        }
    }
    return topology;
}

void ClosedSurface::update(const MeshView& mesh, const ClosedMeshTopology& topology, const Vec3* points) {
    mesh_ = &mesh;
    topology_ = &topology;
    points_ = points;
    const BvhTopology& tree = topology.tree;
    const int32_t nodes = tree.node_count();
    lower_.resize(static_cast<size_t>(nodes));
    upper_.resize(static_cast<size_t>(nodes));
    // Children always follow their parent in the node order.
    for (int32_t node = nodes - 1; node >= 0; --node) {
        if (tree.is_leaf(node)) {
            const std::array<Vec3, 3> t = triangle(tree.triangle[node]);
            lower_[node] = t[0].cwiseMin(t[1]).cwiseMin(t[2]);
            upper_[node] = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
        } else {
            lower_[node] = lower_[tree.left[node]].cwiseMin(lower_[tree.right[node]]);
            upper_[node] = upper_[tree.left[node]].cwiseMax(upper_[tree.right[node]]);
        }
    }
    // Six times the enclosed volume, about the centre of the boxes (less rounding than about the origin).
    const Vec3 centre = nodes > 0 ? Vec3(0.5 * (lower_[0] + upper_[0])) : Vec3::Zero();
    double volume = 0.0;
    for (int32_t t = 0; t < mesh.triangle_count; ++t) {
        const std::array<Vec3, 3> p = triangle(t);
        volume += (p[0] - centre).dot((p[1] - centre).cross(p[2] - centre));
    }
    orientation_ = volume < 0.0 ? -1.0 : 1.0;
}

Vec3 ClosedSurface::unit_normal(int32_t tri) const {
    const std::array<Vec3, 3> t = triangle(tri);
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
    const double length = n.norm();
    return length > 0.0 ? Vec3(n / length) : Vec3::Zero();
}

Vec3 ClosedSurface::pseudonormal(int32_t tri, TriangleFeature feature) const {
    Vec3 n = Vec3::Zero();
    switch (feature) {
    case TriangleFeature::Interior:
        n = unit_normal(tri);
        break;
    case TriangleFeature::Edge01:
    case TriangleFeature::Edge12:
    case TriangleFeature::Edge20: {
        const int edge = static_cast<int>(feature) - static_cast<int>(TriangleFeature::Edge01);
        n = unit_normal(tri);
        const int32_t across = topology_->neighbour[tri][edge];
        if (across >= 0) n += unit_normal(across);
        break;
    }
    default: {
        const int corner = static_cast<int>(feature) - static_cast<int>(TriangleFeature::Corner0);
        const int32_t vertex = mesh_->triangle(tri)[corner];
        const Vec3& p = points_[vertex];
        for (int64_t i = topology_->vertex_start[vertex]; i < topology_->vertex_start[vertex + 1]; ++i) {
            const int32_t around = topology_->vertex_triangles[static_cast<size_t>(i)];
            const Triangle ids = mesh_->triangle(around);
            const int at = ids[0] == vertex ? 0 : (ids[1] == vertex ? 1 : 2);
            const Vec3 u = points_[ids[(at + 1) % 3]] - p, v = points_[ids[(at + 2) % 3]] - p;
            n += angle_between(u, v) * unit_normal(around);
        }
        break;
    }
    }
    return orientation_ * n;
}

ClosedSurface::Closest ClosedSurface::closest(const Vec3& p, int32_t hint) const {
    Closest best;
    best.on.distance_squared = std::numeric_limits<double>::infinity();
    if (empty()) return best;
    const BvhTopology& tree = topology_->tree;
    const auto try_triangle = [&](int32_t tri) {
        const std::array<Vec3, 3> t = triangle(tri);
        const ClosestOnTriangle on = closest_on_triangle(p, t[0], t[1], t[2]);
        if (on.distance_squared < best.on.distance_squared ||
            (on.distance_squared == best.on.distance_squared && tri < best.triangle)) {
            best.on = on;
            best.triangle = tri;
        }
    };
    if (hint >= 0 && hint < mesh_->triangle_count) try_triangle(hint);
    int32_t stack[TRAVERSAL_STACK];
    double stack_distance[TRAVERSAL_STACK];
    int top = 0;
    stack[top] = 0;
    stack_distance[top++] = box_distance_squared(p, lower_[0], upper_[0]);
    while (top > 0) {
        --top;
        const int32_t node = stack[top];
        if (stack_distance[top] > best.on.distance_squared) continue;
        if (tree.is_leaf(node)) {
            if (tree.triangle[node] != hint) try_triangle(tree.triangle[node]);
            continue;
        }
        const int32_t l = tree.left[node], r = tree.right[node];
        const double dl = box_distance_squared(p, lower_[l], upper_[l]);
        const double dr = box_distance_squared(p, lower_[r], upper_[r]);
        // the nearer child is popped first
        const bool left_first = dl <= dr;
        const int32_t first = left_first ? l : r, second = left_first ? r : l;
        const double d_first = left_first ? dl : dr, d_second = left_first ? dr : dl;
        if (d_second <= best.on.distance_squared && top < TRAVERSAL_STACK) {
            stack[top] = second;
            stack_distance[top++] = d_second;
        }
        if (d_first <= best.on.distance_squared && top < TRAVERSAL_STACK) {
            stack[top] = first;
            stack_distance[top++] = d_first;
        }
    }
    return best;
}

double ClosedSurface::signed_distance(const Vec3& p, int32_t* nearest, int32_t hint) const {
    const Closest c = closest(p, hint);
    if (nearest != nullptr) *nearest = c.triangle;
    if (c.triangle < 0) return -std::numeric_limits<double>::infinity();
    const double distance = std::sqrt(c.on.distance_squared);
    if (distance == 0.0) return 0.0;
    const double side = (p - c.on.point).dot(pseudonormal(c.triangle, c.on.feature));
    return side < 0.0 ? distance : -distance;
}

bool ClosedSurface::meets(const std::array<Vec3, 3>& t) const {
    if (empty()) return false;
    const BvhTopology& tree = topology_->tree;
    const Vec3 lo = t[0].cwiseMin(t[1]).cwiseMin(t[2]);
    const Vec3 hi = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
    const auto overlaps = [&](int32_t node) {
        return (lower_[node].array() <= hi.array()).all() && (lo.array() <= upper_[node].array()).all();
    };
    int32_t stack[TRAVERSAL_STACK];
    int top = 0;
    if (overlaps(0)) stack[top++] = 0;
    while (top > 0) {
        const int32_t node = stack[--top];
        if (tree.is_leaf(node)) {
            const std::array<Vec3, 3> s = triangle(tree.triangle[node]);
            if (!plainly_apart(t, s) && !plainly_apart(s, t) && triangles_intersect_static(t, s, 0.0)) return true;
            continue;
        }
        for (int32_t child : {tree.left[node], tree.right[node]}) {
            if (overlaps(child) && top < TRAVERSAL_STACK) stack[top++] = child;
        }
    }
    return false;
}

} // namespace usdksl
