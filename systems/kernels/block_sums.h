#pragma once
// Sums of small dense blocks keyed by (row block, column block), kept in the order each key was
// first seen, for building sparse matrices whose element contributions repeat a key many times (a
// crack front's amplitudes: every zone element around two nodes adds to their pair). Summing here,
// in the contributions' order, gives the values setFromTriplets would, with one triplet per entry.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace xcut {

template <int R, int C>
class BlockSums {
public:
    using Block = Eigen::Matrix<double, R, C>;
    /// The block at (row block a, column block b), zero when first asked for.
    Block& at(int a, int b) {
        const uint64_t key = (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint32_t>(b);
        const auto [it, fresh] = index_.try_emplace(key, static_cast<int>(blocks_.size()));
        if (fresh) blocks_.push_back(Block::Zero()), keys_.push_back({a, b});
        return blocks_[it->second];
    }
    /// One triplet per entry: (row_stride a + i, col_stride b + j), in the keys' first-seen order.
    void write(int row_stride, int col_stride, std::vector<Eigen::Triplet<double>>& out) const {
        out.reserve(out.size() + blocks_.size() * R * C);
        for (size_t k = 0; k < blocks_.size(); ++k)
            for (int i = 0; i < R; ++i)
                for (int j = 0; j < C; ++j)
                    out.emplace_back(row_stride * keys_[k][0] + i, col_stride * keys_[k][1] + j, blocks_[k](i, j));
    }

private:
    std::unordered_map<uint64_t, int> index_;
    std::vector<Block, Eigen::aligned_allocator<Block>> blocks_;
    std::vector<std::array<int, 2>> keys_;
};

}  // namespace xcut
