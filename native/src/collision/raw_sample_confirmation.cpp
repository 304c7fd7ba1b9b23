#include "usdksl/collision/raw_sample_confirmation.hpp"

#include "usdksl/collision/triangle_pair_tester.hpp"

#include <algorithm>

namespace usdksl {
namespace {

/// A contact of meshes whose flightplans kept every sample already is a raw
/// answer; any dropped sample (even one exactly on its chord) changes the steps
/// the narrow phase saw, so the time is recomputed on the raw intervals. Every
/// reported time then comes from the same raw steps whatever the method or
/// time window, which keeps answers byte-identical across them.
bool needs_confirmation(const Scene& scene, const Contact& c) {
    return scene.merged(c.mesh_a) || scene.merged(c.mesh_b);
}

/// Tests one triangle pair on the raw samples from time code `from` on; the
/// tester records its first contact.
void first_raw_contact(TrianglePairTester& raw, const Contact& c, double from, double t_begin, double t_end) {
    if (from <= t_begin && raw.test_static(c.mesh_a, c.tri_a, c.mesh_b, c.tri_b, t_begin)) return;
    double t = std::max(from, t_begin);
    while (true) {
        const PairStep step = raw.step_containing(c.mesh_a, c.tri_a, c.mesh_b, c.tri_b, t);
        if (!step.valid() || step.begin >= t_end) return;
        if (raw.test_step(c.mesh_a, c.tri_a, c.mesh_b, c.tri_b, step)) return;
        t = step.end;
    }
}

} // namespace

void mark_meshes_to_confirm(const Scene& candidate_scene, const std::vector<Contact>& candidates,
                            std::vector<FlightplanKind>& kinds) {
    kinds.resize(candidate_scene.meshes.size(), FlightplanKind::Unused);
    for (const Contact& c : candidates) {
        if (needs_confirmation(candidate_scene, c)) kinds[c.mesh_a] = kinds[c.mesh_b] = FlightplanKind::RawSamples;
    }
}

std::vector<Contact> confirm_on_raw_samples(const Scene& candidate_scene, const Scene& raw_scene,
                                            const std::vector<Contact>& candidates, const CCDSettings& settings,
                                            double t_begin, double t_end, Counters& counters) {
    std::vector<Contact> confirmed;
    TrianglePairTester raw(raw_scene, settings, counters);
    int64_t confirmations = 0;
    for (const Contact& c : candidates) {
        if (!needs_confirmation(candidate_scene, c)) {
            confirmed.push_back(c);
            continue;
        }
        ++confirmations;
        first_raw_contact(raw, c, c.time, t_begin, t_end);
    }
    counters.raw_confirmations += confirmations;
    counters.raw_rejections += confirmations - static_cast<int64_t>(raw.contacts().size());
    confirmed.insert(confirmed.end(), raw.contacts().begin(), raw.contacts().end());
    std::sort(confirmed.begin(), confirmed.end(), contact_before);
    return confirmed;
}

std::vector<Contact> confirm_on_raw_samples(const Scene& candidate_scene, const std::vector<Contact>& candidates,
                                            const CCDSettings& settings, double t_begin, double t_end,
                                            Counters& counters) {
    std::vector<FlightplanKind> kinds;
    mark_meshes_to_confirm(candidate_scene, candidates, kinds);
    if (std::all_of(kinds.begin(), kinds.end(), [](FlightplanKind k) { return k == FlightplanKind::Unused; })) {
        return candidates;
    }
    const Scene raw_scene(candidate_scene.meshes, kinds);
    return confirm_on_raw_samples(candidate_scene, raw_scene, candidates, settings, t_begin, t_end, counters);
}

} // namespace usdksl
