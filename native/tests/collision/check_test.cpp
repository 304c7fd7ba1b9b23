/// @file check_test.cpp
/// @brief The scene-level check: every method finds brute force's triangle
///        pairs at bit-identical times, and windows merge exactly.

#include "../../src/collision/raw_sample_confirmation.hpp"
#include "animations.hpp"
#include "usdksl/broad_phase/baselines.hpp"
#include "usdksl/collision/check.hpp"
#include "usdksl/kinetic/separation_list.hpp"
#include "usdksl/scene/window_stop.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

using namespace usdksl;

namespace {

using PairKey = std::tuple<int32_t, int32_t, int32_t, int32_t>;

std::map<PairKey, double> first_contacts(const std::vector<MeshAnimation>& meshes, Method method, double t_begin,
                                         double t_end, double thickness = 0.0) {
    CheckOptions options;
    options.method = method;
    options.ccd.thickness = thickness;
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

namespace {

/// Runs `method` over [0, t_end] told at once to stop at `stop_at`; returns
/// its candidates (confirmed on the raw samples unless discrete) and the end
/// it reached.
std::pair<std::map<PairKey, double>, double> stopped_run(const std::vector<MeshAnimation>& meshes, Method method,
                                                         double t_end, double stop_at, double thickness) {
    const Scene scene(meshes, method != Method::Discrete);
    Counters counters;
    CheckOptions options;
    options.method = method;
    options.ccd.thickness = thickness;
    options.t_end = t_end;
    TrianglePairTester tester(scene, options.ccd, counters);
    WindowStop stop(0.0, t_end);
    stop.stop_at = stop_at;
    if (method == Method::KineticSeparationList) {
        KineticSeparationLists lists(scene, {{0, 0}}, tester, counters, options);
        lists.run({}, &stop);
    } else if (method == Method::SweptVolume) {
        run_swept_volume(scene, {{0, 0}}, options, tester, counters, &stop);
    } else {
        run_discrete(scene, {{0, 0}}, options, tester, counters, &stop);
    }
    const double reached = stop.reached.load();
    const std::vector<Contact> contacts =
        method == Method::Discrete ? tester.sorted_contacts()
                                   : confirm_on_raw_samples(scene, tester.sorted_contacts(), options.ccd, 0.0, reached,
                                                            counters);
    std::map<PairKey, double> out;
    for (const Contact& c : contacts) out[{c.mesh_a, c.tri_a, c.mesh_b, c.tri_b}] = c.time;
    return {out, reached};
}

} // namespace

TEST(Check, AWindowStoppedEarlyAndTheRestFromTheStopMergeToTheWholeRun) {
    // What a thread that takes the rest of a running window relies on: the
    // window stops at the first step boundary at or after its new end, and
    // everything that first touches before it is among its contacts.
    const std::vector<MeshAnimation> meshes{animations::folding_cloth(6, 14)};
    // The layers come this close before they pass through each other, at
    // samples too (for the discrete check).
    const double thickness = 0.05;
    for (Method method : {Method::KineticSeparationList, Method::SweptVolume, Method::Discrete}) {
        const auto whole = first_contacts(meshes, method, 0.0, 13.0, thickness);
        ASSERT_FALSE(whole.empty()) << static_cast<int>(method);
        // The first sample after the first contact: contacts on both sides.
        double first = 13.0;
        for (const auto& entry : whole) first = std::min(first, entry.second);
        const double cut = std::floor(first) + 1.0;
        auto [merged, reached] = stopped_run(meshes, method, 13.0, cut, thickness);
        EXPECT_GE(reached, cut) << static_cast<int>(method);
        EXPECT_LT(reached, 13.0) << "stopped early, method " << static_cast<int>(method);
        size_t before_cut = 0;
        for (const auto& entry : whole) before_cut += entry.second < cut;
        EXPECT_GT(before_cut, 0u) << static_cast<int>(method);
        EXPECT_LT(before_cut, whole.size()) << static_cast<int>(method);
        for (const auto& [key, time] : first_contacts(meshes, method, cut, 13.0, thickness)) {
            auto it = merged.find(key);
            if (it == merged.end() || time < it->second) merged[key] = time;
        }
        EXPECT_EQ(merged, whole) << static_cast<int>(method);
    }
}
