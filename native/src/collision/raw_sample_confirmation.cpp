#include "usdksl/collision/raw_sample_confirmation.hpp"

#include "usdksl/collision/triangle_pair_tester.hpp"

#include <algorithm>

namespace usdksl {
namespace {

/// Candidates confirmed between two progress calls (where a stop request is raised).
constexpr int64_t kProgressEveryCandidates = 1 << 7;

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

std::vector<Contact> confirm_on_raw_samples(const Scene& candidate_scene, const std::vector<Contact>& candidates,
                                            const CCDSettings& settings, double t_begin, double t_end,
                                            Counters& counters, const ProgressCallback& progress) {
    std::vector<FlightplanKind> kinds(candidate_scene.meshes.size(), FlightplanKind::Unused);
    std::vector<Contact> confirmed;
    for (const Contact& c : candidates) {
        if (needs_confirmation(candidate_scene, c)) {
            kinds[c.mesh_a] = kinds[c.mesh_b] = FlightplanKind::RawSamples;
        } else {
            confirmed.push_back(c);
        }
    }
    if (confirmed.size() == candidates.size()) return confirmed;

    const Scene raw_scene(candidate_scene.meshes, kinds);
    TrianglePairTester raw(raw_scene, settings, counters);
    for (const Contact& c : candidates) {
        if (!needs_confirmation(candidate_scene, c)) continue;
        ++counters.raw_confirmations;
        if (progress && counters.raw_confirmations % kProgressEveryCandidates == 0) {
            progress(t_end, static_cast<int64_t>(confirmed.size() + raw.contacts().size()));
        }
        first_raw_contact(raw, c, c.time, t_begin, t_end);
    }
    counters.raw_rejections = counters.raw_confirmations - static_cast<int64_t>(raw.contacts().size());
    confirmed.insert(confirmed.end(), raw.contacts().begin(), raw.contacts().end());
    std::sort(confirmed.begin(), confirmed.end(), contact_before);
    return confirmed;
}

} // namespace usdksl
