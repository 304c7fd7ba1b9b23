#include "usdksl/collision/check.hpp"

#include "raw_sample_confirmation.hpp"
#include "time_windows.hpp"
#include "window_schedule.hpp"

#include "usdksl/broad_phase/baselines.hpp"
#include "usdksl/kinetic/separation_list.hpp"
#include "usdksl/run_on_threads.hpp"
#include "usdksl/scene/scene.hpp"
#include "usdksl/scene/triangle_pair_tester.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>

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
    const auto triangle_in_range = [&](int32_t mesh, int32_t tri) {
        return mesh >= 0 && mesh < static_cast<int32_t>(meshes.size()) && tri >= 0 &&
               tri < static_cast<int32_t>(meshes[static_cast<size_t>(mesh)].triangles.size());
    };
    for (const auto& [mesh_a, tri_a, mesh_b, tri_b] : options.settled_pairs) {
        if (!triangle_in_range(mesh_a, tri_a) || !triangle_in_range(mesh_b, tri_b)) {
            throw std::invalid_argument("settled triangle pair out of range");
        }
    }
}

/// Time windows per thread planned for a method that cannot cut a running
/// window short (brute force): more windows than threads balance uneven work
/// at the cost of one set-up per window.
constexpr int32_t WINDOWS_PER_THREAD_UNCUT = 4;

int32_t resolve_threads(int32_t requested) {
    if (requested > 0) return requested;
    return std::max(1, static_cast<int32_t>(std::thread::hardware_concurrency()));
}

/// Thrown in a window's thread once another window's progress call raised (a
/// stop request): every thread unwinds at its next progress call instead of
/// finishing its window.
struct WindowCancelled {};

/// True when the method honours WindowStop, so a running window can be cut.
bool cuts_windows(Method method) { return method != Method::BruteForce; }

/// Runs body(window) for every window the schedule hands out, on `threads`
/// threads; a thread left without a window calls when_idle() before it ends.
template <typename Body, typename WhenIdle>
void check_windows_in_parallel(int32_t threads, WindowSchedule& schedule, Body body, WhenIdle when_idle) {
    run_on_threads<ScheduledWindow*, WindowCancelled>(
        threads,
        [&](ScheduledWindow*& window) {
            if ((window = schedule.next()) != nullptr) return true;
            when_idle();
            return false;
        },
        [&](ScheduledWindow* window) {
            body(*window);
            schedule.finish(*window);
        },
        [&]() { schedule.cancel(); });
}

/// Runs one method over [t_begin, t_end] on `scene`, recording candidates in
/// `tester`; a method that honours `stop` may end early (see WindowStop).
void run_method(const Scene& scene, const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                const CheckOptions& options, TrianglePairTester& tester, Counters& counters,
                WindowStop* stop = nullptr) {
    switch (options.method) {
    case Method::KineticSeparationList: {
        KineticSeparationLists lists(scene, mesh_pairs, tester, counters, options);
        lists.run(options.progress, stop);
        break;
    }
    case Method::SweptVolume:
        run_swept_volume(scene, mesh_pairs, options, tester, counters, stop);
        break;
    case Method::Discrete:
        run_discrete(scene, mesh_pairs, options, tester, counters, stop);
        break;
    case Method::BruteForce:
        run_brute_force(scene, mesh_pairs, options, tester, stop);
        break;
    }
}

void add_counters(Counters& total, const Counters& part) {
    total.kinetic_tree_events += part.kinetic_tree_events;
    total.bv_overlap_events += part.bv_overlap_events;
    total.fathers_do_not_overlap_events += part.fathers_do_not_overlap_events;
    total.leaves_do_not_overlap_events += part.leaves_do_not_overlap_events;
    total.plane_kept_steps += part.plane_kept_steps;
    total.polygons_collide_events += part.polygons_collide_events;
    total.bv_change_events += part.bv_change_events;
    total.bv_tests += part.bv_tests;
    total.narrow_phase_tests += part.narrow_phase_tests;
    total.cleared_steps += part.cleared_steps;
    total.primitive_queries += part.primitive_queries;
    total.reused_queries += part.reused_queries;
    total.undecided_queries += part.undecided_queries;
    total.raw_confirmations += part.raw_confirmations;
    total.raw_rejections += part.raw_rejections;
    total.time_windows += part.time_windows;
}

/// Joins the progress of windows checked at once into one callback, called
/// with the total time covered (added to the range start) and all contacts.
class WindowProgress {
public:
    WindowProgress(const ProgressCallback& user, const WindowSchedule& schedule, double t_begin)
        : user_(user), schedule_(schedule), t_begin_(t_begin) {}
    ProgressCallback for_window(ScheduledWindow& window) {
        if (!user_) return {};
        return [this, &window](double t, int64_t contacts) {
            std::lock_guard<std::mutex> lock(mutex_);
            if (cancelled_) throw WindowCancelled{};
            window.progress_time = t;
            window.progress_contacts = contacts;
            double covered = 0.0;
            int64_t total = 0;
            schedule_.for_each([&](const ScheduledWindow& w) {
                // A window cut short may have run past its new end: that time is counted once.
                covered += std::clamp(w.progress_time, w.begin, std::max(w.begin, w.end)) - w.begin;
                total += w.progress_contacts;
            });
            try {
                user_(t_begin_ + covered, total);
            } catch (...) {
                cancelled_ = true;
                throw;
            }
        };
    }

private:
    const ProgressCallback& user_;
    const WindowSchedule& schedule_;
    const double t_begin_;
    std::mutex mutex_;
    std::atomic<bool> cancelled_{false};
};

/// Earliest contact per triangle pair over all windows (the earlier window on
/// equal times), sorted by contact_before.
std::vector<Contact> merge_windows(const std::vector<std::vector<Contact>>& per_window) {
    std::vector<std::pair<Contact, size_t>> all;
    for (size_t w = 0; w < per_window.size(); ++w) {
        for (const Contact& c : per_window[w]) all.emplace_back(c, w);
    }
    const auto pair_then_time = [](const std::pair<Contact, size_t>& x, const std::pair<Contact, size_t>& y) {
        return std::tie(x.first.mesh_a, x.first.tri_a, x.first.mesh_b, x.first.tri_b, x.first.time, x.second) <
               std::tie(y.first.mesh_a, y.first.tri_a, y.first.mesh_b, y.first.tri_b, y.first.time, y.second);
    };
    std::sort(all.begin(), all.end(), pair_then_time);
    std::vector<Contact> merged;
    for (size_t i = 0; i < all.size(); ++i) {
        const Contact& c = all[i].first;
        if (i > 0) {
            const Contact& p = all[i - 1].first;
            if (p.mesh_a == c.mesh_a && p.tri_a == c.tri_a && p.mesh_b == c.mesh_b && p.tri_b == c.tri_b) continue;
        }
        merged.push_back(c);
    }
    std::sort(merged.begin(), merged.end(), contact_before);
    return merged;
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
    // Their candidates found on raw-sample steps carry that step's confirming
    // test (TrianglePairTester::carry_confirmations); the reference confirms
    // everything afresh, so it stays independent of that shortcut.
    const bool merge = options.method == Method::KineticSeparationList || options.method == Method::SweptVolume;
    const int32_t threads = resolve_threads(options.threads);
    const Scene scene(meshes, merge, threads, options.frames_per_time_code);
    const bool cuttable = cuts_windows(options.method);
    std::unique_ptr<WindowCuts> cuts;
    std::vector<TimeWindow> planned{{options.t_begin, options.t_end}};
    if (threads > 1) {
        cuts = std::make_unique<WindowCuts>(scene, mesh_pairs, options.t_begin, options.t_end);
        planned = cuttable ? split_into_windows(*cuts, threads, WindowSizes::Equal)
                           : split_into_windows(*cuts, threads * WINDOWS_PER_THREAD_UNCUT, WindowSizes::Falling);
    }
    if (planned.size() == 1) {
        result.counters.time_windows = 1;
        TrianglePairTester tester(scene, options.ccd, result.counters);
        if (merge) tester.carry_confirmations(confirming(options.ccd).tolerance);
        if (options.method != Method::BruteForce) tester.settle(options.settled_pairs);
        run_method(scene, mesh_pairs, options, tester, result.counters);
        // The discrete baseline answers at sampled instants; it stays what it is, misses included.
        // Candidates are confirmed in the order they were found (the
        // confirmed contacts come back sorted): no sorted copy of millions.
        result.contacts = options.method == Method::Discrete
                              ? tester.sorted_contacts()
                              : confirm_on_raw_samples(scene, tester.contacts(), options.ccd, options.t_begin,
                                                       options.t_end, result.counters, options.progress);
        return result;
    }
    // Windows are checked at once, each on its own copy of the scene (shared
    // flightplans, own cursors). Every reported time is computed on raw
    // sample steps, which a window tests exactly as a whole run does, so the
    // earliest contact per pair over the windows is the whole run's, wherever
    // the windows were cut. A window leaves alone the pairs that windows
    // beginning earlier have found (WindowFindings).
    WindowSchedule schedule(*cuts, planned, cuttable);
    WindowProgress progress(options.progress, schedule, options.t_begin);
    // Brute force, the reference, tests every pair in every window itself.
    WindowFindings findings;
    const bool share_findings = options.method != Method::BruteForce;
    // The discrete baseline answers at sampled instants; it stays what it is, misses included.
    const bool confirm = options.method != Method::Discrete;
    std::vector<FlightplanKind> checked_kinds(meshes.size(), FlightplanKind::Unused);
    for (const auto& [mesh_a, mesh_b] : mesh_pairs) checked_kinds[mesh_a] = checked_kinds[mesh_b] = FlightplanKind::RawSamples;
    std::unique_ptr<Scene> raw_scene;
    std::once_flag raw_scene_started;
    check_windows_in_parallel(threads, schedule, [&](ScheduledWindow& window) {
        const Scene local(scene);
        CheckOptions window_options = options;
        window_options.t_begin = window.begin;
        window_options.t_end = window.end;
        window_options.progress = progress.for_window(window);
        TrianglePairTester tester(local, options.ccd, window.counters);
        if (merge) tester.carry_confirmations(confirming(options.ccd).tolerance);
        if (share_findings) {
            tester.settle(options.settled_pairs);
            tester.share_findings(findings, findings.join(window.begin));
        }
        run_method(local, mesh_pairs, window_options, tester, window.counters, &window.stop);
        window.candidates = tester.sorted_contacts();
    }, [&]() {
        // The first thread left without a window builds the raw flightplans
        // the candidates are confirmed on while the others finish, for every
        // mesh a candidate can name; with none running, it is left for after.
        if (!confirm || !schedule.any_running()) return;
        std::call_once(raw_scene_started, [&]() {
            try {
                raw_scene = std::make_unique<Scene>(meshes, checked_kinds, 1);
            } catch (...) {
                raw_scene.reset();  // built again below, where a failure is reported
            }
        });
    });
    // Each window as far as it covered (stop.reached): a window cut short ends
    // where it stopped, at or after the begin of the window that took its rest.
    const std::vector<ScheduledWindow*> windows = schedule.in_time_order();
    const size_t count = windows.size();
    std::vector<std::vector<Contact>> confirmed(count);
    std::vector<FlightplanKind> kinds;
    for (const ScheduledWindow* window : windows) {
        add_counters(result.counters, window->counters);
        mark_meshes_to_confirm(scene, window->candidates, kinds);
    }
    if (confirm && !raw_scene &&
        std::any_of(kinds.begin(), kinds.end(), [](FlightplanKind k) { return k != FlightplanKind::Unused; })) {
        raw_scene = std::make_unique<Scene>(meshes, kinds, threads);
    }
    if (!confirm || !raw_scene) {
        for (size_t w = 0; w < count; ++w) confirmed[w] = windows[w]->candidates;
    } else {
        // Windows are confirmed in time order, each over all threads, every
        // candidate up to the check's end: a pair an earlier window decided
        // (its first raw contact from there on, or none) needs no confirming
        // in a later one (merging keeps the earliest), where a contact that
        // lasts, such as cloth resting on a table, would otherwise be
        // confirmed again.
        std::set<std::tuple<int32_t, int32_t, int32_t, int32_t>> decided_pairs;
        for (size_t w = 0; w < count; ++w) {
            std::vector<Contact> open;
            for (const Contact& c : windows[w]->candidates) {
                if (decided_pairs.insert({c.mesh_a, c.tri_a, c.mesh_b, c.tri_b}).second) open.push_back(c);
            }
            const int32_t chunks = static_cast<int32_t>(std::min<size_t>(static_cast<size_t>(threads), open.size()));
            std::vector<std::vector<Contact>> parts(static_cast<size_t>(chunks));
            std::vector<Counters> part_counters(static_cast<size_t>(chunks));
            parallel_for<WindowCancelled>(threads, chunks, [&](int32_t k) {
                std::vector<Contact> share;
                for (size_t i = static_cast<size_t>(k); i < open.size(); i += static_cast<size_t>(chunks)) {
                    share.push_back(open[i]);
                }
                const Scene raw_local(*raw_scene);
                // Up to the check's end, not the window's: a later window
                // may have left the pair to this one (WindowFindings). From
                // the check's begin, not the window's: a pair found at a
                // window's begin is tested on the raw steps around it as a
                // whole run tests it, not held still there, which only the
                // check's begin asks for (near the thickness the two answers
                // can differ within the narrow phase's tolerance).
                parts[k] = confirm_on_raw_scene(raw_local, share, options.ccd, options.t_begin, options.t_end,
                                                part_counters[k], progress.for_window(*windows[w]));
            });
            for (int32_t k = 0; k < chunks; ++k) {
                add_counters(result.counters, part_counters[k]);
                confirmed[w].insert(confirmed[w].end(), parts[k].begin(), parts[k].end());
            }
        }
    }
    result.counters.time_windows = static_cast<int64_t>(count);
    result.contacts = merge_windows(confirmed);
    return result;
}

} // namespace usdksl
