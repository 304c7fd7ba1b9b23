#pragma once
/// @file animations.hpp
/// @brief Small deterministic animated meshes for the C++ unit tests.

#include "usdksl/mesh_animation.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace usdksl::animations {

/// @brief An (n x n)-quad sheet, two triangles per quad (one authored face per
///        triangle), sampled at `samples` integer time codes; vertex v at
///        sample k is position(v, k) for the given callable (x, z in [0, 1]).
template <typename Position>
MeshAnimation sheet(int n, int samples, Position position) {
    MeshAnimation mesh;
    mesh.vertex_count = (n + 1) * (n + 1);
    for (int k = 0; k < samples; ++k) {
        mesh.times.push_back(static_cast<double>(k));
        for (int i = 0; i <= n; ++i) {
            for (int j = 0; j <= n; ++j) {
                const Vec3 p = position(static_cast<double>(i) / n, static_cast<double>(j) / n, k);
                mesh.points.insert(mesh.points.end(), {p[0], p[1], p[2]});
            }
        }
    }
    const auto id = [n](int i, int j) { return i * (n + 1) + j; };
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    }
    for (size_t t = 0; t < mesh.triangles.size(); ++t) mesh.triangle_face.push_back(static_cast<int32_t>(t));
    return mesh;
}

/// @brief A 2 x 2-quad sheet that zigzags up and down over 100 sample steps
///        (time codes 0..100), turning every 10 samples: merged flightplans
///        keep breakpoints at the turns (time codes 0, 10, 20, ...) only.
inline MeshAnimation zigzag_sheet() {
    return sheet(2, 101, [](double x, double z, int k) { return Vec3(x, 0.01 * std::abs((k % 20) - 10), z); });
}

/// @brief A rotation that tilts a sheet out of every axis plane, so that its
///        box overlaps whatever lies just above or below it.
inline Eigen::Matrix3d tilt() {
    return (Eigen::AngleAxisd(0.5, Vec3::UnitZ()) * Eigen::AngleAxisd(0.35, Vec3::UnitX())).toRotationMatrix();
}

/// @brief A sheet that waves on curves and folds its right half over its left
///        (self contacts), every sample a breakpoint.
inline MeshAnimation folding_cloth(int n, int samples) {
    return sheet(n, samples, [samples](double x, double z, int k) {
        const double t = static_cast<double>(k);
        const double fold = 1.15 * M_PI * std::min(t / (samples - 3.0), 1.0);
        Vec3 p(x, 0.3 + 0.03 * std::sin(3.0 * x + 0.4 * t) * std::cos(2.0 * z + 0.3 * t), z);
        if (x > 0.5) {
            const double dx = x - 0.5;
            p[0] = 0.5 + dx * std::cos(fold);
            p[1] += dx * std::sin(fold) + 0.03 * dx;
        }
        return p;
    });
}

/// @brief Random vertex trajectories: `runs` straight stretches of random length
///        per vertex, each sampled at every integer time code (so merging has
///        collinear samples to drop), plus optional noise (scene units).
inline MeshAnimation random_walk(int vertices, int samples, uint32_t seed, double noise) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::uniform_int_distribution<int> run_length(1, 6);
    MeshAnimation mesh;
    mesh.vertex_count = vertices;
    mesh.points.assign(static_cast<size_t>(samples) * vertices * 3, 0.0);
    for (int k = 0; k < samples; ++k) mesh.times.push_back(static_cast<double>(k));
    for (int v = 0; v < vertices; ++v) {
        Vec3 p(unit(random), unit(random), unit(random));
        Vec3 velocity(unit(random), unit(random), unit(random));
        int left = run_length(random);
        for (int k = 0; k < samples; ++k) {
            for (int axis = 0; axis < 3; ++axis) {
                mesh.points[(static_cast<size_t>(k) * vertices + v) * 3 + axis] = p[axis] + noise * unit(random);
            }
            if (--left == 0) {
                velocity = Vec3(unit(random), unit(random), unit(random)) * 0.1;
                left = run_length(random);
            }
            p += velocity;
        }
    }
    for (int v = 0; v + 2 < vertices; v += 3) mesh.triangles.push_back({v, v + 1, v + 2});
    for (size_t t = 0; t < mesh.triangles.size(); ++t) mesh.triangle_face.push_back(static_cast<int32_t>(t));
    return mesh;
}

/// @brief Raw (linearly interpolated) position of vertex v at time code t.
inline Vec3 raw_position(const MeshAnimation& mesh, int32_t v, double t) {
    const size_t n = static_cast<size_t>(mesh.vertex_count);
    const auto at = [&](size_t k) {
        return Vec3(mesh.points[(k * n + v) * 3], mesh.points[(k * n + v) * 3 + 1], mesh.points[(k * n + v) * 3 + 2]);
    };
    if (t <= mesh.times.front()) return at(0);
    if (t >= mesh.times.back()) return at(mesh.times.size() - 1);
    size_t k = 0;
    while (mesh.times[k + 1] < t) ++k;
    const double w = (t - mesh.times[k]) / (mesh.times[k + 1] - mesh.times[k]);
    return at(k) + w * (at(k + 1) - at(k));
}

/// @brief One triangle (0.1..0.5 in x and z) at height heights[k] at time code k.
inline MeshAnimation falling_triangle(const std::vector<double>& heights) {
    MeshAnimation mesh;
    mesh.vertex_count = 3;
    for (size_t k = 0; k < heights.size(); ++k) {
        mesh.times.push_back(static_cast<double>(k));
        const double y = heights[k];
        mesh.points.insert(mesh.points.end(), {0.1, y, 0.1, 0.5, y, 0.1, 0.1, y, 0.5});
    }
    mesh.triangles.push_back({0, 1, 2});
    mesh.triangle_face.push_back(0);
    return mesh;
}

/// @brief The unit right triangle in the plane y = 0, still over the same samples.
inline MeshAnimation floor_triangle(int samples) {
    MeshAnimation mesh;
    mesh.vertex_count = 3;
    for (int k = 0; k < samples; ++k) {
        mesh.times.push_back(static_cast<double>(k));
        mesh.points.insert(mesh.points.end(), {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0});
    }
    mesh.triangles.push_back({0, 1, 2});
    mesh.triangle_face.push_back(0);
    return mesh;
}

} // namespace usdksl::animations
