#pragma once
/// @file communicator.hpp  The collectives a distributed solve needs, behind an interface that
/// knows nothing of MPI: the hierarchical solve runs on a Communicator, one process being the
/// SerialCommunicator below and several an MpiCommunicator (distributed/mpi.hpp, built with
/// RADIOSITY_WITH_MPI). Every collective is called by every rank in the same order; results are
/// in rank order, so what a rank makes of them never depends on the timing of the others.

#include <radiosity/config.hpp>
#include <radiosity/error.hpp>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <type_traits>
#include <vector>

namespace radiosity {

/// The collectives of a distributed solve (MPI's allgatherv, alltoallv, gatherv to rank 0 and
/// allreduce, Gropp, Lusk & Skjellum, "Using MPI", ch. 5), on bytes; the typed helpers below
/// wrap them. Counts every byte a rank receives from the others (bytes_received).
class Communicator {
  public:
    virtual ~Communicator() = default;
    virtual int rank() const = 0;  ///< this process, 0 .. size() - 1
    virtual int size() const = 0;  ///< number of processes
    /// Every rank's `mine`, concatenated in rank order, into `all`; counts[r]: rank r's bytes.
    virtual void allgather_bytes(std::span<const std::byte> mine, std::vector<std::byte>& all,
                                 std::vector<std::size_t>& counts) = 0;
    /// send[r] goes to rank r; returns what each rank sent to this one, concatenated in rank
    /// order; counts[r]: the bytes from rank r.
    virtual std::vector<std::byte> alltoall_bytes(const std::vector<std::vector<std::byte>>& send,
                                                  std::vector<std::size_t>& counts) = 0;
    /// Every rank's `mine` concatenated in rank order at rank 0 (empty elsewhere).
    virtual std::vector<std::byte> gather_bytes(std::span<const std::byte> mine) = 0;
    /// Element-wise maximum over the ranks, in place.
    virtual void max_in_place(std::span<double> values) = 0;
    /// Element-wise sum over the ranks, in place (integers: the same on any rank count).
    virtual void sum_in_place(std::span<std::uint64_t> values) = 0;

    /// Bytes this rank has received from the other ranks so far.
    std::uint64_t bytes_received() const { return received_; }
    /// Seconds this rank has spent inside collectives so far: mostly waiting for the slowest
    /// rank to arrive (what the load imbalance of each step between two collectives costs).
    double collective_seconds() const { return seconds_; }

  protected:
    std::uint64_t received_ = 0;  ///< updated by the implementations
    double seconds_ = 0.0;        ///< updated by the implementations
};

/// One process: every collective is the identity.
class SerialCommunicator final : public Communicator {
  public:
    int rank() const override { return 0; }
    int size() const override { return 1; }
    void allgather_bytes(std::span<const std::byte> mine, std::vector<std::byte>& all,
                         std::vector<std::size_t>& counts) override {
        all.assign(mine.begin(), mine.end());
        counts.assign(1, mine.size());
    }
    std::vector<std::byte> alltoall_bytes(const std::vector<std::vector<std::byte>>& send,
                                          std::vector<std::size_t>& counts) override {
        counts.assign(1, send.at(0).size());
        return send.at(0);
    }
    std::vector<std::byte> gather_bytes(std::span<const std::byte> mine) override {
        return {mine.begin(), mine.end()};
    }
    void max_in_place(std::span<double>) override {}
    void sum_in_place(std::span<std::uint64_t>) override {}
};

namespace detail {

/// The bytes of a vector of trivially copyable values.
template <class T, class A>
std::span<const std::byte> as_bytes_of(const std::vector<T, A>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    return std::as_bytes(std::span<const T>(v));
}

/// Values of type T read back from bytes (a whole number of them), into a vector with
/// allocator A.
template <class T, class A = std::allocator<T>>
std::vector<T, A> values_of(std::span<const std::byte> bytes) {
    static_assert(std::is_trivially_copyable_v<T>);
    RADIOSITY_ASSERT(bytes.size() % sizeof(T) == 0);
    std::vector<T, A> v(bytes.size() / sizeof(T));
    if (!v.empty()) std::memcpy(v.data(), bytes.data(), bytes.size());
    return v;
}

}  // namespace detail

/// Allgatherv of typed values: every rank's `mine`, in rank order.
template <class T, class A>
std::vector<T, A> all_gather(Communicator& c, const std::vector<T, A>& mine) {
    std::vector<std::byte> all;
    std::vector<std::size_t> counts;
    c.allgather_bytes(detail::as_bytes_of(mine), all, counts);
    return detail::values_of<T, A>(all);
}

/// Alltoallv of typed values: send[r] to rank r; what came to this rank, in rank order; `from`,
/// if given, receives how many values came from each rank.
template <class T, class A>
std::vector<T, A> all_to_all(Communicator& c, const std::vector<std::vector<T, A>>& send,
                             std::vector<std::size_t>* from = nullptr) {
    std::vector<std::vector<std::byte>> bytes(send.size());
    for (std::size_t r = 0; r < send.size(); ++r) {
        const auto b = detail::as_bytes_of(send[r]);
        bytes[r].assign(b.begin(), b.end());
    }
    std::vector<std::size_t> counts;
    std::vector<T, A> out = detail::values_of<T, A>(c.alltoall_bytes(bytes, counts));
    if (from) {
        from->resize(counts.size());
        for (std::size_t r = 0; r < counts.size(); ++r) (*from)[r] = counts[r] / sizeof(T);
    }
    return out;
}

/// Gatherv of typed values to rank 0, in rank order (empty on the other ranks).
template <class T, class A>
std::vector<T, A> gather_to_first(Communicator& c, const std::vector<T, A>& mine) {
    return detail::values_of<T, A>(c.gather_bytes(detail::as_bytes_of(mine)));
}

}  // namespace radiosity
