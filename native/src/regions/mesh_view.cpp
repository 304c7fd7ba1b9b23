/// @file mesh_view.cpp
/// @brief The sample step a time falls in.

#include "usdksl/regions/mesh_view.hpp"

#include <algorithm>

namespace usdksl {

SampleBlend blend_at(const MeshView& mesh, double t) {
    SampleBlend blend;
    const int32_t count = mesh.sample_count;
    if (count <= 1 || !(t > mesh.times[0])) return blend;  // before the first sample (or static): held still
    if (t >= mesh.times[count - 1]) {
        blend.k0 = blend.k1 = count - 1;
        return blend;
    }
    // times[k0] <= t < times[k0 + 1]
    const int32_t k1 = static_cast<int32_t>(std::upper_bound(mesh.times, mesh.times + count, t) - mesh.times);
    blend.k0 = k1 - 1;
    blend.k1 = k1;
    const double t0 = mesh.times[blend.k0];
    blend.w = t == t0 ? 0.0 : (t - t0) / (mesh.times[k1] - t0);
    if (blend.w == 0.0) blend.k1 = blend.k0;
    return blend;
}

} // namespace usdksl
