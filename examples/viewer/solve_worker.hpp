#pragma once
/// @file solve_worker.hpp  The solve on a thread of its own, watched as it goes: progressive
/// shooting reports after every shot and a gathering solver after every sweep (through the
/// library's progress callback, which carries the solver's current B), so the picture can follow
/// the light as it spreads. The callback is also where the solve pauses: while paused, the
/// solver's thread waits inside it; a step lets one batch of shots (or one sweep) through.

#include "patches.hpp"

#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solve.hpp>

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace radiosity::view {

/// Where a solve stands.
enum class SolveState { idle, form_factors, running, paused, done, cancelled, failed };

/// The values at one moment of the solve, for drawing.
struct SolveSnapshot {
    std::vector<Colour> radiosity;  ///< B of every patch
    std::vector<Colour> unshot;     ///< shooting's unshot dB (for the ambient term); else empty
    std::size_t iteration = 0;      ///< shots or sweeps done
    double residual = 1.0;          ///< unshot power over emitted power, or the sweep's change
    std::uint64_t version = 0;      ///< grows with every snapshot
};

/// One point of the convergence plot: the residual after so many shots or sweeps.
struct ResidualPoint {
    std::size_t iteration = 0;
    double residual = 0.0;
};

/// What the panels say about the solve.
struct SolveStatus {
    SolveState state = SolveState::idle;
    radiosity::SolverKind solver = radiosity::SolverKind::progressive;
    std::string phase;                 ///< the library's phase ("form factors", "solve")
    double fraction = 0.0;             ///< how far through the phase
    std::size_t iteration = 0;         ///< shots or sweeps done
    double residual = 1.0;             ///< at the last report
    radiosity::Report report;          ///< the solver's report, once done
    double form_factor_seconds = 0.0;  ///< assembling F (gathering solvers)
    std::string error;                 ///< why it failed
};

/// A solve of the patches on a worker thread (see the file comment). All members may be
/// called from the viewer's thread while the solve runs.
class SolveWorker {
  public:
    /// A worker for these patches (which must outlive it); nothing runs until start().
    explicit SolveWorker(const Patches& patches);
    ~SolveWorker();
    SolveWorker(const SolveWorker&) = delete;
    SolveWorker& operator=(const SolveWorker&) = delete;

    /// Starts a solve from B = E with the given solver, ending any solve under way. A gathering
    /// solver first assembles F (once: later starts reuse it); shooting takes rows on demand,
    /// as the `radiosity` program does. paused: stop at the first report.
    void start(radiosity::SolverKind solver, bool paused = false);
    void pause();   ///< holds the solve at its next report
    void resume();  ///< lets a paused solve go on
    void step();    ///< lets a paused solve run one batch of shots (or one sweep), then pause
    void cancel();  ///< stops the solve (it keeps the values reached)
    /// Shots between snapshots (and per step) of progressive shooting, at least 1.
    void set_batch(std::size_t shots);
    std::size_t batch() const;  ///< shots per snapshot
    /// Pauses the solve once it has done this many shots or sweeps (0: never).
    void pause_at(std::size_t iteration);
    /// Waits until the solve is paused, done, cancelled or failed.
    void wait_settled();

    /// The latest snapshot, if it is newer than the given version.
    std::optional<SolveSnapshot> snapshot_after(std::uint64_t version) const;
    SolveStatus status() const;  ///< where the solve stands
    /// The convergence history from point `from` on.
    std::vector<ResidualPoint> history(std::size_t from = 0) const;
    /// The assembled matrix, once a gathering solver has made it; else null.
    std::shared_ptr<const radiosity::DenseMatrix> matrix() const;

  private:
    void run(radiosity::SolverKind solver);
    radiosity::Solution<Colour> gather(radiosity::SolverKind solver,
                                       const radiosity::System<Colour>& system,
                                       const radiosity::ProgressCallback& observer);
    std::shared_ptr<const radiosity::DenseMatrix> assembled(
        const radiosity::ProgressCallback& observer);
    bool observe(const radiosity::Progress& p);
    void publish_locked();
    void finish(const radiosity::Solution<Colour>& solution);
    void end_locked(SolveState state);
    void join();

    const Patches& patches_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;     // the solver's thread waits on it while paused
    std::condition_variable settled_;  // the viewer's thread waits on it in wait_settled
    std::thread thread_;
    bool cancel_ = false, paused_ = false, stepping_ = false;
    std::size_t step_until_ = 0, pause_at_ = 0, batch_ = 1;
    SolveStatus status_;
    SolveSnapshot snapshot_;
    std::vector<double> B_, unshot_;  // the solver's values at its last report
    std::vector<ResidualPoint> history_;
    std::shared_ptr<const radiosity::DenseMatrix> matrix_;
    double matrix_seconds_ = 0.0;
};

}  // namespace radiosity::view
