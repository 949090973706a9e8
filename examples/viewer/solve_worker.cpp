// The solve on a worker thread (solve_worker.hpp).
#include "solve_worker.hpp"

#include <radiosity/solver/direct.hpp>
#include <radiosity/solver/gauss_seidel.hpp>
#include <radiosity/solver/jacobi.hpp>
#include <radiosity/solver/progressive.hpp>

#include <algorithm>
#include <chrono>

namespace radiosity::view {

namespace {

std::vector<Colour> colours(const std::vector<double>& v) {
    std::vector<Colour> out(v.size() / 3);
    for (std::size_t i = 0; i < out.size(); ++i)
        out[i] = Colour{float(v[3 * i]), float(v[3 * i + 1]), float(v[3 * i + 2])};
    return out;
}

/// The solver's settings from the program's options, as radiosity::solve sets them.
template <class Options>
Options settings(const radiosity::SolveOptions& o) {
    Options s;
    s.tolerance = o.tolerance;
    if (o.max_iterations > 0) s.max_iterations = o.max_iterations;
    return s;
}

}  // namespace

SolveWorker::SolveWorker(const Patches& patches)
    : patches_(patches), batch_(std::max<std::size_t>(1, patches.size() / 100)) {}

SolveWorker::~SolveWorker() {
    cancel();
    join();
}

void SolveWorker::join() {
    if (thread_.joinable()) thread_.join();
}

void SolveWorker::start(radiosity::SolverKind solver, bool paused) {
    cancel();
    join();
    std::lock_guard lock(mutex_);
    cancel_ = false;
    paused_ = paused;
    stepping_ = false;
    history_.clear();
    B_.clear();
    unshot_.clear();
    status_ = SolveStatus{};
    status_.solver = solver;
    status_.state = SolveState::running;
    snapshot_.radiosity = patches_.emission();  // B = E before the first shot or sweep
    snapshot_.unshot =
        solver == radiosity::SolverKind::progressive ? patches_.emission() : std::vector<Colour>{};
    snapshot_.iteration = 0;
    snapshot_.residual = 1.0;
    ++snapshot_.version;
    thread_ = std::thread([this, solver] { run(solver); });
}

void SolveWorker::run(radiosity::SolverKind solver) {
    const radiosity::System<Colour> system = patches_.system();
    const radiosity::ProgressCallback observer = [this](const radiosity::Progress& p) {
        return observe(p);
    };
    try {
        if (solver == radiosity::SolverKind::progressive) {
            auto shooting = settings<radiosity::ProgressiveOptions>(patches_.options());
            shooting.report_every = 1;  // the worker decides when to draw
            finish(patches_.visit([&](const auto& method) {
                return radiosity::Progressive(shooting).solve(system, method, observer);
            }));
        } else {
            finish(gather(solver, system, observer));
        }
    } catch (const radiosity::Cancelled&) {
        std::lock_guard lock(mutex_);
        end_locked(SolveState::cancelled);
    } catch (const std::exception& e) {
        std::lock_guard lock(mutex_);
        status_.error = e.what();
        end_locked(SolveState::failed);
    }
}

radiosity::Solution<Colour> SolveWorker::gather(radiosity::SolverKind solver,
                                                const radiosity::System<Colour>& system,
                                                const radiosity::ProgressCallback& observer) {
    const radiosity::SolveOptions& o = patches_.options();
    const std::shared_ptr<const radiosity::DenseMatrix> F = assembled(observer);
    switch (solver) {
        case radiosity::SolverKind::jacobi:
            return radiosity::Jacobi(settings<radiosity::JacobiOptions>(o))
                .solve(system, *F, observer);
        case radiosity::SolverKind::gauss_seidel:
            return radiosity::GaussSeidel(settings<radiosity::GaussSeidelOptions>(o))
                .solve(system, *F, observer);
        case radiosity::SolverKind::direct:
            return radiosity::Direct().solve(system, *F, observer);
        case radiosity::SolverKind::progressive:
        case radiosity::SolverKind::hierarchical:  // refused by the command line (view_args.cpp)
            break;
    }
    throw radiosity::Error("the worker gathers with Jacobi, Gauss-Seidel or the direct solve");
}

std::shared_ptr<const radiosity::DenseMatrix> SolveWorker::assembled(
    const radiosity::ProgressCallback& observer) {
    if (auto F = matrix()) {  // made by an earlier start
        std::lock_guard lock(mutex_);
        status_.form_factor_seconds = matrix_seconds_;
        return F;
    }
    {
        std::lock_guard lock(mutex_);
        status_.state = SolveState::form_factors;
    }
    const auto t0 = std::chrono::steady_clock::now();
    auto F = std::make_shared<const radiosity::DenseMatrix>(patches_.visit([&](const auto& method) {
        return radiosity::assemble_dense(method, patches_.size(), observer);
    }));
    std::lock_guard lock(mutex_);
    matrix_ = F;
    matrix_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    status_.form_factor_seconds = matrix_seconds_;
    status_.state = SolveState::running;  // until the first sweep's report
    return F;
}

bool SolveWorker::observe(const radiosity::Progress& p) {
    std::unique_lock lock(mutex_);
    if (cancel_) return false;
    status_.phase = std::string(p.phase);
    status_.fraction = p.fraction;
    if (p.radiosity.empty()) return true;  // form factors, or a solver without sweeps
    status_.iteration = p.iteration;
    status_.residual = p.residual;
    history_.push_back({p.iteration, p.residual});
    B_.assign(p.radiosity.begin(), p.radiosity.end());
    unshot_.assign(p.unshot.begin(), p.unshot.end());
    if ((stepping_ && p.iteration >= step_until_) || (pause_at_ > 0 && p.iteration >= pause_at_)) {
        paused_ = true;
        stepping_ = false;
        if (p.iteration >= pause_at_) pause_at_ = 0;
    }
    const bool shooting = !p.unshot.empty();
    if (paused_ || !shooting || p.iteration % batch_ == 0) publish_locked();
    if (paused_) status_.state = SolveState::paused;
    settled_.notify_all();
    wake_.wait(lock, [this] { return !paused_ || cancel_; });
    status_.state = SolveState::running;
    return !cancel_;
}

void SolveWorker::publish_locked() {
    snapshot_.radiosity = colours(B_);
    snapshot_.unshot = colours(unshot_);
    snapshot_.iteration = status_.iteration;
    snapshot_.residual = status_.residual;
    ++snapshot_.version;
}

void SolveWorker::finish(const radiosity::Solution<Colour>& solution) {
    std::lock_guard lock(mutex_);
    status_.report = solution.report;
    status_.iteration = solution.report.iterations;
    status_.residual = solution.report.residual;
    snapshot_.radiosity = solution.radiosity;
    // Shooting reports after every shot, so its last report holds the final unshot values.
    snapshot_.unshot = colours(unshot_);
    snapshot_.iteration = solution.report.iterations;
    snapshot_.residual = solution.report.residual;
    ++snapshot_.version;
    end_locked(solution.report.cancelled ? SolveState::cancelled : SolveState::done);
}

void SolveWorker::end_locked(SolveState state) {
    status_.state = state;
    paused_ = false;
    settled_.notify_all();
}

void SolveWorker::pause() {
    std::lock_guard lock(mutex_);
    if (status_.state == SolveState::running || status_.state == SolveState::form_factors)
        paused_ = true;
}

void SolveWorker::resume() {
    std::lock_guard lock(mutex_);
    paused_ = false;
    stepping_ = false;
    wake_.notify_all();
}

void SolveWorker::step() {
    std::lock_guard lock(mutex_);
    if (status_.state != SolveState::paused) return;
    const bool shooting = status_.solver == radiosity::SolverKind::progressive;
    stepping_ = true;
    step_until_ = status_.iteration + (shooting ? batch_ : 1);
    paused_ = false;
    wake_.notify_all();
}

void SolveWorker::cancel() {
    std::lock_guard lock(mutex_);
    cancel_ = true;
    wake_.notify_all();
}

void SolveWorker::set_batch(std::size_t shots) {
    std::lock_guard lock(mutex_);
    batch_ = std::max<std::size_t>(1, shots);
}

std::size_t SolveWorker::batch() const {
    std::lock_guard lock(mutex_);
    return batch_;
}

void SolveWorker::pause_at(std::size_t iteration) {
    std::lock_guard lock(mutex_);
    pause_at_ = iteration;
}

void SolveWorker::wait_settled() {
    std::unique_lock lock(mutex_);
    settled_.wait(lock, [this] {
        const SolveState s = status_.state;
        return s == SolveState::paused || s == SolveState::done || s == SolveState::cancelled ||
               s == SolveState::failed || s == SolveState::idle;
    });
}

std::optional<SolveSnapshot> SolveWorker::snapshot_after(std::uint64_t version) const {
    std::lock_guard lock(mutex_);
    if (snapshot_.version <= version) return std::nullopt;
    return snapshot_;
}

SolveStatus SolveWorker::status() const {
    std::lock_guard lock(mutex_);
    return status_;
}

std::vector<ResidualPoint> SolveWorker::history(std::size_t from) const {
    std::lock_guard lock(mutex_);
    if (from >= history_.size()) return {};
    return {history_.begin() + static_cast<std::ptrdiff_t>(from), history_.end()};
}

std::shared_ptr<const radiosity::DenseMatrix> SolveWorker::matrix() const {
    std::lock_guard lock(mutex_);
    return matrix_;
}

}  // namespace radiosity::view
