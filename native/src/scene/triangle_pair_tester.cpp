#include "usdksl/scene/triangle_pair_tester.hpp"

#include "usdksl/narrow_phase/triangle_pair.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace usdksl {

TrianglePairTester::TrianglePairTester(const Scene& scene, const CCDSettings& settings, Counters& counters)
    : scene_(scene), settings_(settings), counters_(counters) {
    triangle_offset_.push_back(0);
    for (const MeshAnimation& mesh : scene.meshes) {
        triangle_offset_.push_back(triangle_offset_.back() + static_cast<int64_t>(mesh.triangles.size()));
    }
}

void TrianglePairTester::canonical_order(int32_t& mesh_a, int32_t& tri_a, int32_t& mesh_b, int32_t& tri_b) {
    // Inter pairs mesh_a < mesh_b, self pairs tri_a < tri_b. The narrow phase
    // then always sees a pair the same way round: its answer (a lower bound
    // within the tolerance) depends on the order it tries primitives in.
    if (mesh_a > mesh_b || (mesh_a == mesh_b && tri_a > tri_b)) {
        std::swap(mesh_a, mesh_b);
        std::swap(tri_a, tri_b);
    }
}

CCDSettings TrianglePairTester::settings_for(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b) const {
    CCDSettings settings = settings_;
    settings.thickness = scene_.contact_distance(mesh_a, tri_a, mesh_b, tri_b, settings_.thickness);
    return settings;
}

uint64_t TrianglePairTester::key(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b) const {
    uint64_t a = static_cast<uint64_t>(triangle_offset_[mesh_a] + tri_a);
    uint64_t b = static_cast<uint64_t>(triangle_offset_[mesh_b] + tri_b);
    if (a > b) std::swap(a, b);
    return (a << 32) | b;
}

PairStep TrianglePairTester::step_containing(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b,
                                             double t) const {
    double begin = -std::numeric_limits<double>::infinity();
    double end = std::numeric_limits<double>::infinity();
    const auto widen = [&](int32_t mesh, int32_t tri) {
        const Flightplans& plans = scene_.plans[mesh];
        for (int32_t v : scene_.meshes[mesh].triangles[tri]) {
            const int64_t k = plans.segment_of(v, t);
            const double kt = plans.key_time(v, k);
            if (kt <= t) {
                begin = std::max(begin, kt);
                if (k + 1 < plans.key_end(v)) end = std::min(end, plans.key_time(v, k + 1));
            } else {
                end = std::min(end, kt);  // t precedes v's first breakpoint: v holds still until kt
            }
        }
    };
    widen(mesh_a, tri_a);
    widen(mesh_b, tri_b);
    if (!std::isfinite(end)) return {t, t};
    if (!std::isfinite(begin)) begin = std::min(t, end);
    return {begin, end};
}

bool TrianglePairTester::settled(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b) const {
    if (mesh_a == mesh_b) {
        if (tri_a == tri_b) return true;
        const std::vector<int32_t>& face = scene_.meshes[mesh_a].triangle_face;
        if (!face.empty() && face[tri_a] == face[tri_b]) return true;
    }
    const uint64_t k = key(mesh_a, tri_a, mesh_b, tri_b);
    return found_.count(k) != 0 || (!found_earlier_.empty() && found_earlier_.count(k) != 0);
}

void TrianglePairTester::settle(const std::vector<std::array<int32_t, 4>>& pairs) {
    for (const auto& [mesh_a, tri_a, mesh_b, tri_b] : pairs) found_earlier_.insert(key(mesh_a, tri_a, mesh_b, tri_b));
}

void TrianglePairTester::share_findings(WindowFindings& findings, int32_t slot) {
    findings_ = &findings;
    findings_slot_ = slot;
}

void TrianglePairTester::exchange_findings() {
    if (!findings_) return;
    std::vector<uint64_t> keys;
    keys.reserve(contacts_.size() - contacts_published_);
    for (; contacts_published_ < contacts_.size(); ++contacts_published_) {
        const Contact& c = contacts_[contacts_published_];
        keys.push_back(key(c.mesh_a, c.tri_a, c.mesh_b, c.tri_b));
    }
    findings_->publish(findings_slot_, keys);
    findings_->collect_earlier(findings_slot_, findings_cursors_, [this](uint64_t k) { found_earlier_.insert(k); });
}

bool TrianglePairTester::test_step(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b,
                                   const PairStep& step) {
    if (!step.valid()) return false;
    canonical_order(mesh_a, tri_a, mesh_b, tri_b);
    return test_positions(mesh_a, tri_a, mesh_b, tri_b, step, scene_.triangle_at(mesh_a, tri_a, step.begin),
                          scene_.triangle_at(mesh_a, tri_a, step.end), scene_.triangle_at(mesh_b, tri_b, step.begin),
                          scene_.triangle_at(mesh_b, tri_b, step.end),
                          !scene_.merged(mesh_a) && !scene_.merged(mesh_b));
}

bool TrianglePairTester::test_positions(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b,
                                        const PairStep& step, const std::array<Vec3, 3>& a0,
                                        const std::array<Vec3, 3>& a1, const std::array<Vec3, 3>& b0,
                                        const std::array<Vec3, 3>& b1, bool raw_positions, double contact_distance) {
    ++counters_.narrow_phase_tests;
    const MovingTriangle a{scene_.meshes[mesh_a].triangles[tri_a], a0, a1};
    const MovingTriangle b{scene_.meshes[mesh_b].triangles[tri_b], b0, b1};
    CCDSettings settings = settings_for(mesh_a, tri_a, mesh_b, tri_b);
    if (!std::isnan(contact_distance)) settings.thickness = contact_distance;
    // The raw-sample confirmation tests this very step with these positions
    // at the user's thickness: only then is its answer worked out here.
    FinerReplay* replay = finer_ && raw_positions && settings.thickness == settings_.thickness
                              ? finer_.get()
                              : nullptr;
    const TrianglePairContact hit = triangle_pair_ccd(a, b, mesh_a == mesh_b, settings, &vertex_face_memo_, replay);
    count_queries(hit);
    counters_.reused_queries += hit.reused_queries;
    if (!hit.hit) return false;
    Contact contact = contact_from(mesh_a, tri_a, mesh_b, tri_b, step, hit);
    if (replay) {
        CCDSettings finer = settings;
        finer.tolerance = finer_tolerance_;
        contact.carried.answer = finer_triangle_pair_ccd(a, b, mesh_a == mesh_b, finer, *replay, &finer_memo_);
        contact.carried.begin = step.begin;
        contact.carried.end = step.end;
        contact.carried.known = true;
    }
    record(contact);
    return true;
}

void TrianglePairTester::carry_confirmations(double finer_tolerance) {
    finer_tolerance_ = finer_tolerance;
    finer_ = std::make_unique<FinerReplay>(finer_tolerance);
}

bool TrianglePairTester::apply_carried(const Contact& candidate, const PairStep& step) {
    ++counters_.narrow_phase_tests;
    const TrianglePairContact& answer = candidate.carried.answer;
    count_queries(answer);
    if (!answer.hit) return false;
    record(contact_from(candidate.mesh_a, candidate.tri_a, candidate.mesh_b, candidate.tri_b, step, answer));
    return true;
}

void TrianglePairTester::count_queries(const TrianglePairContact& answer) {
    counters_.primitive_queries += answer.queries;
    if (answer.undecided) ++counters_.undecided_queries;
}

Contact TrianglePairTester::contact_from(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b,
                                         const PairStep& step, const TrianglePairContact& answer) {
    Contact contact;
    contact.time = step.begin + answer.toi * (step.end - step.begin);
    contact.mesh_a = mesh_a;
    contact.tri_a = tri_a;
    contact.mesh_b = mesh_b;
    contact.tri_b = tri_b;
    contact.feature = answer.feature;
    contact.undecided = answer.undecided;
    return contact;
}

StepRun TrianglePairTester::test_steps(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b, double from,
                                       double until, bool use_clearance, ClearanceRun* carried,
                                       double ahead_until) {
    constexpr double infinity = std::numeric_limits<double>::infinity();
    canonical_order(mesh_a, tri_a, mesh_b, tri_b);
    if (!found_earlier_.empty() && found_earlier_.count(key(mesh_a, tri_a, mesh_b, tri_b)) != 0) {
        if (carried) carried->valid_at = -infinity;
        return StepRun{from, true};  // an earlier window's candidate answers for it
    }
    const Triangle& ids_a = scene_.meshes[mesh_a].triangles[tri_a];
    const Triangle& ids_b = scene_.meshes[mesh_b].triangles[tri_b];
    const Flightplans* plans[6];
    int32_t vertex[6];
    // Each vertex's segment with its breakpoint times, kept as the walk goes
    // so that a step in which a vertex keeps its segment reads nothing of it.
    int64_t segment[6], last[6];
    double segment_time[6], next_time[6];  // next_time: +inf after the last breakpoint
    for (int i = 0; i < 6; ++i) {
        const Flightplans& p = scene_.plans[i < 3 ? mesh_a : mesh_b];
        plans[i] = &p;
        vertex[i] = i < 3 ? ids_a[i] : ids_b[i - 3];
        segment[i] = p.segment_of(vertex[i], from);
        last[i] = p.key_end(vertex[i]) - 1;
        segment_time[i] = p.key_time(vertex[i], segment[i]);
        next_time[i] = segment[i] < last[i] ? p.key_time(vertex[i], segment[i] + 1) : infinity;
    }
    // A clearance certificate skips steps on which the pair provably stays
    // out of reach; one that fails at once backs off for a few steps, so a
    // pair in near contact does not pay for it on every step.
    ClearanceRun local;
    ClearanceRun& run = carried && carried->valid_at == from ? *carried : local;
    PairClearance& clearance = run.clearance;
    bool& certified = run.certified;
    bool& fresh = run.fresh;
    int32_t& wait = run.wait;
    int32_t& backoff = run.backoff;
    // Only a run that followed every step up to `from` may go on.
    const auto done = [&](StepRun result) {
        if (carried) {
            if (&run == &local) *carried = local;
            carried->valid_at = result.hit ? -infinity : result.tested_until;
        }
        return result;
    };
    const double pair_distance = settings_for(mesh_a, tri_a, mesh_b, tri_b).thickness;
    // Where sub-frame samples were stepped over, each step has its vertices' own slack, mostly far below
    // the largest over the range (an impact's frame).
    const bool per_segment = plans[0]->deviation_per_segment() || plans[3]->deviation_per_segment();
    const double size_fraction = clearance_size_fraction(settings_.tolerance);
    double magnitude = -1.0;
    const auto pair_magnitude = [&]() {  // no coordinate of the six vertices exceeds it
        if (magnitude < 0.0) {
            magnitude = std::max(scene_.triangle_magnitude(mesh_a, tri_a), scene_.triangle_magnitude(mesh_b, tri_b));
        }
        return magnitude;
    };
    std::array<Vec3, 3> a0, a1, b0, b1;
    // A step that begins where the last one ended starts from its end positions:
    // the same segments at the same time code, so the same numbers.
    double positions_end = std::numeric_limits<double>::quiet_NaN();
    double t = from;
    while (true) {
        // The step containing t, as step_containing() finds it.
        double begin = -infinity, end = infinity;
        for (int i = 0; i < 6; ++i) {
            while (next_time[i] <= t) {  // Flightplans::advance_segment
                segment_time[i] = next_time[i];
                ++segment[i];
                next_time[i] = segment[i] < last[i] ? plans[i]->key_time(vertex[i], segment[i] + 1) : infinity;
            }
            if (segment_time[i] <= t) {
                begin = std::max(begin, segment_time[i]);
                end = std::min(end, next_time[i]);
            } else {
                end = std::min(end, segment_time[i]);
            }
        }
        if (!std::isfinite(end)) return done({infinity, false});
        if (!std::isfinite(begin)) begin = std::min(t, end);
        // Every vertex's segment holds `begin` too (no breakpoint lies in (begin, t]).
        const bool starts_at_last_end = begin == positions_end;
        if (starts_at_last_end) {
            a0 = a1;
            b0 = b1;
        }
        // Positions at breakpoints of their own vertex are raw samples.
        bool raw_positions = true;
        for (int i = 0; i < 6; ++i) {
            const Flightplans& p = *plans[i];
            // No breakpoint of the vertex lies inside the step: its segment
            // holds the end too, or the next one begins there.
            const bool breaks_at_end = next_time[i] == end;
            const int64_t at_end = breaks_at_end ? segment[i] + 1 : segment[i];
            raw_positions = raw_positions && segment_time[i] == begin && breaks_at_end;
            Vec3& start = i < 3 ? a0[i] : b0[i - 3];
            Vec3& finish = i < 3 ? a1[i] : b1[i - 3];
            if (!starts_at_last_end) start = p.position_in_segment(vertex[i], segment[i], begin);
            finish = p.position_in_segment(vertex[i], at_end, end);
        }
        positions_end = end;
        double contact_distance = pair_distance;
        if (per_segment) {
            double deviation[2] = {0.0, 0.0};
            for (int i = 0; i < 6; ++i) {
                if (segment_time[i] <= begin)
                    deviation[i / 3] = std::max(deviation[i / 3], plans[i]->segment_deviation(vertex[i], segment[i]));
            }
            contact_distance = settings_.thickness + MERGE_DEVIATION_TO_DISTANCE * (deviation[0] + deviation[1]);
            // A certificate proven for less slack than this step has ran out.
            if (certified && contact_distance > clearance.contact_distance()) {
                certified = false;
                wait = 0;
            }
        }
        bool cleared = false;
        const auto start_certificate = [&]() {
            clearance.start(ids_a, a0, ids_b, b0, mesh_a == mesh_b, contact_distance, settings_.tolerance,
                            pair_magnitude());
            certified = fresh = true;
        };
        if (use_clearance && !certified && wait == 0) start_certificate();
        if (certified) {
            cleared = clearance.holds_at(a1, b1);
            if (!cleared && !fresh) {
                // This certificate ran out after clearing steps: one started
                // at this step's begin may clear it (a pair sliding along
                // another stays apart while drifting far from where it was).
                start_certificate();
                cleared = clearance.holds_at(a1, b1);
            }
            if (cleared) {
                fresh = false;
                backoff = 1;
            } else {
                certified = false;
                wait = backoff;
                backoff = std::min(2 * backoff, CLEARANCE_MAX_BACKOFF_STEPS);
            }
        } else if (wait > 0) {
            --wait;
        }
        if (!cleared && use_clearance) {
            // No certificate answers for this step: one of the step alone
            // may still, at a fraction of the narrow phase's cost.
            const double diameter = std::max(pair_box_diagonal(a0, b0), pair_box_diagonal(a1, b1));
            cleared = swept_apart(a0, a1, b0, b1,
                                  clearance_reach(contact_distance, size_fraction, diameter, 0.0, pair_magnitude()));
        }
        if (cleared) {
            ++counters_.cleared_steps;
        } else if (begin >= until) {
            return done({begin, false});  // covering ahead stops before a step that needs the narrow phase
        } else if (test_positions(mesh_a, tri_a, mesh_b, tri_b, PairStep{begin, end}, a0, a1, b0, b1,
                                  raw_positions, per_segment ? contact_distance : std::numeric_limits<double>::quiet_NaN())) {
            return done({end, true});
        }
        if (end >= until && (!cleared || end >= ahead_until)) return done({end, false});
        t = end;
    }
}

bool TrianglePairTester::test_static(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b, double t) {
    ++counters_.narrow_phase_tests;
    canonical_order(mesh_a, tri_a, mesh_b, tri_b);
    const Triangle& ids_a = scene_.meshes[mesh_a].triangles[tri_a];
    const Triangle& ids_b = scene_.meshes[mesh_b].triangles[tri_b];
    const std::array<Vec3, 3> at_a = scene_.triangle_at(mesh_a, tri_a, t);
    const std::array<Vec3, 3> at_b = scene_.triangle_at(mesh_b, tri_b, t);
    bool hit = triangle_pair_intersect_static(ids_a, at_a, ids_b, at_b, mesh_a == mesh_b,
                                              scene_.contact_distance(mesh_a, tri_a, mesh_b, tri_b, settings_.thickness));
    if (!hit) {
        // The pair held still at t, as the continuous test sees it on a step where nothing moves
        // (between raw samples of still vertices, which the other methods' steps keep): a gap that test
        // cannot tell from contact counts as contact here too, so a pair that never moves in the
        // checked range gets the same answer from every method.
        const TrianglePairContact still = triangle_pair_ccd(MovingTriangle{ids_a, at_a, at_a},
                                                            MovingTriangle{ids_b, at_b, at_b}, mesh_a == mesh_b,
                                                            settings_for(mesh_a, tri_a, mesh_b, tri_b), &vertex_face_memo_);
        count_queries(still);
        counters_.reused_queries += still.reused_queries;
        hit = still.hit;
    }
    if (!hit) return false;
    Contact contact;
    contact.time = t;
    contact.mesh_a = mesh_a;
    contact.tri_a = tri_a;
    contact.mesh_b = mesh_b;
    contact.tri_b = tri_b;
    contact.feature = ContactFeature::Initial;
    record(contact);
    return true;
}

void TrianglePairTester::record(const Contact& contact) {
    const uint64_t k = key(contact.mesh_a, contact.tri_a, contact.mesh_b, contact.tri_b);
    auto it = found_.find(k);
    if (it == found_.end()) {
        found_.emplace(k, contacts_.size());
        contacts_.push_back(contact);
    } else if (contact_before(contact, contacts_[it->second])) {
        contacts_[it->second] = contact;
    }
}

std::vector<Contact> TrianglePairTester::sorted_contacts() const {
    std::vector<Contact> sorted = contacts_;
    std::sort(sorted.begin(), sorted.end(), contact_before);
    return sorted;
}

} // namespace usdksl
