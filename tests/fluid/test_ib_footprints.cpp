// SPDX-License-Identifier: MIT
// The separable footprints of the immersed boundary (fluid/ib_weights.cpp, fluid/ib_footprint.hpp,
// fluid/ib_axis_batch.hpp) against the node list of stencil(), and their SIMD forms against the
// scalar ones bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fluid/ib_axis_batch.hpp"
#include "fluid/immersed_boundary.hpp"
#include "tests/fluid/ib_test_domain.hpp"

namespace dld::fluid {
namespace {

using test::markers_everywhere;
using test::test_domain;

/// Every node of a footprint with a non-zero weight is a node of stencil() with the same weight,
/// and there are as many.
template <typename Footprint, typename NodeWeight>
void expect_same_nodes(const IbStencil& s, int W, NodeWeight node_weight, std::size_t m) {
  int weighted = 0;  // z layers beyond a wall have weight zero in the footprint
  for (int c = 0; c < W; ++c)
    for (int b = 0; b < W; ++b)
      for (int a = 0; a < W; ++a) {
        const auto [node, w] = node_weight(a, b, c);
        if (w == 0.0) continue;
        ++weighted;
        int found = -1;
        for (int r = 0; r < s.count; ++r)
          if (s.node[r] == node) found = r;
        ASSERT_GE(found, 0) << "node " << node << " of marker " << m;
        EXPECT_NEAR(w, s.weight[found], 1e-15) << W << "-point, marker " << m;
      }
  EXPECT_EQ(weighted, s.count) << "the footprint's nodes are the stencil's, marker " << m;
}

template <int W>
void expect_footprint_is_stencil(const Lattice& L, IbKernel k, const std::vector<double>& pos) {
  const ImmersedBoundary ib(L, k);
  int separable = 0, split = 0, masked = 0, listed = 0;
  for (std::size_t m = 0; m < pos.size() / 3; ++m) {
    IbFootprint<W> fp;
    IbSplitFootprint<W> sp;
    IbMaskedFootprint<W> mp;
    IbStencil s;
    ASSERT_TRUE(ib.stencil(&pos[3 * m], s));
    if (ib.footprint<W>(&pos[3 * m], fp)) {
      ++separable;
      expect_same_nodes<IbFootprint<W>>(
          s, W,
          [&](int a, int b, int c) {
            return std::pair{fp.layer[c] + fp.row[b] + fp.x0 + a, fp.wx[a] * fp.wy[b] * fp.wz[c]};
          },
          m);
    } else if (ib.split_footprint<W>(&pos[3 * m], sp)) {
      ++split;
      expect_same_nodes<IbSplitFootprint<W>>(
          s, W,
          [&](int a, int b, int c) {
            const int part = a < sp.split ? 0 : 1;
            return std::pair{sp.layer[c] + sp.row[part][b] + sp.x0[part] +
                                 static_cast<std::size_t>(a - part * sp.split),
                             sp.wx[a] * sp.wy[part][b] * sp.wz[c]};
          },
          m);
    } else if (ib.masked_footprint<W>(&pos[3 * m], mp)) {
      ++masked;
      expect_same_nodes<IbMaskedFootprint<W>>(
          s, W,
          [&](int a, int b, int c) {
            return std::pair{mp.layer[c] + mp.row[b] + mp.x0 + a,
                             mp.wx[b][a] * mp.wy[b] * mp.wz[c]};
          },
          m);
    } else {
      ++listed;
    }
  }
  EXPECT_GT(separable, 100) << W << "-point";
  EXPECT_GT(split, 10) << W << "-point: markers across the shifted x face";
  EXPECT_GT(masked, 10) << W << "-point: markers by the pillar";
  // The pillar is solid at every height and away from the x face: no marker needs stencil().
  EXPECT_EQ(listed, 0) << W << "-point";
}

TEST(ImmersedBoundary, SeparableFootprintHasTheStencilsNodesAndWeights) {
  const Lattice L(test_domain(3.4));
  const auto pos = markers_everywhere(L, 1000, 11);
  expect_footprint_is_stencil<2>(L, IbKernel::kPeskin2, pos);
  expect_footprint_is_stencil<3>(L, IbKernel::kPeskin3, pos);
  expect_footprint_is_stencil<4>(L, IbKernel::kPeskin4, pos);
}

void expect_same_bits(const IbMaskedFootprint<4>& a, const IbMaskedFootprint<4>& b) {
  EXPECT_EQ(a.x0, b.x0);
  for (int k = 0; k < 4; ++k) {
    for (int q = 0; q < 4; ++q) EXPECT_EQ(a.wx[k][q], b.wx[k][q]);  // exact: the same bits
    EXPECT_EQ(a.wy[k], b.wy[k]);
    EXPECT_EQ(a.wz[k], b.wz[k]);
    EXPECT_EQ(a.row[k], b.row[k]);
    EXPECT_EQ(a.layer[k], b.layer[k]);
  }
}

void expect_same_bits(const IbSplitFootprint<4>& a, const IbSplitFootprint<4>& b) {
  EXPECT_EQ(a.split, b.split);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(a.wx[k], b.wx[k]);
    EXPECT_EQ(a.wz[k], b.wz[k]);
    EXPECT_EQ(a.layer[k], b.layer[k]);
    for (int part = 0; part < 2; ++part) {
      EXPECT_EQ(a.wy[part][k], b.wy[part][k]);
      EXPECT_EQ(a.row[part][k], b.row[part][k]);
    }
  }
  EXPECT_EQ(a.x0[0], b.x0[0]);
  EXPECT_EQ(a.x0[1], b.x0[1]);
}

// The SIMD batch of axis weights (fluid/ib_axis_batch.hpp) gives footprint<4>()'s footprint bit
// for bit, also for markers folded from other boxes, by the walls and refused ones (x face,
// pillar, not finite), masked_footprint<4>()'s by the pillar and split_footprint<4>()'s across
// the x face.
TEST(ImmersedBoundary, BatchedFootprintEqualsTheMarkerByMarkerOneBitForBit) {
  const Lattice L(test_domain(3.4));
  const ImmersedBoundary ib(L, IbKernel::kPeskin4);
  auto pos = markers_everywhere(L, 1000, 23);
  for (std::size_t m = 0; m < 100; ++m)
    pos[3 * m] += static_cast<double>(m % 5) * L.nx() - 2.0 * L.nx();
  for (std::size_t m = 100; m < 200; ++m)  // many boxes away in y (a displaced cell's markers)
    pos[3 * m + 1] += static_cast<double>(static_cast<int>(m % 7) - 3) * 1000.0 * L.ny();
  pos[std::size_t{3} * 7] = std::nan("");
  pos[3 * 8 + 2] = INFINITY;
  const std::size_t markers = pos.size() / 3;
  std::vector<std::uint32_t> index(markers);
  for (std::size_t m = 0; m < markers; ++m) index[m] = static_cast<std::uint32_t>(markers - 1 - m);
  int separable = 0, refused = 0, masked = 0, split = 0;
  for (std::size_t q0 = 0; q0 < markers; q0 += kIbBatch) {
    const int n = static_cast<int>(std::min<std::size_t>(kIbBatch, markers - q0));
    Peskin4AxisBatch axes;
    peskin4_axis_batch(pos.data(), &index[q0], n, L.nx(), L.ny(), L.domain().shift, axes);
    for (int l = 0; l < n; ++l) {
      const double* p = &pos[std::size_t{3} * index[q0 + static_cast<std::size_t>(l)]];
      IbFootprint<4> a, b;
      const bool one = ib.footprint<4>(p, a), batch = ib.batched_footprint(axes, l, p, b);
      ASSERT_EQ(one, batch) << "marker " << index[q0 + static_cast<std::size_t>(l)];
      if (!one) {
        ++refused;
        IbMaskedFootprint<4> ma, mb;
        const bool mone = ib.masked_footprint<4>(p, ma);
        ASSERT_EQ(mone, ib.batched_masked_footprint(axes, l, p, mb));
        if (mone) {
          ++masked;
          expect_same_bits(ma, mb);
        }
        IbSplitFootprint<4> sa, sb;
        const bool sone = ib.split_footprint<4>(p, sa);
        ASSERT_EQ(sone, ib.batched_split_footprint(axes, l, p, sb));
        if (sone) {
          ++split;
          expect_same_bits(sa, sb);
        }
        continue;
      }
      ++separable;
      EXPECT_EQ(a.x0, b.x0);
      for (int k = 0; k < 4; ++k) {
        EXPECT_EQ(a.wx[k], b.wx[k]);  // exact equality: the same bits
        EXPECT_EQ(a.wy[k], b.wy[k]);
        EXPECT_EQ(a.wz[k], b.wz[k]);
        EXPECT_EQ(a.row[k], b.row[k]);
        EXPECT_EQ(a.layer[k], b.layer[k]);
      }
    }
  }
  EXPECT_GT(separable, 500);
  EXPECT_GT(refused, 20);
  EXPECT_GT(masked, 10);
  EXPECT_GT(split, 10);
}

// A footprint across the shifted x face spreads (with masked vectors where the CPU has them) the
// same bits as the node-by-node loop over its nodes.
TEST(ImmersedBoundary, SplitFootprintSpreadsTheNodeLoopsBits) {
  const Lattice L(test_domain(3.4));
  const ImmersedBoundary ib(L, IbKernel::kPeskin4);
  const auto pos = markers_everywhere(L, 2000, 31);
  const std::size_t n = L.padded_size();
  std::vector<double> a(3 * n, 0.0), b(3 * n, 0.0);
  double* const fa[3] = {a.data(), a.data() + n, a.data() + 2 * n};
  double* const fb[3] = {b.data(), b.data() + n, b.data() + 2 * n};
  int split = 0;
  for (std::size_t m = 0; m < pos.size() / 3; ++m) {
    IbSplitFootprint<4> sp;
    if (!ib.split_footprint<4>(&pos[3 * m], sp)) continue;
    ++split;
    const double f[3] = {0.3 + 1e-3 * static_cast<double>(m), -0.7, 1.1};
    spread_footprint(sp, f, fa);
    for_each_node(sp, [&](std::size_t node, double w) {
      for (int d = 0; d < 3; ++d) fb[d][node] += w * f[d];
    });
  }
  EXPECT_GT(split, 10);
  EXPECT_EQ(a, b);  // every node, bit for bit; nothing outside the footprints is touched
}

// spread() and interpolate() (separable footprints, x slabs per thread) against the plain sums
// over stencil()'s node lists, for 1 and 2 threads: equal to round-off.

}  // namespace
}  // namespace dld::fluid
