#pragma once
/// @file options.hpp  The settings of hierarchical radiosity (hierarchical.hpp), of its
/// checkpoints (distributed/checkpoint.hpp) and what a solve reports of its hierarchy.

#include <cstddef>
#include <cstdint>
#include <string>

namespace radiosity {

class Communicator;

/// Checkpoints of a long hierarchical solve: its whole state written to a file now and then, so
/// that a killed process or a lost node costs only the work since the last one.
struct CheckpointOptions {
    std::string file;             ///< write checkpoints here (atomically); empty: none
    double every_seconds = 60.0;  ///< at least this long between two; 0: at every safe point
    std::string resume;           ///< continue from this checkpoint; empty: start afresh
};

/// Settings of hierarchical radiosity.
struct HierarchicalOptions {
    /// BF refinement's threshold as a share of the scene's emitted power: a link is refined
    /// while it would move more than link_error times sum_i E_i A_i (rho_r B_s T_rs A_r).
    double link_error = 1e-4;
    /// Elements split only into children of at least this area; 0: the scene's area / 10^6.
    double min_area = 0.0;
    int rays = 4;             ///< visibility rays per link of two elements (a square number)
    int cluster_samples = 4;  ///< sample pairs, one ray each, per link with a cluster
    /// A link whose rays find it partly visible (a shadow's edge crosses the pair) is refined
    /// while it would move more than link_error / shadow_factor of the emitted power, judged on
    /// its transfer without visibility: shadows get finer links than light that varies smoothly.
    double shadow_factor = 4.0;
    int max_depth = 24;  ///< deepest element level below an input face
    /// Multigrid passes before the final threshold, each refined at coarse_factor times the
    /// next one's threshold against the B of the pass before (the first against E and the
    /// ambient term): one is enough for the final refinement to see where light goes (more add
    /// links that the next pass refines again).
    int coarse_passes = 1;
    /// How much coarser each multigrid pass's threshold is than the next one's. The coarse pass
    /// has to show the final one where the light goes; without it every room3 mean comes out 1.3
    /// to 3.6% bright. With the oracle's oriented clusters, 16 against 4: room3 11% slower than
    /// under the isotropic oracle instead of 13% (alternating runs against commit 82a4615, 2
    /// cores), with the same per-material means over seeds 1 to 8 (medians within 0.2%); the
    /// million-triangle box (bench_hierarchy million) at link error 3e-6 within 0.43% of its
    /// few faces on every surface instead of 0.67% (0.81% of their converged solution instead
    /// of 1.15%), in 2.4 GB instead of 2.9 GB; at 1e-4 7.9% instead of 6.2% (its sampling alone
    /// moves that by more: at 340,000 triangles the worst surface was 4.4% and 8.3% off at
    /// seeds 1 and 2). Under the isotropic oracle, 16 had left its darkest face 26% off.
    double coarse_factor = 16.0;
    /// Refine -> solve rounds at the final threshold, until no link splits (a second round
    /// adds a quarter more links for a change in B far below the link error).
    int max_final_passes = 1;
    std::uint64_t seed = 1;  ///< base seed of the links' rays
    /// Sample points per element at which its exposure is tested (exposure.hpp: the share of
    /// its area from which the scene is seen), each with up to 4 rays; 0: every element counts
    /// as wholly exposed (then light leaks into faces hidden under others).
    int exposure_samples = 16;
    /// Rays per leaf (a square number, at most 256) that test whether faces' fronts enclose it,
    /// its row sum then 1 (exposure.hpp: element_enclosed); the sweeps of the final passes
    /// scale an enclosed leaf's irradiance so that its links' row sum is 1 (scale_row_sums,
    /// gather.hpp). 0: no test, the links' own row sums, which beside shared edges exceed 1 (a
    /// furnace of reflectance 0.9 came out 6.6% bright).
    int enclosure_rays = 64;
    /// Largest memory for nodes and links, in bytes; 0: half the physical memory. Refinement
    /// that would pass it stops with an Error naming what to change.
    std::size_t max_bytes = 0;
    CheckpointOptions checkpoint{};  ///< where and how often to checkpoint, what to resume
    /// The ranks to spread the solve over (distributed/mpi.hpp); null: this process alone. The
    /// radiosities are the same, bit for bit, for any number of ranks.
    Communicator* communicator = nullptr;
};

/// What the hierarchy holds at the end of a solve, and where the time went.
struct HierarchyReport {
    std::size_t input_faces = 0;  ///< faces of the patch mesh solved (the roots' sources)
    std::size_t roots = 0;        ///< root elements (faces, polygons split into triangles)
    std::size_t clusters = 0;     ///< cluster nodes
    std::size_t elements = 0;     ///< element nodes (roots and their descendants)
    std::size_t leaves = 0;       ///< leaf elements: the result's patches
    std::size_t links = 0;        ///< links at the end (all ranks')
    std::size_t bytes = 0;        ///< memory of nodes, values and links (this rank's)
    std::size_t passes = 0;       ///< refinement passes
    double refine_seconds = 0.0;  ///< time spent refining (transfers and rays)
    /// Of refine_seconds: judging and evaluating this rank's links (the rest: splitting, the
    /// exchanges of a round and waiting on the other ranks).
    double link_seconds = 0.0;
    /// Of refine_seconds: inside the collectives of the refinement (its rounds', the
    /// re-partition's, a checkpoint's), mostly waiting for the slowest rank (0 on one rank).
    double refine_wait_seconds = 0.0;
    double solve_seconds = 0.0;      ///< time spent gathering, exchanging and pushing-pulling
    double gather_seconds = 0.0;     ///< of solve_seconds: gathering over this rank's links
    double exchange_seconds = 0.0;   ///< of solve_seconds: the per-sweep exchange
    double push_pull_seconds = 0.0;  ///< of solve_seconds: push-pull
    /// Of solve_seconds: finding the links' class shares for the sweeps (class_shares).
    double share_seconds = 0.0;
    int ranks = 1;  ///< processes the solve was spread over
    /// Bytes this rank received in the last sweep's exchange (0 on one rank).
    std::uint64_t exchange_bytes_per_sweep = 0;
    std::uint64_t bytes_received = 0;  ///< bytes this rank received from the others in all
    /// Load imbalance: the busiest rank's time judging, evaluating and gathering links over
    /// the mean (1: balanced; waiting on the others not counted).
    double imbalance = 1.0;
    /// Leaves of the last pass whose links' estimated row sum was impossible (rho g >= 1) and
    /// was held to 1 because the pass's sweeps ran away (scale_row_sums, gather.hpp); 0 unless
    /// they did, as in most scenes.
    std::size_t held_rows = 0;
    /// Enclosed leaves of the last pass, whose irradiance was scaled to a row sum of 1
    /// (HierarchicalOptions::enclosure_rays).
    std::size_t scaled_rows = 0;
    /// ||R G||_inf of the last pass's sweeps (max over leaves of rho_max s g): a bound on their
    /// contraction where below 1; sampled rows past 1 / rho at a few leaves put it above.
    double row_norm = 0.0;
    /// The contraction q the last pass's sweeps stopped by: row_norm, or where that is 1 or
    /// more the weighted max norm's (stopping.hpp); 1 or more where neither gave a bound (then
    /// the largest of the last three observed contractions stood in).
    double contraction = 1.0;
    std::size_t checkpoints = 0;  ///< checkpoints written
    bool resumed = false;         ///< continued from CheckpointOptions::resume
    /// Links per element.
    double links_per_element() const { return elements ? double(links) / double(elements) : 0.0; }
};

}  // namespace radiosity
