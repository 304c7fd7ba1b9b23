#include "usdksl/collision/scene.hpp"

#include <algorithm>

namespace usdksl {

Scene::Scene(const std::vector<MeshAnimation>& meshes_in, bool merge_collinear) : meshes(meshes_in) {
    plans.reserve(meshes.size());
    for (const MeshAnimation& mesh : meshes) {
        plans.emplace_back(mesh, merge_collinear);
        scale = std::max(scale, plans.back().max_abs_coordinate());
        merge_deviation = std::max(merge_deviation, plans.back().merge_deviation());
    }
}

std::array<Vec3, 3> Scene::triangle_at(int32_t mesh, int32_t tri, double t) const {
    const Triangle& ids = meshes[mesh].triangles[tri];
    const Flightplans& p = plans[mesh];
    return {p.position(ids[0], t), p.position(ids[1], t), p.position(ids[2], t)};
}

} // namespace usdksl
