#include "usdksl/collision/check.hpp"

#include "usdksl/broad_phase/baselines.hpp"
#include "usdksl/collision/raw_sample_confirmation.hpp"
#include "usdksl/collision/scene.hpp"
#include "usdksl/collision/triangle_pair_tester.hpp"
#include "usdksl/kinetic/separation_list.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace usdksl {
namespace {

void validate(const std::vector<MeshAnimation>& meshes, const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
              const CheckOptions& options) {
    if (!(options.t_begin <= options.t_end) || !std::isfinite(options.t_begin) || !std::isfinite(options.t_end)) {
        throw std::invalid_argument("time range must be finite with begin <= end");
    }
    if (!(options.ccd.tolerance > 0.0) || !(options.ccd.thickness >= 0.0) || options.ccd.max_iterations <= 0) {
        throw std::invalid_argument("tolerance must be > 0, thickness >= 0, max_iterations > 0");
    }
    for (size_t m = 0; m < meshes.size(); ++m) {
        const MeshAnimation& mesh = meshes[m];
        for (const Triangle& tri : mesh.triangles) {
            for (int32_t v : tri) {
                if (v < 0 || v >= mesh.vertex_count) {
                    throw std::invalid_argument("mesh " + std::to_string(m) + ": triangle vertex out of range");
                }
            }
        }
        if (!mesh.triangle_face.empty() && mesh.triangle_face.size() != mesh.triangles.size()) {
            throw std::invalid_argument("mesh " + std::to_string(m) + ": triangle_face size mismatch");
        }
    }
    for (const auto& [a, b] : mesh_pairs) {
        if (a < 0 || b < 0 || a >= static_cast<int32_t>(meshes.size()) || b >= static_cast<int32_t>(meshes.size())) {
            throw std::invalid_argument("mesh pair index out of range");
        }
    }
}

} // namespace

CheckResult find_contacts(const std::vector<MeshAnimation>& meshes,
                          const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs, const CheckOptions& options) {
    validate(meshes, mesh_pairs, options);
    CheckResult result;
    // The event-based and swept methods run on merged flightplans with local
    // slack and find candidates; every continuous answer (brute force's too)
    // is confirmed on the raw samples at a finer tolerance. The reference and
    // the discrete check read the raw samples directly.
    const bool merge = options.method == Method::KineticSeparationList || options.method == Method::SweptVolume;
    const Scene scene(meshes, merge);
    TrianglePairTester tester(scene, options.ccd, result.counters);
    switch (options.method) {
    case Method::KineticSeparationList: {
        KineticSeparationLists lists(scene, mesh_pairs, tester, result.counters, options.t_begin, options.t_end,
                                     options.ccd.thickness);
        lists.run(options.progress);
        break;
    }
    case Method::SweptVolume:
        run_swept_volume(scene, mesh_pairs, options, tester, result.counters);
        break;
    case Method::Discrete:
        run_discrete(scene, mesh_pairs, options, tester, result.counters);
        break;
    case Method::BruteForce:
        run_brute_force(scene, mesh_pairs, options, tester);
        break;
    }
    // The discrete baseline answers at sampled instants; it stays what it is, misses included.
    result.contacts = options.method == Method::Discrete
                          ? tester.sorted_contacts()
                          : confirm_on_raw_samples(scene, tester.sorted_contacts(), options.ccd, options.t_begin,
                                                   options.t_end, result.counters, options.progress);
    return result;
}

} // namespace usdksl
