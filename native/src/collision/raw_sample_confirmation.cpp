#include "raw_sample_confirmation.hpp"

#include "usdksl/ccd/ccd_constants.hpp"
#include "usdksl/scene/triangle_pair_tester.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace usdksl {
namespace {

/// Tests one triangle pair on the raw samples from time code `from` on; the
/// tester records its first contact.
void first_raw_contact(TrianglePairTester& raw, const Contact& c, double from, double t_begin, double t_end) {
    if (from <= t_begin && raw.test_static(c.mesh_a, c.tri_a, c.mesh_b, c.tri_b, t_begin)) return;
    double t = std::max(from, t_begin);
    if (t > t_begin) {
        // A candidate at a step's begin came from a search at a larger contact
        // distance (merge slack), whose answer near a graze is not monotone in
        // it: the raw step ending there may still touch at the thickness alone,
        // and brute force, which tests every raw step, would report it there.
        const PairStep before = raw.step_containing(c.mesh_a, c.tri_a, c.mesh_b, c.tri_b,
                                                    std::nextafter(t, -std::numeric_limits<double>::infinity()));
        if (before.valid() && before.end == t && before.begin >= t_begin &&
            raw.test_step(c.mesh_a, c.tri_a, c.mesh_b, c.tri_b, before)) {
            return;
        }
    }
    // The candidate's own step may come with its test worked out already.
    const PairStep step = raw.step_containing(c.mesh_a, c.tri_a, c.mesh_b, c.tri_b, t);
    if (!step.valid() || step.begin >= t_end) return;
    if (c.carried.known && step.begin == c.carried.begin && step.end == c.carried.end) {
        if (raw.apply_carried(c, step)) return;
        t = step.end;
    }
    // Every later step as test_step would test it, but those a clearance certificate clears skipped: a
    // candidate that never touches (within its slack only) costs the certificate's steps, not searches.
    raw.test_steps(c.mesh_a, c.tri_a, c.mesh_b, c.tri_b, t, t_end, true);
}

/// Candidates confirmed between two progress calls (where a stop request is raised).
constexpr int64_t kProgressEveryCandidates = 1 << 7;

} // namespace

CCDSettings confirming(const CCDSettings& settings) {
    CCDSettings fine = settings;
    fine.tolerance = std::max(settings.tolerance * CONFIRMATION_TOLERANCE_FACTOR, CCD_MIN_TOLERANCE);
    return fine;
}

void mark_meshes_to_confirm(const Scene& candidate_scene, const std::vector<Contact>& candidates,
                            std::vector<FlightplanKind>& kinds) {
    kinds.resize(candidate_scene.meshes.size(), FlightplanKind::Unused);
    for (const Contact& c : candidates) kinds[c.mesh_a] = kinds[c.mesh_b] = FlightplanKind::RawSamples;
}

std::vector<Contact> confirm_on_raw_scene(const Scene& raw_scene, const std::vector<Contact>& candidates,
                                          const CCDSettings& settings, double t_begin, double t_end,
                                          Counters& counters, const ProgressCallback& progress) {
    TrianglePairTester raw(raw_scene, confirming(settings), counters);
    int64_t done = 0;
    for (const Contact& c : candidates) {
        if (progress && (++done % kProgressEveryCandidates) == 0) {
            progress(t_end, static_cast<int64_t>(raw.contacts().size()));
        }
        first_raw_contact(raw, c, c.time, t_begin, t_end);
    }
    counters.raw_confirmations += static_cast<int64_t>(candidates.size());
    counters.raw_rejections += static_cast<int64_t>(candidates.size()) - static_cast<int64_t>(raw.contacts().size());
    return raw.sorted_contacts();
}

std::vector<Contact> confirm_on_raw_samples(const Scene& candidate_scene, const std::vector<Contact>& candidates,
                                            const CCDSettings& settings, double t_begin, double t_end,
                                            Counters& counters, const ProgressCallback& progress) {
    if (candidates.empty()) return {};
    std::vector<FlightplanKind> kinds;
    mark_meshes_to_confirm(candidate_scene, candidates, kinds);
    const Scene raw_scene(candidate_scene.meshes, kinds);
    return confirm_on_raw_scene(raw_scene, candidates, settings, t_begin, t_end, counters, progress);
}

} // namespace usdksl
