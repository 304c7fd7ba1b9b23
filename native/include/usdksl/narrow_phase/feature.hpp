#pragma once
/// @file feature.hpp
/// @brief Which primitive pair produced a contact.

#include <cstdint>

namespace usdksl {

/// @brief The primitive pair behind a triangle-pair contact.
enum class ContactFeature : int8_t {
    /// @brief A vertex of triangle A against triangle B.
    VertexFace = 0,
    /// @brief A vertex of triangle B against triangle A.
    FaceVertex = 1,
    /// @brief An edge of A against an edge of B.
    EdgeEdge = 2,
    /// @brief Found by a test at one instant: already touching or
    ///        intersecting at the start of the checked range, or (discrete
    ///        method) at a sample. The reports call it `initial` too.
    Initial = 3,
};

} // namespace usdksl
