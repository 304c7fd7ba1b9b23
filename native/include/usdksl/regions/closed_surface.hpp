#pragma once
/// @file closed_surface.hpp
/// @brief The surface of a closed (watertight, consistently oriented) mesh at
///        one instant: distance from a point to it, and on which side the
///        point lies, through a bounding volume hierarchy over all its
///        triangles.
///
/// Inside test: the angle-weighted pseudonormal of the closest feature
/// (Baerentzen and Aanaes, "Signed distance computation using the angle
/// weighted pseudonormal", IEEE TVCG 2005). On a closed, consistently
/// oriented manifold, p is inside exactly when (p - c) . n < 0, where c is the
/// closest surface point and n the pseudonormal of the feature c lies on: the
/// face normal in a face's interior, the sum of the two face normals on an
/// edge, and the sum of the incident face normals weighted by their angles at
/// a corner. It is chosen over a generalized winding number because the
/// depth needs the closest point anyway (the test then costs a dot product),
/// and over ray casting because it has no special cases where a ray grazes
/// an edge or a vertex. The mesh's orientation (outward or inward normals,
/// e.g. a left-handed USD mesh) is read from the sign of its enclosed volume,
/// so either works. It needs a closed manifold: near a vertex where two closed
/// pieces touch (non-manifold) the answer can be wrong.

#include "usdksl/broad_phase/bvh_topology.hpp"
#include "usdksl/regions/closest_feature.hpp"
#include "usdksl/regions/mesh_view.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace usdksl {

/// @brief What a closed mesh keeps from instant to instant: its tree's
///        shape (built once, refit at every instant), the triangle across
///        each edge, and the triangles around each vertex.
struct ClosedMeshTopology {
    BvhTopology tree;
    /// @brief neighbour[t][i]: the triangle across edge (corner i, corner
    ///        i + 1) of triangle t, -1 when no triangle uses it reversed.
    std::vector<std::array<int32_t, 3>> neighbour;
    /// @brief Triangles around vertex v: vertex_triangles[vertex_start[v] ..
    ///        vertex_start[v + 1]).
    std::vector<int64_t> vertex_start;
    std::vector<int32_t> vertex_triangles;
};

/// @brief The topology of `mesh`, its tree built on the triangle centroids at
///        `points` (vertex_count positions, e.g. one sample).
ClosedMeshTopology build_closed_mesh_topology(const MeshView& mesh, const Vec3* points);

/// @brief The surface at one instant. Cheap to update: the boxes are refit
///        and the orientation read, normals are computed where a query needs
///        them.
class ClosedSurface {
public:
    /// @brief Takes the positions `points` (vertex_count of them; kept by
    ///        pointer, not copied) of `mesh`, whose topology is `topology`.
    void update(const MeshView& mesh, const ClosedMeshTopology& topology, const Vec3* points);

    /// @brief A closest surface point and the triangle it is on.
    struct Closest {
        ClosestOnTriangle on;
        int32_t triangle = -1;
    };

    /// @brief The surface point closest to p. `hint`: a triangle likely to be
    ///        close (e.g. the answer for a nearby point), or -1; the answer
    ///        does not depend on it beyond ties.
    Closest closest(const Vec3& p, int32_t hint = -1) const;

    /// @brief Signed distance (scene units) from p to the surface: positive
    ///        inside, negative outside, 0 on it. `nearest` (optional)
    ///        receives the triangle of the closest point.
    double signed_distance(const Vec3& p, int32_t* nearest = nullptr, int32_t hint = -1) const;

    /// @brief True when closed triangle t shares a point with the surface
    ///        (exact test, no thickness).
    bool meets(const std::array<Vec3, 3>& t) const;

    /// @brief Positions of triangle `tri`.
    std::array<Vec3, 3> triangle(int32_t tri) const {
        const Triangle ids = mesh_->triangle(tri);
        return {points_[ids[0]], points_[ids[1]], points_[ids[2]]};
    }

    /// @brief +1 when the triangles wind counter-clockwise seen from outside
    ///        (outward normals), -1 when they face inward.
    double orientation() const { return orientation_; }

    /// @brief The outward pseudonormal (not normalized) of a feature of
    ///        triangle `tri`.
    Vec3 pseudonormal(int32_t tri, TriangleFeature feature) const;

    bool empty() const { return mesh_ == nullptr || mesh_->triangle_count == 0; }

private:
    Vec3 unit_normal(int32_t tri) const;

    const MeshView* mesh_ = nullptr;
    const ClosedMeshTopology* topology_ = nullptr;
    const Vec3* points_ = nullptr;
    double orientation_ = 1.0;
    std::vector<Vec3> lower_, upper_;
};

} // namespace usdksl
