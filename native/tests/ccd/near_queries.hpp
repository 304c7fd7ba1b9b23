#pragma once
/// @file near_queries.hpp
/// @brief Random unit-sized primitive pairs that pass near each other, for
///        the CCD tests that check answers against sampled or static
///        distances.

#include "usdksl/ccd/edge_edge_ccd.hpp"
#include "usdksl/ccd/vertex_face_ccd.hpp"
#include "usdksl/types.hpp"

#include <array>
#include <random>

namespace usdksl::test_queries {

/// @brief A primitive pair moving linearly over one step: vertex-face
///        (p, a, b, c) or edge-edge (a0, a1, b0, b1), and the thickness
///        asked (scene units).
struct NearQuery {
    std::array<Vec3, 4> start, end;
    double thickness = 0.0;
};

inline Vec3 random_point(std::mt19937_64& random, double spread) {
    std::uniform_real_distribution<double> coordinate(-spread, spread);
    return Vec3(coordinate(random), coordinate(random), coordinate(random));
}

/// @brief Four points in the unit cube, the first primitive (vertex, or
///        first edge) moved onto the other's centre, every point moving by
///        up to 0.3, then the first primitive shifted by up to 0.4 in a random
///        direction: near, on either side of, or through the other. The
///        thickness is left for the caller to draw.
inline NearQuery near_query(std::mt19937_64& random, bool edge_edge) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    NearQuery q;
    for (int i = 0; i < 4; ++i) q.start[i] = random_point(random, 1.0);
    const Vec3 target = edge_edge ? Vec3(0.5 * (q.start[2] + q.start[3]))
                                  : Vec3((q.start[1] + q.start[2] + q.start[3]) / 3.0);
    const Vec3 offset = target - (edge_edge ? Vec3(0.5 * (q.start[0] + q.start[1])) : q.start[0]);
    q.start[0] += offset;
    if (edge_edge) q.start[1] += offset;
    const double motion = 0.3 * unit(random);
    for (int i = 0; i < 4; ++i) q.end[i] = q.start[i] + random_point(random, motion);
    const Vec3 shift = random_point(random, 0.4);
    for (int i = 0; i < (edge_edge ? 2 : 1); ++i) {
        q.start[i] += shift;
        q.end[i] += shift;
    }
    return q;
}

/// @brief The CCD's answer for a query at its own thickness, default
///        tolerance and iteration cap.
inline CCDResult ccd_answer(const NearQuery& q, bool edge_edge) {
    CCDSettings settings;
    settings.thickness = q.thickness;
    const auto& s = q.start;
    const auto& e = q.end;
    return edge_edge ? edge_edge_ccd(s[0], s[1], s[2], s[3], e[0], e[1], e[2], e[3], settings)
                     : vertex_face_ccd(s[0], s[1], s[2], s[3], e[0], e[1], e[2], e[3], settings);
}

} // namespace usdksl::test_queries
