#pragma once
/// @file triangle_pair_tester.hpp
/// @brief Runs the shared narrow phase on triangle pairs over their flightplan
///        steps and keeps the first contact of each pair.

#include "usdksl/flat_hash_map.hpp"
#include "usdksl/ccd/ccd_settings.hpp"
#include "usdksl/ccd/vertex_face_memo.hpp"
#include "usdksl/narrow_phase/triangle_pair.hpp"
#include "usdksl/narrow_phase/pair_clearance.hpp"
#include "usdksl/scene/contact.hpp"
#include "usdksl/scene/counters.hpp"
#include "usdksl/scene/scene.hpp"
#include "usdksl/scene/window_findings.hpp"

#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

namespace usdksl {

/// @brief One linear step of a triangle pair: between consecutive breakpoints
///        of the union of its six vertices' flightplans (time codes).
struct PairStep {
    double begin;
    double end;
    bool valid() const { return end > begin; }
};

/// @brief Outcome of testing consecutive steps of one triangle pair.
struct StepRun {
    /// @brief End (time code) of the last step tested; +inf when the pair's
    ///        vertices all hold still after it, so no later step exists.
    double tested_until;
    /// @brief True when the pair needs no further test: a step had a contact
    ///        (recorded; the run stopped there), or a time window that begins
    ///        earlier found the pair (TrianglePairTester::share_findings).
    bool hit;
};

/// @brief Tests triangle pairs and records each pair's first contact. Every
///        method goes through it, so equal inputs give equal contact times.
///        The thickness of `settings` is the user's; each pair is tested at
///        the scene's contact distance for its two triangles (thickness plus
///        the slack of their own vertices' merged flightplans).
class TrianglePairTester {
public:
    TrianglePairTester(const Scene& scene, const CCDSettings& settings, Counters& counters);

    /// @brief The pair's step containing time code t ([begin, end) with
    ///        begin <= t < end); invalid when no vertex moves after t.
    PairStep step_containing(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b, double t) const;

    /// @brief True when the pair can never be reported: same triangle, same
    ///        authored face of one mesh, or already has its first contact
    ///        (here, or in a time window that begins earlier).
    bool settled(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b) const;

    /// @brief Continuous test over the whole step; records and returns true on contact.
    bool test_step(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b, const PairStep& step);

    /// @brief Tests the pair's steps in time order, from the one containing
    ///        time code `from` until one ends at or after `until`, stopping at
    ///        the first contact. Each step is tested exactly as test_step
    ///        tests step_containing(...) (bit-identical answers), but the
    ///        flightplan segments are walked with a local cursor. With
    ///        `use_clearance`, steps that a PairClearance certificate proves
    ///        out of reach are skipped (counted as cleared_steps). A `carried`
    ///        run whose valid_at equals `from` goes on from where the last
    ///        call left it; any other starts afresh; either way it is left
    ///        ready for a call from the returned tested_until. Past `until`
    ///        it goes on up to `ahead_until` (time code) while the certificate
    ///        clears steps, and stops before the first step it does not clear
    ///        (whose begin is then the returned tested_until).
    StepRun test_steps(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b, double from, double until,
                       bool use_clearance, ClearanceRun* carried = nullptr,
                       double ahead_until = -std::numeric_limits<double>::infinity());

    /// @brief From now on, each continuous contact found on a raw-sample
    ///        step (every position its vertex's raw sample, no merge slack)
    ///        carries the same pair's test of that step at `finer_tolerance`
    ///        (interval fraction; the raw-sample confirmation's), which
    ///        finer_triangle_pair_ccd works out from this test's searches
    ///        where they part from the finer ones: a fraction of a fresh
    ///        search's cost, the same answer.
    void carry_confirmations(double finer_tolerance);

    /// @brief Records the contact a candidate's carried confirmation gives
    ///        on `step` (the carried one) and returns whether it hit; counts
    ///        it as one narrow-phase test.
    bool apply_carried(const Contact& candidate, const PairStep& step);

    /// @brief Static test at time code t; records an Initial contact at t and returns true on contact.
    bool test_static(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b, double t);

    /// @brief Leaves alone `pairs` (mesh_a, tri_a, mesh_b, tri_b, either
    ///        order), whose first contacts a run over an earlier range found
    ///        (CheckOptions::settled_pairs), as pairs earlier windows found.
    void settle(const std::vector<std::array<int32_t, 4>>& pairs);
    /// @brief From now on, exchange_findings() publishes the pairs this
    ///        tester finds as the window in `slot` of `findings`, and takes
    ///        the pairs that windows beginning earlier found: settled here
    ///        (see WindowFindings for why that keeps the answer).
    void share_findings(WindowFindings& findings, int32_t slot);
    /// @brief Publishes the pairs found since the last call and takes those
    ///        earlier windows published meanwhile; nothing without
    ///        share_findings. Methods call it once per step.
    void exchange_findings();

    /// @brief A key naming the triangle pair, equal for both orders, unique within the scene.
    uint64_t key(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b) const;

    /// @brief The settings every pair is tested with (the user's thickness).
    const CCDSettings& settings() const { return settings_; }

    /// @brief First contacts found so far, in discovery order.
    const std::vector<Contact>& contacts() const { return contacts_; }
    /// @brief The contacts sorted by contact_before.
    std::vector<Contact> sorted_contacts() const;

private:
    static void canonical_order(int32_t& mesh_a, int32_t& tri_a, int32_t& mesh_b, int32_t& tri_b);
    /// The user's settings at the pair's contact distance (its own slack).
    CCDSettings settings_for(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b) const;
    /// Narrow phase of one canonically ordered pair over `step`, given the
    /// positions at its ends; records and returns true on contact.
    /// `raw_positions`: every position is its vertex's raw sample, as the
    /// raw-sample confirmation reads it (then a contact may carry its
    /// confirmation). `contact_distance` (scene units): the step's own, when
    /// its vertices' slack is known per segment; NaN: the pair's (settings_for).
    bool test_positions(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b, const PairStep& step,
                        const std::array<Vec3, 3>& a0, const std::array<Vec3, 3>& a1,
                        const std::array<Vec3, 3>& b0, const std::array<Vec3, 3>& b1, bool raw_positions,
                        double contact_distance = std::numeric_limits<double>::quiet_NaN());
    void record(const Contact& contact);
    /// Adds a narrow-phase answer's primitive queries (and whether it was
    /// undecided) to the counters.
    void count_queries(const TrianglePairContact& answer);
    /// The contact that `answer` (a hit on `step`) reports for the
    /// canonically ordered pair.
    static Contact contact_from(int32_t mesh_a, int32_t tri_a, int32_t mesh_b, int32_t tri_b, const PairStep& step,
                                const TrianglePairContact& answer);

    const Scene& scene_;
    CCDSettings settings_;
    Counters& counters_;
    std::vector<int64_t> triangle_offset_;
    FlatHashMap<uint64_t, size_t> found_;
    /// Pairs that time windows beginning earlier found (share_findings).
    FlatHashSet<uint64_t> found_earlier_;
    WindowFindings* findings_ = nullptr;
    int32_t findings_slot_ = -1;
    size_t contacts_published_ = 0;
    std::vector<size_t> findings_cursors_;
    std::vector<Contact> contacts_;
    /// Repeated vertex-face queries of this tester's narrow phase (a tester
    /// is used by one thread at a time).
    VertexFaceMemo vertex_face_memo_;
    /// Finer vertex-face answers of the carried confirmations.
    VertexFaceMemo finer_memo_;
    /// Set by carry_confirmations.
    std::unique_ptr<FinerReplay> finer_;
    double finer_tolerance_ = 0.0;
};

} // namespace usdksl
