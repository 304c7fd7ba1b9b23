#pragma once
/// @file triangle_pair.hpp
/// @brief The narrow phase every method shares: two moving triangles over one
///        linear step, and two triangles at one instant.

#include "usdksl/ccd/ccd_settings.hpp"
#include "usdksl/ccd/vertex_face_memo.hpp"
#include "usdksl/narrow_phase/feature.hpp"
#include "usdksl/types.hpp"

#include <array>
#include <cstdint>

namespace usdksl {

/// @brief Earliest contact of one triangle pair over one step.
struct TrianglePairContact {
    bool hit = false;
    /// @brief Fraction of the step in [0,1]; a conservative (early) bound.
    double toi = 1.0;
    ContactFeature feature = ContactFeature::VertexFace;
    /// @brief True when any contributing primitive query hit the iteration cap.
    bool undecided = false;
    /// @brief Number of primitive CCD queries run (counter for benchmarks).
    int32_t queries = 0;
    /// @brief Of those, vertex-face queries answered by the memo (counter for benchmarks).
    int32_t reused_queries = 0;
};

/// @brief Vertex ids and positions of one triangle at the start and end of a step.
struct MovingTriangle {
    /// @brief Vertex ids; used only to skip primitive pairs that share a vertex
    ///        (meaningful when both triangles come from the same mesh).
    Triangle ids;
    std::array<Vec3, 3> t0;
    std::array<Vec3, 3> t1;
};

/// @brief Earliest contact over one linear step between triangles A and B:
///        the minimum over their 6 vertex-face and 9 edge-edge primitive pairs.
///        When `same_mesh` is true, primitive pairs that share a vertex id are
///        never tested. Conservative: never misses a contact. With a `memo`,
///        vertex-face queries asked recently with the same inputs are answered
///        from it: the same answer bit for bit, at the cost of a lookup.
TrianglePairContact triangle_pair_ccd(const MovingTriangle& a, const MovingTriangle& b,
                                      bool same_mesh, const CCDSettings& settings,
                                      VertexFaceMemo* memo = nullptr);

/// @brief True when triangles A and B (positions at one instant) touch or
///        intersect (within settings.thickness), considering only primitives
///        that share no vertex id when `same_mesh` is true: vertex-face and
///        edge-edge distances, and edges piercing the other triangle.
bool triangle_pair_intersect_static(const Triangle& ids_a, const std::array<Vec3, 3>& a,
                                    const Triangle& ids_b, const std::array<Vec3, 3>& b,
                                    bool same_mesh, double thickness);

/// @brief True when an edge of triangle A that shares no vertex id with B
///        meets closed triangle B (positions at one instant, exact test): the
///        piercing the static test reports, which no distance between
///        primitive pairs shows.
bool edge_pierces_triangle(const Triangle& ids_a, const std::array<Vec3, 3>& a, const Triangle& ids_b,
                           const std::array<Vec3, 3>& b);

} // namespace usdksl
