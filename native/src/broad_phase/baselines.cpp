#include "usdksl/broad_phase/baselines.hpp"

#include "aabb_tree.hpp"

#include "usdksl/broad_phase/sample_times.hpp"
#include "usdksl/flat_hash_map.hpp"

#include <memory>

namespace usdksl {
namespace {

/// Triangle-pair tests between two progress calls. The callback is also where a
/// stop request (Ctrl-C, SIGTERM, a timeout) is raised, so it must come every few
/// milliseconds of work, not only once per interval or per mesh pair.
constexpr int64_t kProgressEveryTests = 1 << 8;

/// Calls options.progress every kProgressEveryTests triangle-pair tests.
class ProgressTicker {
public:
    ProgressTicker(const CheckOptions& options, const TrianglePairTester& tester)
        : options_(options), tester_(tester) {}

    void tested(double t) {
        if (options_.progress && ++tests_ % kProgressEveryTests == 0) report(t);
    }

    void report(double t) const {
        if (options_.progress) options_.progress(t, static_cast<int64_t>(tester_.contacts().size()));
    }

private:
    const CheckOptions& options_;
    const TrianglePairTester& tester_;
    int64_t tests_ = 0;
};

std::vector<std::unique_ptr<AabbTree>> build_trees(const Scene& scene,
                                                   const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                                                   double t_build) {
    std::vector<std::unique_ptr<AabbTree>> trees(scene.meshes.size());
    for (const auto& [a, b] : mesh_pairs) {
        for (int32_t m : {a, b}) {
            if (!trees[m]) trees[m] = std::make_unique<AabbTree>(scene, m, t_build);
        }
    }
    return trees;
}

/// Each tree grows by half the contact distance its mesh contributes, so two
/// boxes meet exactly when their triangles may come within contact distance.
std::vector<double> tree_paddings(const Scene& scene, double thickness) {
    std::vector<double> padding(scene.meshes.size());
    for (size_t m = 0; m < padding.size(); ++m) {
        padding[m] = 0.5 * thickness + MERGE_DEVIATION_TO_DISTANCE * scene.merge_deviation(static_cast<int32_t>(m));
    }
    return padding;
}

void refit_all(std::vector<std::unique_ptr<AabbTree>>& trees, double t0, double t1,
               const std::vector<double>& padding) {
    for (size_t m = 0; m < trees.size(); ++m) {
        if (trees[m]) trees[m]->refit(t0, t1, padding[m]);
    }
}

} // namespace

void run_swept_volume(const Scene& scene, const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                      const CheckOptions& options, TrianglePairTester& tester, Counters& counters,
                      WindowStop* stop) {
    const std::vector<double> times = merged_sample_times(scene, mesh_pairs, options.t_begin, options.t_end);
    auto trees = build_trees(scene, mesh_pairs, options.t_begin);
    const std::vector<double> padding = tree_paddings(scene, options.ccd.thickness);
    ProgressTicker ticker(options, tester);
    tester.exchange_findings();
    // Static test at the range start, on boxes of that instant.
    refit_all(trees, options.t_begin, options.t_begin, padding);
    for (const auto& [ma, mb] : mesh_pairs) {
        if (!trees[ma] || !trees[mb]) continue;
        for_each_overlapping_leaf_pair(*trees[ma], *trees[mb], ma == mb, &counters.bv_tests,
                                       [&](int32_t ta, int32_t tb) {
                                           if (!tester.settled(ma, ta, mb, tb)) tester.test_static(ma, ta, mb, tb, options.t_begin);
                                           ticker.tested(options.t_begin);
                                       });
    }
    // End (time code) of the last step each triangle pair was tested on.
    FlatHashMap<uint64_t, double> tested_until;
    for (size_t i = 0; i + 1 < times.size(); ++i) {
        const double t0 = times[i], t1 = times[i + 1];
        if (stop && i > 0 && stop->stops_before(t0)) break;
        refit_all(trees, t0, t1, padding);
        for (const auto& [ma, mb] : mesh_pairs) {
            if (!trees[ma] || !trees[mb]) continue;
            for_each_overlapping_leaf_pair(
                *trees[ma], *trees[mb], ma == mb, &counters.bv_tests, [&](int32_t ta, int32_t tb) {
                    // As in the paper's baseline, every pair overlapping on an interval is tested there,
                    // but on its own step (between breakpoints of its six vertices, which holds the
                    // interval), as brute force and KSL test it: the narrow phase's answer within its
                    // tolerance depends on the step, and samples of other meshes cut shorter intervals.
                    ticker.tested(t0);
                    if (tester.settled(ma, ta, mb, tb)) return;
                    const PairStep step = tester.step_containing(ma, ta, mb, tb, t0);
                    if (!step.valid()) return;
                    const auto tested = tested_until.emplace(tester.key(ma, ta, mb, tb), step.begin).first;
                    if (tested->second >= step.end) return;
                    tested->second = step.end;
                    tester.test_step(ma, ta, mb, tb, step);
                });
        }
        if (stop) stop->reach(t1);
        tester.exchange_findings();
        ticker.report(t1);
    }
}

void run_discrete(const Scene& scene, const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                  const CheckOptions& options, TrianglePairTester& tester, Counters& counters,
                  WindowStop* stop) {
    const std::vector<double> samples = merged_sample_times(scene, mesh_pairs, options.t_begin, options.t_end);
    const int32_t substeps = std::max<int32_t>(1, options.discrete_substeps);
    std::vector<double> instants;
    for (size_t i = 0; i < samples.size(); ++i) {
        instants.push_back(samples[i]);
        if (i + 1 == samples.size()) break;
        for (int32_t s = 1; s < substeps; ++s) {
            instants.push_back(samples[i] + (samples[i + 1] - samples[i]) * s / substeps);
        }
    }
    auto trees = build_trees(scene, mesh_pairs, options.t_begin);
    const std::vector<double> padding = tree_paddings(scene, options.ccd.thickness);
    ProgressTicker ticker(options, tester);
    tester.exchange_findings();
    for (size_t i = 0; i < instants.size(); ++i) {
        const double t = instants[i];
        if (stop && i > 0 && stop->stops_before(t)) break;
        refit_all(trees, t, t, padding);
        for (const auto& [ma, mb] : mesh_pairs) {
            if (!trees[ma] || !trees[mb]) continue;
            for_each_overlapping_leaf_pair(*trees[ma], *trees[mb], ma == mb, &counters.bv_tests,
                                           [&](int32_t ta, int32_t tb) {
                                               if (!tester.settled(ma, ta, mb, tb)) tester.test_static(ma, ta, mb, tb, t);
                                               ticker.tested(t);
                                           });
        }
        // Every instant before the next one is tested.
        if (stop) stop->reach(i + 1 < instants.size() ? instants[i + 1] : t);
        tester.exchange_findings();
        ticker.report(t);
    }
}

void run_brute_force(const Scene& scene, const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                     const CheckOptions& options, TrianglePairTester& tester, WindowStop* stop) {
    ProgressTicker ticker(options, tester);
    for (const auto& [ma, mb] : mesh_pairs) {
        const int32_t na = static_cast<int32_t>(scene.meshes[ma].triangles.size());
        const int32_t nb = static_cast<int32_t>(scene.meshes[mb].triangles.size());
        for (int32_t ta = 0; ta < na; ++ta) {
            for (int32_t tb = (ma == mb ? ta + 1 : 0); tb < nb; ++tb) {
                ticker.tested(options.t_begin);
                if (tester.settled(ma, ta, mb, tb)) continue;
                if (tester.test_static(ma, ta, mb, tb, options.t_begin)) continue;
                double t = options.t_begin;
                while (true) {
                    const PairStep step = tester.step_containing(ma, ta, mb, tb, t);
                    if (!step.valid() || step.begin >= options.t_end) break;
                    ticker.tested(step.begin);
                    if (tester.test_step(ma, ta, mb, tb, step)) break;
                    t = step.end;
                }
            }
        }
        ticker.report(options.t_end);
    }
    if (stop) stop->reach(options.t_end);
}

} // namespace usdksl
