#pragma once
/// @file region_shapes.hpp
/// @brief Meshes the regions tests measure: boxes and spheres (closed),
///        sheets (open), stored with the view the core reads.

#include "usdksl/regions/mesh_view.hpp"

#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace usdksl::region_shapes {

/// @brief A mesh that owns its arrays; view() points into them.
struct StoredMesh {
    std::vector<double> times;
    std::vector<double> points;  // sample-major
    int32_t vertex_count = 0;
    std::vector<int32_t> triangles;
    std::vector<int32_t> triangle_face;

    MeshView view() const {
        MeshView v;
        v.times = times.data();
        v.sample_count = static_cast<int32_t>(times.size());
        v.points = points.data();
        v.vertex_count = vertex_count;
        v.triangles = triangles.data();
        v.triangle_count = static_cast<int32_t>(triangles.size() / 3);
        v.triangle_face = triangle_face.data();
        return v;
    }

    std::vector<Vec3> sample(int32_t k) const {
        std::vector<Vec3> out;
        for (int32_t v = 0; v < vertex_count; ++v) {
            const double* p = points.data() + (static_cast<size_t>(k) * vertex_count + v) * 3;
            out.emplace_back(p[0], p[1], p[2]);
        }
        return out;
    }
};

/// @brief A static box of half-sizes h centred at `centre`, outward normals,
///        six quad faces of two triangles each.
inline StoredMesh box(const Vec3& centre, const Vec3& h) {
    StoredMesh mesh;
    mesh.times = {0.0};
    mesh.vertex_count = 8;
    for (int i = 0; i < 8; ++i) {
        const Vec3 p = centre + Vec3((i & 1) ? h[0] : -h[0], (i & 2) ? h[1] : -h[1], (i & 4) ? h[2] : -h[2]);
        mesh.points.insert(mesh.points.end(), {p[0], p[1], p[2]});
    }
    // quads wound counter-clockwise seen from outside
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (int f = 0; f < 6; ++f) {
        const int* q = quads[f];
        mesh.triangles.insert(mesh.triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
        mesh.triangle_face.insert(mesh.triangle_face.end(), {f, f});
    }
    return mesh;
}

/// @brief An icosphere of radius r at `centre` (vertices on the sphere),
///        `levels` subdivisions of an icosahedron, outward normals.
inline StoredMesh icosphere(const Vec3& centre, double r, int levels) {
    const double g = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vec3> v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                           {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    for (Vec3& p : v) p.normalize();
    std::vector<std::array<int32_t, 3>> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                             {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                             {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                             {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (int level = 0; level < levels; ++level) {
        std::map<std::pair<int32_t, int32_t>, int32_t> middle;
        const auto mid = [&](int32_t a, int32_t b) {
            const auto key = std::make_pair(std::min(a, b), std::max(a, b));
            const auto found = middle.find(key);
            if (found != middle.end()) return found->second;
            v.push_back((v[a] + v[b]).normalized());
            return middle[key] = static_cast<int32_t>(v.size()) - 1;
        };
        std::vector<std::array<int32_t, 3>> next;
        for (const auto& t : f) {
            const int32_t ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
            next.push_back({t[0], ab, ca});
            next.push_back({t[1], bc, ab});
            next.push_back({t[2], ca, bc});
            next.push_back({ab, bc, ca});
        }
        f = next;
    }
    StoredMesh mesh;
    mesh.times = {0.0};
    mesh.vertex_count = static_cast<int32_t>(v.size());
    for (const Vec3& p : v) {
        const Vec3 q = centre + r * p;
        mesh.points.insert(mesh.points.end(), {q[0], q[1], q[2]});
    }
    for (size_t t = 0; t < f.size(); ++t) {
        mesh.triangles.insert(mesh.triangles.end(), f[t].begin(), f[t].end());
        mesh.triangle_face.push_back(static_cast<int32_t>(t));
    }
    return mesh;
}

/// @brief The mesh with every triangle's winding reversed (inward normals).
inline StoredMesh reversed(StoredMesh mesh) {
    for (size_t t = 0; t < mesh.triangles.size(); t += 3) std::swap(mesh.triangles[t + 1], mesh.triangles[t + 2]);
    return mesh;
}

/// @brief An n x n quad sheet in the plane z = height over [x0, x1] x [y0, y1],
///        one authored face per quad (two triangles), sampled at `times` with
///        height(time) added to z.
template <typename Height>
StoredMesh sheet(int n, double x0, double x1, double y0, double y1, const std::vector<double>& times, Height height) {
    StoredMesh mesh;
    mesh.times = times;
    mesh.vertex_count = (n + 1) * (n + 1);
    for (double t : times) {
        for (int i = 0; i <= n; ++i) {
            for (int j = 0; j <= n; ++j) {
                mesh.points.insert(mesh.points.end(),
                                   {x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * j / n, height(t)});
            }
        }
    }
    const auto id = [n](int i, int j) { return i * (n + 1) + j; };
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            const int32_t face = i * n + j;
            mesh.triangles.insert(mesh.triangles.end(),
                                  {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)});
            mesh.triangle_face.insert(mesh.triangle_face.end(), {face, face});
        }
    }
    return mesh;
}

} // namespace usdksl::region_shapes
