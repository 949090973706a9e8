#pragma once
/// @file exchange.hpp  The one exchange per sweep of a distributed gather: each rank gathers
/// the irradiance H of the receivers it owns, then one all-gather hands every rank every
/// receiver's H, so that each can push-pull the whole hierarchy alike (the same operations in
/// the same order on every rank: the same B, bit for bit, whatever the number of ranks). A few
/// control words ride along (a checkpoint is due, the user asked to stop), so that every rank
/// takes the same decision after the same sweep without a second collective.

#include <radiosity/distributed/communicator.hpp>
#include <radiosity/hierarchy/gather.hpp>

#include <algorithm>
#include <array>
#include <cstring>
#include <vector>

namespace radiosity {

/// The receivers of every rank, in rank order, and the exchange of per-receiver values.
class ReceiverExchange {
  public:
    static constexpr std::size_t controls = 2;  ///< control words per rank and exchange

    /// Learns every rank's receivers (one all-gather; links fixed from here to the next
    /// refinement).
    ReceiverExchange(Communicator& c, const LinkGroups& mine) : comm_(c) {
        std::vector<std::byte> all;
        c.allgather_bytes(detail::as_bytes_of(mine.receivers), all, counts_);
        receivers_ = detail::values_of<NodeId>(all);
        for (auto& n : counts_) n /= sizeof(NodeId);
    }

    /// Shares `width` values per receiver: this rank's (`mine`, in its groups' order) go to
    /// every rank, each scattered into per_node[n * width ..]; returns the control words
    /// combined over the ranks (the maximum of each).
    std::array<double, controls> share(const std::vector<double>& mine, std::size_t width,
                                       std::vector<double>& per_node,
                                       const std::array<double, controls>& control) {
        return share(mine, width, control, [&](NodeId n, const double* values) {
            std::copy_n(values, width, per_node.data() + n * width);
        });
    }

    /// As above, each receiver's `width` values handed to put(node, values) instead.
    template <class Put>
    std::array<double, controls> share(const std::vector<double>& mine, std::size_t width,
                                       const std::array<double, controls>& control, Put&& put) {
        // The buffers are kept from sweep to sweep: tens of MB at a million faces, which fresh
        // allocations would fault in page by page every sweep.
        std::vector<double>& message = message_;
        message.assign(mine.begin(), mine.end());
        message.insert(message.end(), control.begin(), control.end());
        std::vector<std::byte>& all = all_;
        std::vector<std::size_t> bytes;
        const std::uint64_t before = comm_.bytes_received();
        comm_.allgather_bytes(detail::as_bytes_of(message), all, bytes);
        last_bytes_ = comm_.bytes_received() - before;
        // Read straight out of the received bytes: each rank's values, then its controls.
        std::array<double, controls> out{};
        const std::byte* at = all.data();
        std::size_t node = 0;
        for (std::size_t r = 0; r < bytes.size(); ++r) {
            const std::size_t n = counts_[r];
            RADIOSITY_ASSERT(bytes[r] == (n * width + controls) * sizeof(double));
            values_.resize(width);
            for (std::size_t i = 0; i < n; ++i, ++node, at += width * sizeof(double)) {
                std::memcpy(values_.data(), at, width * sizeof(double));
                put(receivers_[node], values_.data());
            }
            for (std::size_t k = 0; k < controls; ++k, at += sizeof(double)) {
                double c = 0.0;
                std::memcpy(&c, at, sizeof c);
                out[k] = std::max(out[k], c);
            }
        }
        return out;
    }

    /// Bytes this rank received in the last share().
    std::uint64_t last_bytes() const { return last_bytes_; }
    /// Receivers over all ranks.
    std::size_t receivers() const { return receivers_.size(); }

  private:
    Communicator& comm_;
    std::vector<NodeId> receivers_;    // every rank's, in rank order
    std::vector<std::size_t> counts_;  // per rank
    std::uint64_t last_bytes_ = 0;
    std::vector<double> message_;  // this rank's values and controls
    std::vector<std::byte> all_;   // every rank's
    std::vector<double> values_;   // one receiver's, aligned
};

}  // namespace radiosity
