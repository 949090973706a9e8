#pragma once
/// @file solve_loop.hpp  The loop of a hierarchical solve (hierarchical.hpp): multigrid passes of
/// refine -> gather -> push-pull, on one rank or spread over several (each refining and
/// gathering the receivers it owns, distributed/partition.hpp; every rank holding the nodes and
/// B), with checkpoints at the points where the state is whole: after each refinement round and
/// after each sweep. The state is flat arrays (the elements split, in order; B; the links), so a
/// checkpoint is those arrays, and a resumed solve replays the splits and goes on to the same
/// bits as one never stopped.

#include <radiosity/distributed/checkpoint.hpp>
#include <radiosity/distributed/communicator.hpp>
#include <radiosity/distributed/exchange.hpp>
#include <radiosity/distributed/partition.hpp>
#include <radiosity/error.hpp>
#include <radiosity/form_factor/budget.hpp>
#include <radiosity/hierarchy/exposure.hpp>
#include <radiosity/hierarchy/gather.hpp>
#include <radiosity/hierarchy/options.hpp>
#include <radiosity/hierarchy/refine.hpp>
#include <radiosity/hierarchy/stopping.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solver/session.hpp>
#include <radiosity/solver/system.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace radiosity::detail {

/// Where a solve stands besides its nodes, B and links: the rest of what a checkpoint holds.
struct SolveState {
    std::uint32_t pass = 0;       ///< multigrid pass
    std::uint32_t iterating = 0;  ///< 0: refining the pass; 1: sweeping it
    std::uint64_t sweep = 0;      ///< sweeps of this pass done
    std::uint64_t sweeps = 0;     ///< sweeps over all passes (Report::iterations)
    std::uint64_t passes = 0;     ///< refinement passes finished
    double previous = std::numeric_limits<double>::infinity();  ///< last sweep's change
    double first = 0.0;                                         ///< first sweep's bound
    std::array<double, 3> ratio{1.0, 1.0, 1.0};       ///< the last three observed contractions
    std::uint64_t splits = 0, settled = 0, open = 0;  ///< RefineRound's counts
    std::uint32_t sweeps_done = 0;                    ///< 1: this pass's sweeps have met their rule
    std::uint32_t converged = 0;                      ///< the last sweep's Report::converged
    /// 1: this pass's sweeps ran away and its impossible row sums are held (scale_row_sums)
    std::uint32_t held = 0;
    std::uint32_t unused = 0;  ///< (keeps the layout free of padding: it is written as bytes)
    double residual = 0.0;     ///< the last sweep's Report::residual
    double error_bound = std::numeric_limits<double>::infinity();  ///< and its error bound
};

/// Tags of a checkpoint's sections.
enum CheckpointTag : std::uint32_t {
    tag_state = 1,
    tag_splits = 2,
    tag_B = 3,
    tag_B_max = 4,
    tag_done = 5,
    tag_frontier = 6
};

/// The state of a hierarchical solve for K bands: the nodes, their values, this rank's links.
template <std::size_t K>
class HierarchySolve {
  public:
    HierarchySolve(const HierarchySolve&) = delete;  // comm_ may point at its own serial_
    HierarchySolve& operator=(const HierarchySolve&) = delete;
    HierarchySolve(Hierarchy h, const HierarchicalOptions& o)
        : h_(std::move(h)), o_(o), comm_(o.communicator ? o.communicator : &serial_) {
        cost_.assign(h_.roots.size(), 0);
        // First estimate of the work per root: its area (finer quadtrees, more links).
        std::vector<double> c(h_.roots.size());
        const double mean = h_.area[0] / double(c.size());
        for (std::size_t i = 0; i < c.size(); ++i)
            c[i] = 1.0 + h_.roots.area(h_.order[i]) / (mean > 0.0 ? mean : 1.0);
        partition_ = Partition(c.size(), comm_->size(), c);
    }

    /// Sets E and rho of every root (from its face, by callback) and the clusters' rho_max.
    template <class Material>
    void set_materials(Material&& material) {
        v_.extend(h_, h_.size());
        for (NodeId n = 0; n < h_.size(); ++n)
            if (!h_.is_cluster(n))
                material(h_.surface[h_.root_of(n)], &v_.E[n * K], &v_.rho[n * K]);
        for (std::size_t i = h_.size(); i-- > 0;) {
            double r = 0.0;
            if (h_.is_cluster(NodeId(i)))
                for (NodeId c = h_.first_child[i]; c < h_.first_child[i] + 2; ++c)
                    r = std::max(r, v_.rho_max[c]);
            else
                for (std::size_t k = 0; k < K; ++k) r = std::max(r, v_.rho[i * K + k]);
            v_.rho_max[i] = r;
            for (std::size_t k = 0; k < K; ++k) v_.B[i * K + k] = v_.E[i * K + k];
        }
        std::vector<double> scratch;
        std::fill(v_.H.begin(), v_.H.end(), 0.0);
        push_pull(h_, v_, scratch);  // B = E at the leaves, means above
        // One walk over the roots (the only elements yet): the emitted power, the link error's
        // scale, and the area sums of E and rho that the ambient term takes.
        emitted_ = 0.0;
        std::array<double, K> E{}, rho{};
        double area = 0.0;
        for (NodeId n = 0; n < h_.size(); ++n)
            if (!h_.is_cluster(n)) {
                double e = 0.0;
                for (std::size_t k = 0; k < K; ++k) {
                    e = std::max(e, v_.E[n * K + k]);
                    E[k] += h_.area[n] * v_.E[n * K + k];
                    rho[k] += h_.area[n] * v_.rho[n * K + k];
                }
                emitted_ += e * h_.area[n];
                area += h_.area[n];
            }
        floor_by_ambient(E, rho, area);
    }

    /// Measures exposure (exposure.hpp) from now on: `points` sample points per element, rays
    /// through `scene`; the roots at once, each new leaf when a refinement pass ends. 0 points:
    /// every node counts as wholly exposed. The leaves' enclosure tests (refresh_enclosure) take
    /// their rays through `scene` too.
    void set_exposure(const Bvh& scene, int points, std::uint64_t seed) {
        exposure_scene_ = &scene;
        exposure_points_ = points;
        exposure_seed_ = seed;
        measured_.assign(h_.size(), 0);
        refresh_exposure();
    }

    /// Runs the passes (hierarchical.hpp's file comment) under `tolerance`, from the start or
    /// from o.checkpoint.resume.
    template <Visibility V>
    Report run(const V& scene, double tolerance, std::size_t max_iterations,
               const ProgressCallback& progress, HierarchyReport& hr) {
        Report report;
        report.solver = "hierarchical";
        hash_ = scene_hash(tolerance, max_iterations);
        last_checkpoint_ = std::chrono::steady_clock::now();
        bool resumed_in_refinement = false;
        if (!o_.checkpoint.resume.empty()) {
            resumed_in_refinement = resume(o_.checkpoint.resume);
            hr.resumed = true;
            report.converged = state_.converged != 0;
            report.residual = state_.residual;
            report.error_bound = state_.error_bound;
        } else if (h_.size() > 1 && partition_.owner(h_, 0) == comm_->rank()) {
            links_.push_back({0, 0, 0.0f, 1.0f});  // the top cluster's self-link
        }
        RefineSettings s = settings();
        const auto passes = std::uint32_t(o_.coarse_passes + o_.max_final_passes);
        for (; state_.pass < passes; ++state_.pass, state_.iterating = 0) {
            const bool final = state_.pass >= std::uint32_t(o_.coarse_passes);
            s.threshold =
                o_.link_error * emitted_ *
                std::pow(o_.coarse_factor, final ? 0 : o_.coarse_passes - int(state_.pass));
            if (!state_.iterating) {
                const auto t0 = std::chrono::steady_clock::now();
                const double waited = comm_->collective_seconds();
                if (!resumed_in_refinement) begin_pass();
                resumed_in_refinement = false;
                refine(scene, s, progress);
                hr.refine_wait_seconds += comm_->collective_seconds() - waited;
                links_ = std::move(round_.done);
                state_.splits = round_.splits;
                round_ = RefineRound{};
                hr.refine_seconds += seconds_since(t0);
                state_ = next_sweeps(state_);
                if (final && (state_.splits == 0 || state_.pass + 1 == passes)) drop_dark_links();
            }
            refresh_exposure();  // the pass's new leaves (or, resumed, the replayed ones)
            if (final) refresh_enclosure();
            const auto t0 = std::chrono::steady_clock::now();
            if (!state_.sweeps_done)  // (a checkpoint taken after the pass's last sweep)
                iterate(scene, final ? tolerance : std::max(tolerance, 1e-2), max_iterations,
                        progress, report, hr);
            hr.solve_seconds += seconds_since(t0);
            if (report.cancelled) break;
            if (final && state_.splits == 0) break;
        }
        report.iterations = state_.sweeps;
        finish_report(hr);
        return report;
    }

    const Hierarchy& hierarchy() const { return h_; }   ///< the nodes
    const LinkVector& links() const { return links_; }  ///< this rank's, by receiver
    const NodeValues<K>& values() const { return v_; }  ///< E, rho, B, H per node
    /// Bytes of nodes, values and this rank's links.
    std::size_t bytes() const {
        // Per link its class shares if any (ClassShares, and those sampled in this pass so
        // far); per node E, rho, B, H, push-pull's total and rho_max, B_max, exposure,
        // row_scale, and the stopping rule's weight where it has one; per mixed cluster Hc, Bc, S
        // and push-pull's `down` (the classes and the rest); per top node its index among the
        // mixed.
        return h_.bytes() + links_.capacity() * sizeof(Link) +
               (shares_.entries.capacity() + sampled_shares_.capacity()) * sizeof(ClassShares) +
               shares_.begin.capacity() * sizeof(std::size_t) +
               h_.size() * (5 * K + 4) * sizeof(double) +
               v_.S.size() / facing_classes * ((3 * K + 1) * facing_classes + K) * sizeof(double) +
               v_.mixed.size() * sizeof(NodeId) + norm_.weight.capacity() * sizeof(double);
    }
    /// A hash of everything that decides the result: the roots' geometry and materials and the
    /// options; a checkpoint carries it, and is refused by a run whose hash differs.
    std::uint64_t scene_hash(double tolerance, std::size_t max_iterations) const {
        Fnv1a f;
        f.add_value(std::uint64_t(K));
        for (std::size_t r = 0; r < h_.roots.size(); ++r)
            for (const Vec3& p : h_.roots.polygon(r)) f.add_value(p);
        f.add(h_.surface.data(), h_.surface.size() * sizeof(std::uint32_t));
        for (NodeId n = 0; n < h_.size() && n < v_.E.size() / K; ++n)
            if (!h_.is_cluster(n) && h_.depth[n] == 0)
                for (std::size_t k = 0; k < K; ++k) {
                    f.add_value(v_.E[n * K + k]);
                    f.add_value(v_.rho[n * K + k]);
                }
        for (const double x :
             {o_.link_error, o_.min_area, tolerance, o_.shadow_factor, o_.coarse_factor})
            f.add_value(x);
        for (const int x : {o_.rays, o_.cluster_samples, o_.max_depth, o_.coarse_passes,
                            o_.max_final_passes, o_.exposure_samples, o_.enclosure_rays})
            f.add_value(x);
        f.add_value(o_.seed);
        f.add_value(std::uint64_t(max_iterations));
        return f.value();
    }

  private:
    /// Before the first solve the oracle knows only E, so every source that does not emit
    /// looks black to it: the first pass would keep the top cluster links that carry all of
    /// the indirect light, judged on nothing and estimated from a few samples each, and the
    /// next pass refine from the B those give (on room3 the brightest leaf after the first
    /// pass was 0.56 or 1.06 by the seed, the final links 218,000 to 328,000). So until then
    /// each node's B_max is at least the ambient term of progressive refinement (Cohen, Chen,
    /// Wallace & Greenberg 1988) for it: rho_max H with H = E_mean / (1 - rho_mean) per band,
    /// means by area over the roots, the irradiance of a closed scene of that reflectance
    /// (B_mean = E_mean + rho_mean B_mean), its reflectance taken at most 0.95: the term
    /// with_ambient (solver/progressive.hpp) adds for display, here of E instead of the
    /// unshot radiosity. Open scenes get less light than that: the first pass then refines a
    /// little more than it needs. E and rho: sums of A E and A rho over the roots, area theirs.
    void floor_by_ambient(const std::array<double, K>& E, const std::array<double, K>& rho,
                          double area) {
        if (!(area > 0.0)) return;
        double H = 0.0;  // the ambient irradiance, largest over the bands
        for (std::size_t k = 0; k < K; ++k)
            H = std::max(H, E[k] / area / (1.0 - std::min(rho[k] / area, 0.95)));
        for (NodeId n = 0; n < h_.size(); ++n)
            v_.B_max[n] = std::max(v_.B_max[n], v_.rho_max[n] * H);
    }

    RefineSettings settings() const {
        RefineSettings s;
        s.min_area = o_.min_area > 0.0 ? o_.min_area : h_.area[0] * 1e-6;
        s.max_depth = o_.max_depth;
        s.rays = o_.rays;
        s.cluster_samples = o_.cluster_samples;
        s.shadow_factor = o_.shadow_factor;
        s.seed = o_.seed;
        return s;
    }

    /// After the last refinement: drops the links that carry nothing, a cluster link whose
    /// samples found no transfer or a link whose rays were all blocked (44% of the links of
    /// room3). They were kept while another pass could judge them again (a dropped link takes
    /// its pair's light out for good); the sweeps would add 0 B for each, so B keeps its bits.
    void drop_dark_links() {
        std::erase_if(links_,
                      [](const Link& l) { return l.coefficient == 0.0f || l.visibility == 0.0f; });
        links_.shrink_to_fit();
    }

    /// The class shares known on this rank, sorted by pair (link_order): the last table's
    /// (sorted already) merged with those the refinement sampled since (which it then forgets).
    std::vector<ClassShares> known_shares() {
        std::vector<ClassShares> sampled = std::move(sampled_shares_);
        sampled_shares_ = {};
        sort_by_pair(sampled);
        std::vector<ClassShares> known(sampled.size() + shares_.entries.size());
        std::merge(sampled.begin(), sampled.end(), shares_.entries.begin(), shares_.entries.end(),
                   known.begin(), [](const ClassShares& a, const ClassShares& b) {
                       return pair_key(a.receiver, a.source) < pair_key(b.receiver, b.source);
                   });
        return known;
    }

    /// Forgets the sweeps of this pass so far, for the stopping rule: their count, the last
    /// change, the first bound and the observed contractions.
    static void forget_sweeps(SolveState& st) {
        st.sweep = 0;
        st.previous = std::numeric_limits<double>::infinity();
        st.first = 0.0;
        st.ratio = {1.0, 1.0, 1.0};
    }

    /// The state at the start of a pass's sweeps.
    static SolveState next_sweeps(SolveState st) {
        st.iterating = 1;
        st.sweeps_done = 0;
        st.held = 0;
        st.passes += 1;
        forget_sweeps(st);
        return st;
    }

    /// Starts a pass: re-partitions the receivers by the work measured in the last pass (the
    /// links move to their new owners: one all-to-all), and puts every link in the frontier.
    void begin_pass() {
        if (comm_->size() > 1 && state_.pass > 0) {
            comm_->sum_in_place(cost_);
            std::vector<double> c(cost_.size());
            for (std::size_t i = 0; i < c.size(); ++i) c[i] = 1.0 + double(cost_[i]);
            partition_ = Partition(c.size(), comm_->size(), c);
            std::vector<LinkVector> send(std::size_t(comm_->size()));
            for (const Link& l : links_)
                send[std::size_t(partition_.owner(h_, l.receiver))].push_back(l);
            links_ = all_to_all(*comm_, send);
        }
        std::fill(cost_.begin(), cost_.end(), 0);
        round_ = RefineRound{};
        round_.frontier = std::move(links_);
        links_.clear();
        std::array<std::uint64_t, 1> open{round_.frontier.size()};
        comm_->sum_in_place(open);
        round_.open = open[0];
    }

    /// 1 if a checkpoint is due on this rank's clock.
    double checkpoint_due() const {
        if (o_.checkpoint.file.empty()) return 0.0;
        return seconds_since(last_checkpoint_) >= o_.checkpoint.every_seconds ? 1.0 : 0.0;
    }

    template <Visibility V>
    void refine(const V& scene, const RefineSettings& s, const ProgressCallback& progress) {
        RefineShare share{*comm_, partition_, cost_, split_log_};
        share.shares = &sampled_shares_;
        // Links live in a round about three times over (settled or to be judged, the round's
        // tasks, their evaluations), each vector up to twice its size as it grows: what the
        // memory limit leaves after the nodes allows so many.
        const std::size_t limit = o_.max_bytes ? o_.max_bytes : default_matrix_limit();
        share.max_links = limit > bytes() ? (limit - bytes()) / (6 * sizeof(Link)) : 0;
        auto inputs = [this] { return OracleInputs{v_.rho_max, v_.B_max}; };
        auto added = [this](std::size_t from) { extend_nodes(from); };
        // After each round: progress, and a checkpoint if one is due or the user stops (both
        // decided alike on every rank: the maximum over the ranks).
        auto round_done = [&](const RefineRound& r) {
            const double settled = double(r.settled) / double(r.settled + r.open + 1);
            if (!detail::report(progress, "refine", settled)) stop_ = true;
            std::array<double, 2> c{checkpoint_due(), stop_ ? 1.0 : 0.0};
            comm_->max_in_place(c);
            if (c[0] > 0.0 || (c[1] > 0.0 && !o_.checkpoint.file.empty())) save();
            return c[1] == 0.0;
        };
        refine_links(h_, scene, round_, s, inputs, added, share, round_done);
        compute_seconds_ += share.compute_seconds;
    }

    /// Measures the exposure of the element leaves not measured yet (measure_fresh), and sets
    /// every node with children to its children's mean. Cost: the fresh leaves' rays, divided
    /// among the ranks; O(nodes).
    void refresh_exposure() {
        if (exposure_scene_ == nullptr || exposure_points_ <= 0) return;
        open_.resize(h_.size(), 0);
        const bool any = measure_fresh(
            measured_,
            [&](std::span<const NodeId> nodes) {
                return element_exposures(h_, *exposure_scene_, exposure_points_, exposure_seed_,
                                         nodes);
            },
            [&](NodeId n, const ElementExposure& e) {
                v_.exposure[n] = e.share;
                open_[n] = e.open;
            });
        if (any) mean_exposure(h_, v_.exposure);
    }

    /// Tests the element leaves not tested yet for enclosure (element_enclosed; measure_fresh):
    /// the sweeps scale an enclosed leaf's irradiance to a row sum of 1 (scale_row_sums). Only
    /// in the final passes: the coarse ones only show the oracle where light goes, and most of
    /// their leaves are split again. A leaf whose exposure rays met open space or a back is not
    /// enclosed without more rays. Cost: up to enclosure_rays closest-hit queries per fresh
    /// leaf that exposure did not find open, divided among the ranks.
    void refresh_enclosure() {
        if (exposure_scene_ == nullptr || o_.enclosure_rays <= 0) return;
        open_.resize(h_.size(), 0);  // (0, unknown, without exposure)
        measure_fresh(
            enclosure_tested_,
            [&](std::span<const NodeId> nodes) {
                return elements_enclosed(h_, *exposure_scene_, o_.enclosure_rays, exposure_seed_,
                                         nodes, open_);
            },
            [&](NodeId n, std::uint8_t enclosed) { v_.enclosed[n] = enclosed; });
    }

    /// Measures f of the element leaves not flagged in `measured`, each rank an equal share of
    /// them (the values gathered to all), hands each to store(node, value) and flags them.
    /// f(nodes) gives one value per node, a pure function of the node and the seed, so the
    /// values never depend on the ranks or threads. Returns whether any leaf was measured.
    template <class F, class Store>
    bool measure_fresh(std::vector<std::uint8_t>& measured, const F& f, const Store& store) {
        measured.resize(h_.size(), 0);
        std::vector<NodeId> fresh;
        for (NodeId n = 0; n < h_.size(); ++n)
            if (!measured[n] && !h_.is_cluster(n) && h_.is_leaf(n)) fresh.push_back(n);
        if (fresh.empty()) return false;
        const std::size_t ranks = std::size_t(comm_->size()), me = std::size_t(comm_->rank());
        const std::size_t first = fresh.size() * me / ranks, last = fresh.size() * (me + 1) / ranks;
        const auto got =
            all_gather(*comm_, f(std::span<const NodeId>(fresh).subspan(first, last - first)));
        for (std::size_t i = 0; i < fresh.size(); ++i) {
            store(fresh[i], got[i]);
            measured[fresh[i]] = 1;
        }
        return true;
    }

    /// Gives nodes [from, size) their parent's values; refuses a hierarchy past the memory
    /// limit.
    void extend_nodes(std::size_t from) {
        const std::size_t limit = o_.max_bytes ? o_.max_bytes : default_matrix_limit();
        v_.extend(h_, from);
        if (bytes() > limit)
            throw Error("hierarchical radiosity: the hierarchy would need more than " +
                        std::to_string(limit / 1000000) + " MB (" + std::to_string(h_.size()) +
                        " nodes); raise --link-error or --min-area, or the limit (--max-memory)");
    }

    /// Gather, exchange and push-pull until the bound on the error of B meets the tolerance.
    /// The bound is the sweeping solvers' (session.hpp), q / (1 - q) times the last change,
    /// with q = ||R G||_inf of the sweeps' operator (row_sums) where that is below 1, or else
    /// ||R G||_w of a weighted max norm in which the changes are then measured (stopping.hpp:
    /// sampled row sums scatter past 1 / rho at some leaves, room3's and the Cornell box's do);
    /// relative to the largest reflected radiosity (reflected_size), not to the lamps. Where no
    /// weights give a q below 1 either, q is the largest of the last three observed contractions
    /// change_k / change_k-1, an estimate rather than a bound, which the guard backs (2
    /// sweeps_needed + 10 at that q, at most 1000). (That estimate had stopped the Cornell box's
    /// few faces at seed 1 after 4 sweeps: 0.34 over the first three, while the sweeps went on
    /// contracting by 0.65, and 0.4 to 0.6% dark.) Sweeps that run away (runs_away) are held
    /// and start again (hold_and_restart).
    template <Visibility V>
    void iterate(const V& scene, double tolerance, std::size_t cap,
                 const ProgressCallback& progress, Report& report, HierarchyReport& hr) {
        const LinkGroups groups = group_links(links_);
        // The class shares of the links with a mixed cluster at an end: from the refinement's
        // samples and the last pass's table; sampled again where neither has them (a link
        // sampled on another rank, a solve resumed from a checkpoint).
        const auto t_shares = std::chrono::steady_clock::now();
        shares_ = group_shares(
            groups, class_shares(h_, scene, links_, o_.cluster_samples, o_.seed, known_shares()));
        hr.share_seconds += seconds_since(t_shares);
        ReceiverExchange exchange(*comm_, groups);
        std::vector<double> total, down;
        const double emission = *std::max_element(v_.E.begin(), v_.E.end());
        v_.clear_irradiance();      // the links changed: gathers write their receivers' only
        facing_areas(h_, v_);       // the exposure may have changed with them
        levels_ = node_levels(h_);  // for push-pull's threads: the pass's nodes by level
        // Bc from B under these S (a resumed solve has B from its checkpoint only).
        pull(h_, v_, &levels_);
        row_sums(groups, exchange, total, down, state_.held != 0, hr);
        for (;;) {
            auto t = std::chrono::steady_clock::now();
            gather_links(h_, links_, groups, shares_, v_);
            hr.gather_seconds += seconds_since(t);
            t = std::chrono::steady_clock::now();
            std::array<double, 2> control{checkpoint_due(), stop_ ? 1.0 : 0.0};
            control = share_irradiance(groups, exchange, control);
            hr.exchange_seconds += seconds_since(t);
            hr.exchange_bytes_per_sweep = exchange.last_bytes();
            t = std::chrono::steady_clock::now();
            const double change = push_pull(h_, v_, total, down, &levels_,
                                            norm_.weight.empty() ? nullptr : &norm_.weight);
            hr.push_pull_seconds += seconds_since(t);
            if (!state_.held && runs_away(emission, change) &&
                hold_and_restart(groups, exchange, total, down, hr)) {
                ++state_.sweeps;
                continue;
            }
            check_divergence(change, emission);
            const bool done = sweep_done(change, tolerance, cap, progress, report);
            // One process decides after the sweep (a stop beats convergence, as in the other
            // solvers); several ranks on the words exchanged before it, alike on every rank. A
            // checkpoint taken after the pass's last sweep says so (sweeps_done), so that a
            // resumed run goes on to the next pass as this one would.
            if (comm_->size() == 1) control = {checkpoint_due(), stop_ ? 1.0 : 0.0};
            if (control[0] > 0.0 || (control[1] > 0.0 && !o_.checkpoint.file.empty())) save();
            if (control[1] > 0.0) {
                report.cancelled = true;
                return;
            }
            if (done) return;
        }
    }

    /// With several ranks, hands each receiver's H (and a mixed cluster's Hc) from the rank
    /// that gathered it to every rank, with the sweep's control words (the largest over the
    /// ranks comes back); one process has them all already. One exchange.
    std::array<double, 2> share_irradiance(const LinkGroups& groups, ReceiverExchange& exchange,
                                           std::array<double, 2> control) {
        if (comm_->size() == 1) return control;
        constexpr std::size_t C = facing_classes * K, width = K + C;
        std::vector<double>& mine = exchange_scratch_;
        mine.resize(groups.receivers.size() * width);
        for (std::size_t g = 0; g < groups.receivers.size(); ++g) {
            const NodeId r = groups.receivers[g];
            double* out = &mine[g * width];
            std::copy_n(&v_.H[r * K], K, out);
            if (v_.is_mixed(r))
                std::copy_n(&v_.Hc[v_.mixed[r] * C], C, out + K);
            else
                std::fill_n(out + K, C, 0.0);
        }
        return exchange.share(mine, width, control, [&](NodeId r, const double* in) {
            std::copy_n(in, K, &v_.H[r * K]);
            if (v_.is_mixed(r)) std::copy_n(in + K, C, &v_.Hc[v_.mixed[r] * C]);
        });
    }

    /// The row sums g of the pass's operator, and the leaves' scales (scale_row_sums), from one
    /// sweep's gather and push with every node and class sending B = 1 (B and Bc kept aside and put
    /// back; H and Hc are the next gather's to overwrite); with `hold`, the impossible ones held.
    /// Sets norm_, the stopping rule's norm and contraction, exact for the operator the sweeps
    /// then apply (weigh_contraction, stopping.hpp). Cost: one sweep, and where ||R G||_inf >= 1
    /// a few more.
    void row_sums(const LinkGroups& groups, ReceiverExchange& exchange, std::vector<double>& total,
                  std::vector<double>& down, bool hold, HierarchyReport& hr) {
        std::vector<double> B(v_.B.size(), 1.0), Bc(v_.Bc.size(), 1.0);
        sweep_from(B, Bc, groups, exchange, total, down);
        const HeldRows held = scale_row_sums(h_, v_, total, hold);
        norm_ = ContractionNorm{{}, held.norm};
        if (held.norm >= 1.0)
            norm_ = weigh_contraction(h_, leaf_rows(h_, v_, total), held.norm,
                                      [&](const std::vector<double>& w) {
                                          return unit_rows(groups, exchange, w, total, down);
                                      });
        hr.held_rows = held.held;
        hr.scaled_rows = held.scaled;
        hr.row_norm = held.norm;
        hr.contraction = norm_.q;
    }

    /// One sweep's gather, exchange and push from the radiosities B and Bc of every node and
    /// class instead of the solution's, E left out: `total` then holds each node's pushed
    /// irradiance. B and Bc are swapped in and back; H and Hc are the next gather's to
    /// overwrite. Cost: one sweep.
    void sweep_from(std::vector<double>& B, std::vector<double>& Bc, const LinkGroups& groups,
                    ReceiverExchange& exchange, std::vector<double>& total,
                    std::vector<double>& down) {
        std::swap(B, v_.B);
        std::swap(Bc, v_.Bc);
        gather_links(h_, links_, groups, shares_, v_);
        share_irradiance(groups, exchange, {0.0, 0.0});
        push(h_, v_, total, down, &levels_);
        std::swap(B, v_.B);
        std::swap(Bc, v_.Bc);
    }

    /// M w at the leaves (leaf_rows, stopping.hpp): sweep_from B = w (every band) at the
    /// leaves, pulled up to the clusters and their classes (B_max, which pull also sets, put
    /// back). Cost: one sweep.
    std::vector<double> unit_rows(const LinkGroups& groups, ReceiverExchange& exchange,
                                  const std::vector<double>& w, std::vector<double>& total,
                                  std::vector<double>& down) {
        std::vector<double> B(v_.B.size(), 0.0), Bc(v_.Bc.size(), 0.0), B_max = v_.B_max;
        for (NodeId i = 0; i < h_.size(); ++i)
            if (h_.is_leaf(i)) std::fill_n(&B[i * K], K, w[i]);
        std::swap(B, v_.B);
        std::swap(Bc, v_.Bc);
        pull(h_, v_, &levels_);
        std::swap(B, v_.B);
        std::swap(Bc, v_.Bc);
        v_.B_max = std::move(B_max);
        sweep_from(B, Bc, groups, exchange, total, down);
        return leaf_rows(h_, v_, total);
    }

    /// Whether the sweeps run away: the brightest leaf past E_max / (1 - rho_max), which bounds
    /// every solution of B = E + rho F B whose row sums are at most 1 (and every sweep from
    /// below it: B' <= E_max + rho_max ||B||), and the change growing, in this sweep (`change`)
    /// and the three before. Links whose estimated row sums pass 1 / rho at some leaves
    /// (scale_row_sums) get there; but the bound alone is passed by mere noise too (a furnace of
    /// rho 0.9 with two blocks, 18,520 triangles, sampled once per cluster link: leaves at 1.7
    /// to 2.4 times its exact B at every seed, with the walls' mean within 4% of it), where the
    /// sweeps converge and holding would bias them (the walls came out 7.6 to 10.1% dark). Never
    /// with a reflectance of 1 or more (no bound: check_divergence stops those).
    bool runs_away(double emission, double change) const {
        const double rho = v_.rho_max[0];  // the largest reflectance of any leaf
        const auto growing = [](double ratio) { return ratio > 1.0; };
        return rho < 1.0 && v_.B_max[0] > emission / (1.0 - rho) && change > state_.previous &&
               std::all_of(state_.ratio.begin(), state_.ratio.end(), growing);
    }

    /// Sweeps of a pass that ran away start again with the impossible row sums held
    /// (row_sums): from B = E at the leaves, the contraction's history forgotten. Returns
    /// false, and the sweeps go on as they are, if no row sum is impossible. The sweeps made
    /// count in Report::iterations.
    bool hold_and_restart(const LinkGroups& groups, ReceiverExchange& exchange,
                          std::vector<double>& total, std::vector<double>& down,
                          HierarchyReport& hr) {
        state_.held = 1;
        row_sums(groups, exchange, total, down, true, hr);
        if (hr.held_rows == 0) return false;
        v_.clear_irradiance();
        push_pull(h_, v_, total, down, &levels_);  // H = 0: B = E at the leaves, means above
        forget_sweeps(state_);
        return true;
    }

    /// Throws if the sweeps diverge (detail::diverged, every solver's rule): a radiosity no
    /// longer finite, or the brightest leaf past 1e9 times the brightest emission (`emission`,
    /// any band). No solution of B = E + rho F B
    /// with rho < 1 comes near (||B|| <= ||E|| / (1 - rho_max)), and sweeps that run away are
    /// held below that first (hold_and_restart); only a reflectance of 1 or more grows B so
    /// now, and what the sweeps make of it must not be handed on. (Before the rows were held,
    /// the million-triangle box at seed 3 grew so, through 1,000 sweeps to radiosities past
    /// 1e300.)
    void check_divergence(double change, double emission) const {
        if (std::isfinite(change) && !detail::diverged(v_.B_max[0], emission)) return;
        throw Error("hierarchical radiosity: the solution diverged after sweep " +
                    std::to_string(state_.sweeps + 1) +
                    " (a radiosity past 1e9 times the brightest emission, or not finite): a "
                    "reflectance of 1 or more makes light grow at every bounce");
    }

    /// After a sweep: the stopping rule and progress; true when the pass's sweeps are done.
    bool sweep_done(double change, double tolerance, std::size_t cap,
                    const ProgressCallback& progress, Report& report) {
        SolveState& st = state_;
        const std::size_t it = st.sweep++;
        ++st.sweeps;
        st.ratio[it % 3] =
            st.previous > 0.0 && std::isfinite(st.previous) ? change / st.previous : 1.0;
        st.previous = change;
        const double q_seen = *std::max_element(st.ratio.begin(), st.ratio.end());
        const double q = norm_.q < 1.0 ? norm_.q : (it >= 3 ? q_seen : 1.0);
        const StoppingRule rule = StoppingRule::sweeps(tolerance, q, cap);
        // The change and the bound relative to the largest reflected radiosity (stopping.hpp);
        // the change in the sweeps' norm, weighted where ||R G||_inf >= 1 (so residual too).
        const double size = reflected_size(h_, v_);
        report.residual = size > 0.0 ? change / size : change;
        report.error_bound = rule.bound(change, size);
        report.converged = rule.met(report.error_bound);
        st.converged = report.converged ? 1 : 0;
        st.residual = report.residual;
        st.error_bound = report.error_bound;
        if (it == 0) st.first = report.error_bound;
        report.iterations = st.sweeps;
        Progress pr{"solve", rule.fraction(st.first, report.error_bound), report.residual,
                    report.iterations};
        if (!detail::report(progress, pr)) stop_ = true;
        const bool done =
            report.converged || it + 1 >= std::min<std::size_t>(rule.max_iterations, 1000);
        st.sweeps_done = done ? 1 : 0;
        return done;
    }

    /// Writes a checkpoint: every rank's links gathered at rank 0, which writes the file.
    void save() {
        const bool refining = state_.iterating == 0;
        if (refining) {
            state_.splits = round_.splits;
            state_.settled = round_.settled;
            state_.open = round_.open;
        }
        const LinkVector done = gather_to_first(*comm_, refining ? round_.done : links_);
        const LinkVector frontier =
            gather_to_first(*comm_, refining ? round_.frontier : LinkVector{});
        if (comm_->rank() == 0) {
            CheckpointWriter w;
            w.add_value(tag_state, state_);
            w.add<NodeId>(tag_splits, split_log_);
            w.add<double>(tag_B, v_.B);
            w.add<double>(tag_B_max, v_.B_max);
            w.add<Link>(tag_done, done);
            w.add<Link>(tag_frontier, frontier);
            w.write(o_.checkpoint.file, hash_);
        }
        ++checkpoints_;
        last_checkpoint_ = std::chrono::steady_clock::now();
    }

    /// Continues from a checkpoint: rank 0 reads it, every rank replays its splits and takes B
    /// and its own links. Returns whether it was taken inside a refinement pass.
    bool resume(const std::string& file);

    /// The totals over the ranks: links, and the load imbalance of refine + gather.
    void finish_report(HierarchyReport& hr) {
        hr.ranks = comm_->size();
        const std::vector<double> t =
            all_gather(*comm_, std::vector<double>{compute_seconds_ + hr.gather_seconds});
        double sum = 0.0, worst = 0.0;
        for (double x : t) sum += x, worst = std::max(worst, x);
        hr.imbalance = sum > 0.0 ? worst / (sum / double(t.size())) : 1.0;
        std::array<std::uint64_t, 1> links{links_.size()};
        comm_->sum_in_place(links);
        hr.links = links[0];
        hr.bytes_received = comm_->bytes_received();
        hr.checkpoints = checkpoints_;
        hr.passes = state_.passes;
        hr.link_seconds = compute_seconds_;
    }

    Hierarchy h_;
    HierarchicalOptions o_;
    SerialCommunicator serial_;
    Communicator* comm_;
    Partition partition_;
    std::vector<std::uint64_t> cost_;  // per position of the cluster order, this pass
    NodeValues<K> v_;
    LinkVector links_;
    GroupShares shares_;                       // of links_, for the sweeps (class_shares)
    std::vector<ClassShares> sampled_shares_;  // sampled by this rank's refinement since
    RefineRound round_;
    SolveState state_;
    std::vector<NodeId> split_log_;
    double emitted_ = 0.0;
    ContractionNorm norm_;                  // the sweeps' norm and contraction in it (row_sums)
    std::vector<double> exchange_scratch_;  // share_irradiance's, kept from sweep to sweep
    NodeLevels levels_;                     // the pass's nodes by level (iterate)
    const Bvh* exposure_scene_ = nullptr;   // rays for exposure (set_exposure); null: none
    int exposure_points_ = 0;
    std::uint64_t exposure_seed_ = 0;
    std::vector<std::uint8_t> measured_;          // per node: exposure measured (element leaves)
    std::vector<std::uint8_t> enclosure_tested_;  // per node: enclosure tested (element leaves)
    std::vector<std::uint8_t> open_;  // per node: its exposure rays met open space or a back
    double compute_seconds_ = 0.0;    // judging and evaluating links, this rank
    std::uint64_t hash_ = 0;
    std::size_t checkpoints_ = 0;
    bool stop_ = false;  // the progress callback asked to stop (acted on at the next safe point)
    std::chrono::steady_clock::time_point last_checkpoint_;
};

template <std::size_t K>
bool HierarchySolve<K>::resume(const std::string& file) {
    // Rank 0 reads and checks the file; the others learn its verdict first, so a refused
    // checkpoint ends every rank with the same message instead of leaving them waiting.
    std::string error;
    std::vector<SolveState> state;
    std::vector<NodeId> splits;
    std::vector<double> B, B_max;
    LinkVector done, frontier;
    if (comm_->rank() == 0) try {
            const CheckpointReader r(file, hash_);
            state = {r.value<SolveState>(tag_state)};
            splits = r.get<NodeId>(tag_splits);
            B = r.get<double>(tag_B);
            B_max = r.get<double>(tag_B_max);
            done = r.get<Link, LinkVector::allocator_type>(tag_done);
            frontier = r.get<Link, LinkVector::allocator_type>(tag_frontier);
            // What only rank 0 can check (the others see the data after it): sizes and ids
            // against the node count that replaying the splits will give.
            const std::size_t nodes = h_.size() + 4 * splits.size();
            if (B.size() != nodes * K || B_max.size() != nodes)
                throw Error("checkpoint " + file + ": its radiosities do not fit its hierarchy");
            for (const auto* links : {&done, &frontier})
                for (const Link& l : *links)
                    if (l.receiver >= nodes || l.source >= nodes)
                        throw Error("checkpoint " + file + ": a link names a node it lacks");
        } catch (const Error& e) {
            error = e.what();
        }
    const std::vector<char> message =
        all_gather(*comm_, std::vector<char>(error.begin(), error.end()));
    if (!message.empty()) throw Error(std::string(message.begin(), message.end()));
    state = all_gather(*comm_, state);
    splits = all_gather(*comm_, splits);
    B = all_gather(*comm_, B);
    B_max = all_gather(*comm_, B_max);
    const std::size_t before = h_.size();
    for (const NodeId n : splits) {
        if (n >= h_.size() || h_.is_cluster(n) || !h_.is_leaf(n))
            throw Error("checkpoint " + file + ": its splits do not fit this scene's hierarchy");
        split_element(h_, n);
    }
    extend_nodes(before);
    split_log_ = std::move(splits);
    v_.B = std::move(B);
    v_.B_max = std::move(B_max);
    state_ = state.at(0);
    // Each link to the rank that owns its receiver.
    const auto deal = [&](const LinkVector& links) {
        std::vector<LinkVector> send(std::size_t(comm_->size()));
        for (const Link& l : links)
            send[std::size_t(partition_.owner(h_, l.receiver))].push_back(l);
        return all_to_all(*comm_, send);
    };
    done = deal(done);
    frontier = deal(frontier);
    if (state_.iterating) {
        sort_links(done);
        links_ = std::move(done);
        return false;
    }
    round_.done = std::move(done);
    round_.frontier = std::move(frontier);
    round_.splits = state_.splits;
    round_.settled = state_.settled;
    round_.open = state_.open;
    return true;
}

}  // namespace radiosity::detail
