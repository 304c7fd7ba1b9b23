#pragma once
/// @file intersection_segment.hpp
/// @brief Where two triangles cross: the segment their surfaces share, whose
///        length summed over a region's triangle pairs is the length of the
///        two surfaces' intersection curve.

#include "usdksl/types.hpp"

#include <array>

namespace usdksl {

/// @brief The part two closed triangles share when they are not coplanar: a
///        segment from p to q (scene units) on the line where their planes
///        meet, a single point (p == q) when they only touch.
struct IntersectionSegment {
    /// @brief False when the triangles share no point, and for coplanar
    ///        triangles (whose overlap is an area, not a curve: it adds 0 to
    ///        an intersection length).
    bool meets = false;
    Vec3 p = Vec3::Zero();
    Vec3 q = Vec3::Zero();
    /// @brief True when two corners of a lie exactly in b's plane: the
    ///        segment runs along that edge of a, and the triangle across it
    ///        (when it is not coplanar with b) finds the same segment.
    bool along_edge_of_a = false;
    /// @brief The same for an edge of b in a's plane.
    bool along_edge_of_b = false;

    double length() const { return meets ? (q - p).norm() : 0.0; }
};

/// @brief The segment shared by closed triangles a and b. Which side of the
///        other's plane each vertex lies on is decided exactly (orient3d), so
///        touching, edge-on and vertex-on configurations are classified
///        without rounding; the endpoints are then interpolated in floating
///        point (each off by a few units in the last place of the coordinates).
///        Triangles of zero area count as coplanar: they share no segment.
IntersectionSegment triangle_intersection_segment(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b);

} // namespace usdksl
