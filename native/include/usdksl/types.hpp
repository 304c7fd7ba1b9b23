#pragma once
/// @file types.hpp
/// @brief Small value types shared by every topic of the core.

#include <Eigen/Core>
#include <array>
#include <cstdint>

namespace usdksl {

/// @brief A point or displacement in world space (scene units).
using Vec3 = Eigen::Vector3d;

/// @brief Vertex indices of one triangle, into its mesh's vertex array.
using Triangle = std::array<int32_t, 3>;

} // namespace usdksl
