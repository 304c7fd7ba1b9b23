#pragma once
/// @file separation_list.hpp
/// @brief Kinetic separation lists (paper section 5): the BVTT front of every
///        checked mesh pair (or mesh against itself), kept valid step by step.

#include "usdksl/flat_hash_map.hpp"
#include "usdksl/kinetic/chunked_vector.hpp"
#include "usdksl/kinetic/step_box_tree.hpp"
#include "usdksl/narrow_phase/pair_clearance.hpp"
#include "usdksl/narrow_phase/shared_vertex_clearance.hpp"
#include "usdksl/scene/check_options.hpp"
#include "usdksl/scene/scene.hpp"
#include "usdksl/scene/triangle_pair_tester.hpp"
#include "usdksl/scene/window_stop.hpp"

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace usdksl {

/// @brief How far (fraction of the smaller box's extent) two boxes must stay
///        apart over a whole step before a father pair replaces its children
///        in the front: boxes that touch and part every few frames would
///        otherwise expand and collapse the front each time.
constexpr double FRONT_HYSTERESIS = 1.0;

/// @brief How far (fraction of the smaller triangle's box extent) two leaf
///        boxes must stay apart over a whole step before their triangle pair
///        stops being covered by the narrow phase.
constexpr double LEAF_HYSTERESIS = 0.25;

/// @brief Steps between two looks at whether an entry's father stays apart.
///        Coarsening the front is never needed to find every contact (a finer
///        front finds the same ones), so each step looks at the fathers of
///        one entry in this many, spread by entry index.
constexpr int64_t FRONT_COARSEN_EVERY_STEPS = 8;

/// @brief Steps beyond the current one that an overlapping leaf pair's narrow
///        phase covers in the same call while its clearance certificate
///        clears them: one call per step would cost more than the steps.
constexpr int64_t LEAF_COVER_AHEAD_STEPS = 15;

/// @brief Relative allowance by which the per-step travel bounds are
///        inflated: covers the rounding of the displacements and their sums.
constexpr double TRAVEL_ROUNDING = 1e-9;

/// @brief Node ids of mesh_a's tree per table of a list's front index.
constexpr int32_t FRONT_INDEX_BLOCK_NODES = 4096;

/// @brief All separation lists of one check, sharing one tree per mesh. Each
///        list entry is a BVTT node: a pair of tree nodes whose boxes do not
///        meet (with the father it hangs from), or an overlapping pair of
///        leaves whose triangles the narrow phase tests on every flightplan
///        step while they keep overlapping. The front changes only where
///        flightplans bend, so it is brought up to date once per step between
///        consecutive breakpoints of the scene, all of that step's events
///        together: on a per-frame simulation cache every frame is a
///        breakpoint, and events one by one would cost a heap operation each;
///        on merged keyframes a step spans many frames.
class KineticSeparationLists {
public:
    /// @brief Lists over [options.t_begin, options.t_end] (time codes), their
    ///        boxes padded for options.ccd.thickness: the one value the tester
    ///        was built with too.
    KineticSeparationLists(const Scene& scene, const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                           TrianglePairTester& tester, Counters& counters, const CheckOptions& options);

    /// @brief Processes every step up to t_end (time codes), or, given a
    ///        `stop`, up to the first step boundary at or after its stop_at,
    ///        publishing each step's end in its `reached`.
    void run(const ProgressCallback& progress, WindowStop* stop = nullptr);

private:
    struct List {
        int32_t mesh_a;
        int32_t mesh_b;
        bool self;
        /// (a << 32 | b) -> entry, one table per block of FRONT_INDEX_BLOCK_NODES
        /// consecutive node ids of a: the entries an expansion creates lie in
        /// one subtree, whose ids run nearly consecutively, so they land in a
        /// table small enough to stay in cache instead of one scattered
        /// over the whole front (a miss per entry on a million faces).
        std::vector<FlatHashMap<uint64_t, int32_t>> index;
    };
    /// Ordered widest first: 48 bytes, and a front holds tens of entries per triangle.
    struct Entry {
        double tested_until = -1e300;  // end of the last flightplan step the narrow phase covered
        int32_t list = -1;
        int32_t a = -1, b = -1;      // tree nodes (mesh_a's tree, mesh_b's tree)
        int32_t fa = -1, fb = -1;    // BVTT father, -1 for the root pair
        int32_t quiet_until = 0;     // no step before this one can find work for it: boxes apart, a
                                     // plane sure to keep the pair apart, or an overlapping leaf pair
                                     // covered ahead up to that step
        int32_t certificate = -1;    // overlapping leaf pair: its ClearanceRun in clearance_runs_; pair kept
                                     // whole by a plane (plane_kept): its plane in kept_planes_; else -1
        bool overlapping_leaf = false;
        bool plane_kept = false;     // boxes meet, but a plane keeps every triangle pair beneath apart
        bool inert = false;          // leaf pair whose triangle pair is settled
        bool alive = false;
    };
    struct NodePair { int32_t a, b; };
    /// A plane that keeps two nodes apart over the step it was found on.
    struct NodePlane {
        Vec3 normal;        // unit, the vertices under b above those under a
        double gap = 0.0;   // scene units between them along it at the step's end
        int32_t step = -1;  // the step it was found on
    };
    /// A self leaf pair whose triangles share a vertex: its boxes overlap for
    /// the whole shot, so it leaves the front and its narrow phase follows
    /// the steps here, its certificate asked at the trees' step positions.
    struct SharedVertexPair {
        double tested_until;  // end (time code) of the last step the narrow phase or certificate covered
        SharedVertexClearance clearance;
        int32_t list;
        int32_t tri_a, tri_b;
        int32_t leaf_a, leaf_b;  // their leaves in the mesh's tree
        int8_t wait;     // steps to go before the next certificate
        int8_t backoff;  // steps to wait after the next one fails at once
        bool certified;  // a certificate is running
        bool fresh;      // it has not cleared a step yet
        bool static_pending;  // created at the window's begin: its static test is still to come
        bool static_hit;      // the static test found contact at the window's begin
    };

    // BVTT structure
    NodePair normalized(const List& list, int32_t a, int32_t b) const;
    bool father_of(const List& list, int32_t a, int32_t b, NodePair& father) const;
    int children_of(const List& list, int32_t a, int32_t b, NodePair out[4]) const;
    /// Moves `top` up its fathers while keeps(father) holds; returns whether
    /// `top` has a father left, then in `up` (the first that did not hold).
    template <class Keeps>
    bool climb(const List& list, NodePair& top, NodePair& up, Keeps&& keeps) const;
    bool both_leaves(const List& list, int32_t a, int32_t b) const;

    // Geometry of the current step
    /// Scene units two boxes (already grown by their rounding margins) grow
    /// by before they count as overlapping: the list's contact distance.
    double margin_of(const List& list) const;
    /// True when the boxes of (a, b) meet at some time of the current step;
    /// otherwise, given `quiet`, sets it to their quiet_until().
    bool meet(const List& list, int32_t a, int32_t b, int64_t* quiet = nullptr);
    /// True when the boxes of (a, b), grown by the list's contact distance,
    /// stay apart by more than `fraction` of the smaller one's extent for the
    /// whole current step.
    bool apart(const List& list, int32_t a, int32_t b, double fraction) const;
    /// First step after the current one at which the boxes ba and bb of
    /// nodes a (mesh_a's tree) and b (mesh_b's), apart at the current step's
    /// end, may meet: their gap then, against the most any vertex under
    /// either node moves per step (the trees' recorded travel), and beyond
    /// the recorded steps any vertex of their meshes (travel_).
    int64_t quiet_until(const List& list, int32_t a, int32_t b, const StepBox& ba, const StepBox& bb,
                        double margin) const;
    /// Fills travel_ for the steps in times_.
    void measure_travel();

    // Front maintenance
    /// Returns the entry, or -1 when the pair takes none: handed over
    /// (hand_over_if_sharing_vertex) or done with at once (see done_with).
    int32_t create_entry(int32_t list, int32_t a, int32_t b, const NodePair* father, bool overlapping_leaf);
    /// `keep_tested`: a leaf pair's tested_until is saved for its return.
    void remove_entry(int32_t id, bool keep_tested = true);
    /// True when nothing under the entry can ever need work again in the
    /// front: a settled (inert) leaf pair.
    bool done_with(const Entry& entry) const;
    /// True when (a, b) are self leaves whose triangles share a vertex: then
    /// the pair goes to shared_vertex_pairs_ (unless settled or covered to
    /// the window's end) and never into the front. Such leaves' boxes always
    /// meet, so their fathers do too and the pair never comes back.
    bool hand_over_if_sharing_vertex(int32_t list, int32_t a, int32_t b);
    /// tested_until saved for the leaf pair (a, b) when its entry left the
    /// front, taken out of leaf_tested_until_; -1e300 when none was saved.
    double take_saved_tested_until(const List& list, int32_t a, int32_t b);
    void expand(int32_t list, int32_t a, int32_t b);
    void remove_descendants(int32_t list, int32_t a, int32_t b);
    /// Brings one entry created in an earlier step up to the current step.
    void update(int32_t id);
    /// Runs the narrow phase on the leaf pair's flightplan steps that the
    /// current step reaches and were not tested yet.
    void cover(Entry& entry);
    /// Brings every pair of shared_vertex_pairs_ to the current step's end:
    /// its certificate clears the step, or the narrow phase tests it.
    void step_shared_vertex_pairs();
    /// At the window's begin, for an overlapping leaf pair: starts its
    /// clearance run there and returns true when that certificate holds at
    /// once, which proves what the static test would answer (no contact);
    /// otherwise leaves the run as new and returns false.
    bool clear_at_begin(Entry& entry);
    /// True when the pair's certificate (started, restarted or backing off
    /// as test_steps() schedules a ClearanceRun) clears the current step.
    bool clears_step(SharedVertexPair& pair);
    /// The steps after this one that a pair's certificate, having cleared
    /// this one, provably clears too, from how far the trees' recorded
    /// travel lets its corners move (its allowance): the index in times_ of
    /// the last one's end.
    size_t cleared_ahead(const SharedVertexPair& pair) const;
    /// The clearance certificate an overlapping leaf pair carries from one
    /// step to the next (allocated on first use).
    ClearanceRun& clearance_run(Entry& entry);
    void release_clearance_run(Entry& entry);
    bool share_vertex(int32_t mesh, int32_t tri_a, int32_t tri_b) const;
    /// The table of the list's front index that holds the pairs of node a.
    static FlatHashMap<uint64_t, int32_t>& index_of(List& list, int32_t a);
    /// Key of a leaf pair of `list` in leaf_tested_until_.
    uint64_t tester_key(const List& list, int32_t a, int32_t b) const;
    /// True, setting `plane`, when (a, b) of an inter-mesh list are small
    /// enough to look for a plane (NODE_PLANE_MAX_TRIANGLES) and one keeps
    /// their vertices apart beyond the narrow phase's reach over the current
    /// step (find_node_plane, trying `previous`'s normal first, when given:
    /// found on the step before, its gap is the gap at this step's begin).
    bool plane_separates(const List& list, int32_t a, int32_t b, const NodePlane* previous, NodePlane& plane) const;
    /// First step after the current one on which `plane` may stop keeping
    /// (a, b) apart (node_plane_quiet_until): the entry sleeps until then,
    /// as one whose boxes are apart does.
    int64_t plane_quiet_until(const List& list, int32_t a, int32_t b, const NodePlane& plane) const;
    /// Replaces the entry, its siblings and everything under its father by
    /// the highest ancestor pair a plane keeps apart, when its father is one;
    /// true then (the entry is gone).
    bool coarsen_to_plane(int32_t id);
    /// create_entry() for a pair `plane` keeps apart over the current step.
    void create_plane_kept_entry(int32_t list, int32_t a, int32_t b, const NodePair* father, const NodePlane& plane);
    /// Marks the entry kept by `plane` over the current step and lets it
    /// sleep while the plane is sure to keep it (plane_quiet_until).
    void keep_plane(int32_t id, const NodePlane& plane);
    void release_plane(Entry& entry);
    /// @brief Counts one unit of work; calls progress every kProgressEveryWork units.
    void worked();

    const Scene& scene_;
    TrianglePairTester& tester_;
    Counters& counters_;
    double t_begin_, t_end_;
    std::vector<double> times_;                 // breakpoint times: the steps' ends (time codes)
    /// Per used mesh: travel_[m][k] bounds (scene units) how far any of its
    /// vertices moves along any axis during steps 0..k-1 together.
    std::vector<std::vector<double>> travel_;
    size_t travel_recorded_ = 0;  // the trees recorded the travel of every step before this one
    double step_begin_ = 0.0, step_end_ = 0.0;  // current step (time codes)
    int64_t step_index_ = 0;
    bool initializing_ = false;
    const ProgressCallback* progress_ = nullptr;  // set while run() runs
    int64_t work_ = 0;                            // entries created and narrow-phase runs

    std::vector<std::unique_ptr<StepBoxTree>> trees_;  // per mesh, null when unused
    std::vector<List> lists_;
    ChunkedVector<Entry> entries_;
    std::vector<int32_t> free_entries_;
    /// Per entry slot: the first step whose update may find work for it
    /// (the step after the one it was last brought up to date in, or its
    /// quiet_until when later; never for a free slot). The steps scan this
    /// array, not the entries, most of which sleep or lie free.
    HugeVector<int32_t> wake_step_;
    std::vector<double> margin_;  // per list: contact distance of its two meshes
    /// tested_until of leaf pairs whose entry was removed from the front, so a
    /// pair that returns does not run its narrow phase on the same steps again.
    FlatHashMap<uint64_t, double> leaf_tested_until_;
    ChunkedVector<ClearanceRun> clearance_runs_;
    HugeVector<SharedVertexPair> shared_vertex_pairs_;
    std::vector<int32_t> free_clearance_runs_;
    std::vector<NodePlane> kept_planes_;  // of the entries kept by a plane, each as last found
    std::vector<int32_t> free_kept_planes_;
};

} // namespace usdksl
