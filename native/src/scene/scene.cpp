#include "usdksl/scene/scene.hpp"

#include <algorithm>
#include <stdexcept>

namespace usdksl {
namespace {

std::vector<FlightplanKind> uniform_kinds(size_t count, bool merge_collinear) {
    return std::vector<FlightplanKind>(count,
                                       merge_collinear ? FlightplanKind::MergedSamples : FlightplanKind::RawSamples);
}

} // namespace

Scene::Scene(const std::vector<MeshAnimation>& meshes_in, bool merge_collinear, int32_t threads,
             double frames_per_time_code)
    : Scene(meshes_in, uniform_kinds(meshes_in.size(), merge_collinear), threads, frames_per_time_code) {}

Scene::Scene(const std::vector<MeshAnimation>& meshes_in, const std::vector<FlightplanKind>& kinds, int32_t threads,
             double frames_per_time_code)
    : meshes(meshes_in) {
    if (kinds.size() != meshes.size()) throw std::invalid_argument("scene: one flightplan kind per mesh");
    std::vector<FlightplanRequest> requests;
    for (size_t m = 0; m < meshes.size(); ++m) {
        if (kinds[m] == FlightplanKind::Unused) continue;
        const bool merging = kinds[m] == FlightplanKind::MergedSamples;
        requests.push_back({&meshes[m], merging, merging ? frames_per_time_code : 0.0});
    }
    std::vector<Flightplans> built = Flightplans::build_all(requests, threads);
    plans.resize(meshes.size());
    merge_deviation_.reserve(meshes.size());
    for (size_t m = 0, r = 0; m < meshes.size(); ++m) {
        if (kinds[m] != FlightplanKind::Unused) plans[m] = std::move(built[r++]);
        merge_deviation_.push_back(plans[m].merge_deviation());
    }
}

std::array<Vec3, 3> Scene::triangle_at(int32_t mesh, int32_t tri, double t) const {
    const Triangle& ids = meshes[mesh].triangles[tri];
    const Flightplans& p = plans[mesh];
    return {p.position(ids[0], t), p.position(ids[1], t), p.position(ids[2], t)};
}

} // namespace usdksl
