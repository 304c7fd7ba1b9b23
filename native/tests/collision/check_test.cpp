/// @file check_test.cpp
/// @brief The scene-level check: every method finds brute force's triangle
///        pairs at bit-identical times, and windows merge exactly.

#include "animations.hpp"
#include "usdksl/collision/check.hpp"

#include <gtest/gtest.h>

#include <map>
#include <tuple>

using namespace usdksl;

namespace {

using PairKey = std::tuple<int32_t, int32_t, int32_t, int32_t>;

std::map<PairKey, double> first_contacts(const std::vector<MeshAnimation>& meshes, Method method, double t_begin,
                                         double t_end) {
    CheckOptions options;
    options.method = method;
    options.t_begin = t_begin;
    options.t_end = t_end;
    const CheckResult result = find_contacts(meshes, {{0, 0}}, options);
    std::map<PairKey, double> out;
    for (const Contact& c : result.contacts) out[{c.mesh_a, c.tri_a, c.mesh_b, c.tri_b}] = c.time;
    return out;
}

} // namespace

TEST(Check, KineticAndSweptReportBruteForcesPairsAtIdenticalTimes) {
    const std::vector<MeshAnimation> meshes{animations::folding_cloth(6, 14)};
    const auto brute = first_contacts(meshes, Method::BruteForce, 0.0, 13.0);
    ASSERT_FALSE(brute.empty()) << "the cloth must fold onto itself";
    EXPECT_EQ(first_contacts(meshes, Method::KineticSeparationList, 0.0, 13.0), brute);
    EXPECT_EQ(first_contacts(meshes, Method::SweptVolume, 0.0, 13.0), brute);
}

TEST(Check, WindowsSplitAtSamplesMergeToTheWholeRun) {
    const std::vector<MeshAnimation> meshes{animations::folding_cloth(6, 14)};
    const auto whole = first_contacts(meshes, Method::KineticSeparationList, 0.0, 13.0);
    auto merged = first_contacts(meshes, Method::KineticSeparationList, 0.0, 9.0);
    for (const auto& [key, time] : first_contacts(meshes, Method::KineticSeparationList, 9.0, 13.0)) {
        auto it = merged.find(key);
        if (it == merged.end() || time < it->second) merged[key] = time;
    }
    EXPECT_EQ(merged, whole);
}

TEST(Check, RejectsBadInputWithAnException) {
    std::vector<MeshAnimation> meshes{animations::folding_cloth(2, 3)};
    meshes[0].triangles.push_back({0, 1, 999});
    meshes[0].triangle_face.push_back(99);
    CheckOptions options;
    options.t_end = 2.0;
    EXPECT_THROW(find_contacts(meshes, {{0, 0}}, options), std::invalid_argument);
}
