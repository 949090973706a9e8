#pragma once
/// @file partition.hpp  Which rank owns which receivers of a distributed hierarchical solve.
/// The roots lie along the cluster order (Hierarchy::order), in which every cluster's roots are
/// one range; each rank owns a contiguous range of that order, cut where the cost of the roots
/// before it reaches its share (a 1-D partition of a space-filling order, as Warren & Salmon's
/// hashed oct-tree and every treecode since do). A node belongs to the rank owning the first
/// root below it, so an element's whole quadtree and most clusters stay on one rank, and links
/// live with their receivers. Who owns what changes only the work per rank, never a result.

#include <radiosity/hierarchy/nodes.hpp>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace radiosity {

/// A partition of the cluster order among ranks.
class Partition {
  public:
    Partition() = default;
    /// Ranges cut so that each rank's roots have about an equal share of `cost` (one value per
    /// position of Hierarchy::order, all positive); with cost empty, equal counts of roots.
    Partition(std::size_t positions, int ranks, const std::vector<double>& cost = {})
        : owner_(positions, 0), ranks_(ranks) {
        std::vector<double> prefix(positions + 1, 0.0);
        for (std::size_t i = 0; i < positions; ++i)
            prefix[i + 1] = prefix[i] + (cost.empty() ? 1.0 : cost[i]);
        std::size_t at = 0;
        for (int r = 0; r < ranks; ++r) {
            // the first position whose prefix passes rank r + 1's share
            const double share = prefix[positions] * double(r + 1) / double(ranks);
            const std::size_t end =
                r + 1 == ranks ? positions
                               : std::size_t(std::lower_bound(prefix.begin(), prefix.end(), share) -
                                             prefix.begin());
            for (; at < end; ++at) owner_[at] = r;
        }
    }

    /// The rank owning node n (its first root's position in the cluster order).
    int owner(const Hierarchy& h, NodeId n) const {
        return owner_.empty() ? 0 : owner_[h.member_begin[n]];
    }
    /// The rank owning position i of the cluster order.
    int owner_of_position(std::size_t i) const { return owner_.empty() ? 0 : owner_[i]; }
    int ranks() const { return ranks_; }  ///< number of ranks
    /// Positions of the cluster order that rank r owns.
    std::size_t positions_of(int r) const {
        return std::size_t(std::count(owner_.begin(), owner_.end(), r));
    }

  private:
    std::vector<int> owner_;  // per position of the cluster order
    int ranks_ = 1;
};

}  // namespace radiosity
