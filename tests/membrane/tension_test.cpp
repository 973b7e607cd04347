// SPDX-License-Identifier: MIT
// Flat membrane patch in uniaxial tension (T2 = 0) against the closed forms of Barthes-Biesel,
// Diaz, Dhenin, J. Fluid Mech. 460 (2002) 211 (../shared/reference/membrane_laws): the patch is
// stretched to l1 along x with free lateral edges, solved quasi-statically, and T1 is the reaction
// on the pulled edge per current length.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "membrane/lbfgs.hpp"
#include "membrane/model_registry.hpp"

namespace dld::membrane {
namespace {

constexpr int kN = 6;  // squares per side

TriMesh patch() {
  TriMesh m;
  m.nodes.resize(3, (kN + 1) * (kN + 1));
  auto id = [](int i, int j) { return j * (kN + 1) + i; };
  for (int j = 0; j <= kN; ++j)
    for (int i = 0; i <= kN; ++i) m.nodes.col(id(i, j)) << double(i) / kN, double(j) / kN, 0.0;
  for (int j = 0; j < kN; ++j)
    for (int i = 0; i < kN; ++i) {
      // Alternate diagonals so the patch has no preferred shear direction.
      if ((i + j) % 2 == 0) {
        m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        m.faces.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        m.faces.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  return m;
}

struct Tension {
  double t1;  ///< tension per current length
  double l2;  ///< lateral stretch
};

template <class Model>
Tension uniaxial(const Model& model, const TriMesh& ref, double l1) {
  const int n = ref.node_count();
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(ref.nodes.data(), 3 * n);
  Eigen::VectorXd fixed = Eigen::VectorXd::Zero(3 * n);
  for (int i = 0; i < n; ++i) {
    x(3 * i) *= l1;
    fixed(3 * i + 2) = 1;                                                    // stays flat
    if (ref.nodes(0, i) == 0.0 || ref.nodes(0, i) == 1.0) fixed(3 * i) = 1;  // pulled edges: x set
  }
  fixed(1) = 1;  // node 0 pinned in y (no rigid drift)
  Points f(3, n);
  auto objective = [&](const Eigen::VectorXd& xv, Eigen::VectorXd& g) {
    Eigen::Map<const Points> xp(xv.data(), 3, n);
    f.setZero();
    const double e = model.add_forces(xp, f);
    g = -Eigen::Map<const Eigen::VectorXd>(f.data(), 3 * n);
    g = g.cwiseProduct((1.0 - fixed.array()).matrix());
    return e;
  };
  LbfgsOptions o;
  // Node forces are O(G_s h) = O(0.1); the energy-based line search stalls near 1e-8.
  o.gradient_tolerance = 1e-7;
  o.max_iterations = 5000;
  o.max_step = 0.01;
  const LbfgsResult r = minimize_lbfgs(x, objective, o);
  EXPECT_TRUE(r.converged) << "max gradient " << r.max_gradient;
  Eigen::Map<const Points> xp(x.data(), 3, n);
  f.setZero();
  model.add_forces(xp, f);
  double pull = 0.0;
  for (int i = 0; i < n; ++i)
    if (ref.nodes(0, i) == 1.0) pull -= f(0, i);  // the load balances the membrane force
  const double height = xp.row(1).maxCoeff() - xp.row(1).minCoeff();
  return {pull / height, height};
}

// Closed forms (reference/README.md, Barthes-Biesel et al. 2002).
Tension skalak_exact(double l1, double c) {
  const double l2 = std::sqrt((1 + c * l1 * l1) / (1 + c * l1 * l1 * l1 * l1));
  return {(l1 / l2) * (l1 * l1 - 1 + c * l2 * l2 * (l1 * l1 * l2 * l2 - 1)), l2};
}
Tension neo_hookean_exact(double l1) {
  const double l2 = 1.0 / std::sqrt(l1);
  return {(1.0 / (l1 * l2)) * (l1 * l1 - 1.0 / (l1 * l1 * l2 * l2)), l2};
}

TEST(UniaxialTension, SkalakMatchesBarthesBiesel2002) {
  const TriMesh ref = patch();
  const double c = 1.0;
  const SkalakModel model(ref, {3.0, 3.0 * c});  // G_s = kappa_s / 3 = 1
  for (double e1 : {0.02, 0.1, 0.3, 0.6, 1.0}) {
    const Tension sim = uniaxial(model, ref, 1.0 + e1), ref_t = skalak_exact(1.0 + e1, c);
    std::printf("skalak e1 %.2f: T1/Gs %.8f (exact %.8f), l2 %.8f (exact %.8f)\n", e1, sim.t1,
                ref_t.t1, sim.l2, ref_t.l2);
    EXPECT_NEAR(sim.t1 / ref_t.t1, 1.0, 0.01);
    EXPECT_NEAR(sim.l2 / ref_t.l2, 1.0, 0.01);
  }
}

TEST(UniaxialTension, NeoHookeanMatchesBarthesBiesel2002) {
  const TriMesh ref = patch();
  const NeoHookeanModel model(ref, {1.0});
  for (double e1 : {0.02, 0.1, 0.3, 0.6, 1.0}) {
    const Tension sim = uniaxial(model, ref, 1.0 + e1), ref_t = neo_hookean_exact(1.0 + e1);
    std::printf("neo-Hookean e1 %.2f: T1/Gs %.8f (exact %.8f), l2 %.8f (exact %.8f)\n", e1, sim.t1,
                ref_t.t1, sim.l2, ref_t.l2);
    EXPECT_NEAR(sim.t1 / ref_t.t1, 1.0, 0.01);
    EXPECT_NEAR(sim.l2 / ref_t.l2, 1.0, 0.01);
  }
}

}  // namespace
}  // namespace dld::membrane
