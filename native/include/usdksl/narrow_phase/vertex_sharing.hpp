#pragma once
/// @file vertex_sharing.hpp
/// @brief Which primitives of two triangles of one mesh share a vertex: the
///        narrow phase never tests those, and every certificate of it skips
///        them alike.

#include "usdksl/types.hpp"

#include <cstdint>

namespace usdksl {

/// @brief True when vertex `v` is a corner of the triangle `ids`.
inline bool triangle_holds_vertex(const Triangle& ids, int32_t v) { return ids[0] == v || ids[1] == v || ids[2] == v; }

/// @brief True when the edges (e0, e1) and (f0, f1) share an end.
inline bool edges_share_vertex(int32_t e0, int32_t e1, int32_t f0, int32_t f1) {
    return e0 == f0 || e0 == f1 || e1 == f0 || e1 == f1;
}

} // namespace usdksl
