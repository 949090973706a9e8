#pragma once
/// @file mpi.hpp  The Communicator over MPI (the MPI 3.1 standard's MPI_Allgatherv,
/// MPI_Alltoallv, MPI_Gatherv and MPI_Allreduce), for a hierarchical solve spread over the ranks
/// of an mpirun. Only this header includes <mpi.h>; build with -DRADIOSITY_WITH_MPI=ON, which
/// links MPI::MPI_CXX. MPI's default error handler stays: a failed collective (a rank that died)
/// ends the job rather than hanging it.

#include <radiosity/distributed/communicator.hpp>
#include <radiosity/config.hpp>
#include <radiosity/error.hpp>

#include <mpi.h>

#include <chrono>
#include <climits>
#include <cstdlib>
#include <string>
#include <vector>

namespace radiosity {

/// A Communicator on an MPI communicator (MPI_COMM_WORLD by default), which the caller has
/// initialised (MpiSession) and keeps alive.
class MpiCommunicator final : public Communicator {
  public:
    /// Wraps `comm` (not duplicated: the caller's collectives must not interleave with ours).
    explicit MpiCommunicator(MPI_Comm comm = MPI_COMM_WORLD) : comm_(comm) {
        MPI_Comm_rank(comm_, &rank_);
        MPI_Comm_size(comm_, &size_);
    }
    int rank() const override { return rank_; }
    int size() const override { return size_; }

    void allgather_bytes(std::span<const std::byte> mine, std::vector<std::byte>& all,
                         std::vector<std::size_t>& counts) override {
        const Timer timer(seconds_);
        const int n = count_of(mine.size());
        std::vector<int> c(nranks()), at(nranks());
        MPI_Allgather(&n, 1, MPI_INT, c.data(), 1, MPI_INT, comm_);
        const std::size_t total = offsets(c, at);
        all.resize(total);
        MPI_Allgatherv(mine.data(), n, MPI_BYTE, all.data(), c.data(), at.data(), MPI_BYTE, comm_);
        counts.assign(c.begin(), c.end());
        received_ += total - mine.size();
    }

    std::vector<std::byte> alltoall_bytes(const std::vector<std::vector<std::byte>>& send,
                                          std::vector<std::size_t>& counts) override {
        const Timer timer(seconds_);
        RADIOSITY_ASSERT(send.size() == std::size_t(size_));
        std::vector<int> sc(nranks()), sa(nranks()), rc(nranks()), ra(nranks());
        std::vector<std::byte> flat;
        for (int r = 0; r < size_; ++r) {
            sc[std::size_t(r)] = count_of(send[std::size_t(r)].size());
            sa[std::size_t(r)] = count_of(flat.size());
            flat.insert(flat.end(), send[std::size_t(r)].begin(), send[std::size_t(r)].end());
        }
        MPI_Alltoall(sc.data(), 1, MPI_INT, rc.data(), 1, MPI_INT, comm_);
        std::vector<std::byte> out(offsets(rc, ra));
        MPI_Alltoallv(flat.data(), sc.data(), sa.data(), MPI_BYTE, out.data(), rc.data(), ra.data(),
                      MPI_BYTE, comm_);
        received_ += out.size() - std::size_t(rc[std::size_t(rank_)]);
        counts.assign(rc.begin(), rc.end());
        return out;
    }

    std::vector<std::byte> gather_bytes(std::span<const std::byte> mine) override {
        const Timer timer(seconds_);
        const int n = count_of(mine.size());
        std::vector<int> c(nranks()), at(nranks());
        MPI_Gather(&n, 1, MPI_INT, c.data(), 1, MPI_INT, 0, comm_);
        std::vector<std::byte> out;
        if (rank_ == 0) out.resize(offsets(c, at));
        MPI_Gatherv(mine.data(), n, MPI_BYTE, out.data(), c.data(), at.data(), MPI_BYTE, 0, comm_);
        if (rank_ == 0) received_ += out.size() - mine.size();
        return out;
    }

    void max_in_place(std::span<double> v) override {
        const Timer timer(seconds_);
        MPI_Allreduce(MPI_IN_PLACE, v.data(), count_of(v.size()), MPI_DOUBLE, MPI_MAX, comm_);
        received_ += v.size_bytes() * std::size_t(size_ > 1);
    }
    void sum_in_place(std::span<std::uint64_t> v) override {
        const Timer timer(seconds_);
        MPI_Allreduce(MPI_IN_PLACE, v.data(), count_of(v.size()), MPI_UINT64_T, MPI_SUM, comm_);
        received_ += v.size_bytes() * std::size_t(size_ > 1);
    }

  private:
    /// Adds the time from its making to its end to a total (each collective's time).
    struct Timer {
        explicit Timer(double& total) : total_(total) {}
        ~Timer() {
            total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
        }
        Timer(const Timer&) = delete;
        Timer& operator=(const Timer&) = delete;
        double& total_;
        std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
    };
    std::size_t nranks() const { return std::size_t(size_); }
    /// MPI counts are ints: a message over 2 GiB is refused rather than truncated.
    static int count_of(std::size_t n) {
        if (n > std::size_t(INT_MAX))
            throw Error("distributed solve: a message of " + std::to_string(n) +
                        " bytes is more than MPI's int counts carry; use more ranks");
        return static_cast<int>(n);
    }
    /// Displacements from counts; returns the total.
    static std::size_t offsets(const std::vector<int>& c, std::vector<int>& at) {
        std::size_t total = 0;
        for (std::size_t r = 0; r < c.size(); ++r) {
            at[r] = count_of(total);
            total += std::size_t(c[r]);
        }
        return total;
    }

    MPI_Comm comm_;
    int rank_ = 0, size_ = 1;
};

/// MPI_Init_thread / MPI_Finalize for a program's lifetime (funneled: only the main thread
/// calls MPI; OpenMP threads inside a rank never do).
class MpiSession {
  public:
    MpiSession(int& argc, char**& argv) {
        int provided = 0;
        MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    }
    ~MpiSession() { MPI_Finalize(); }

    /// Whether an MPI launcher started this process (mpirun or mpiexec of Open MPI, MPICH or
    /// Intel MPI, or srun with PMI or PMIx): the variables each puts in its ranks' environment.
    /// A program run on its own may skip MPI_Init and work as one process: Open MPI's singleton
    /// start spawns a runtime daemon (orted), 0.4 s that room3's whole solve is not much longer.
    static bool launched() {
        for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
            if (std::getenv(v) != nullptr) return true;
        return false;
    }
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;

    /// Ranks sharing this rank's machine (MPI_COMM_TYPE_SHARED), to divide its cores among them.
    static int ranks_on_this_node() {
        MPI_Comm local;
        MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &local);
        int n = 1;
        MPI_Comm_size(local, &n);
        MPI_Comm_free(&local);
        return n;
    }
    /// Ends every rank of the job (a rank that cannot go on must not leave the others waiting).
    [[noreturn]] static void abort(int status) {
        MPI_Abort(MPI_COMM_WORLD, status);
        std::abort();
    }
};

}  // namespace radiosity
