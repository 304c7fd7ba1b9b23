#pragma once
/// @file check.hpp
/// @brief The one entry point of the core: first contacts of mesh pairs over a time range.

#include "usdksl/mesh_animation.hpp"
#include "usdksl/scene/check_options.hpp"
#include "usdksl/scene/contact.hpp"
#include "usdksl/scene/counters.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace usdksl {

/// @brief Contacts (first per triangle pair, sorted by contact_before) and counters.
struct CheckResult {
    std::vector<Contact> contacts;
    Counters counters;
};

/// @brief First contact of every triangle pair of the given mesh pairs over
///        [options.t_begin, options.t_end]. A pair (i, i) is a self check.
CheckResult find_contacts(const std::vector<MeshAnimation>& meshes,
                          const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                          const CheckOptions& options);

} // namespace usdksl
