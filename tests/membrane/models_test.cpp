// SPDX-License-Identifier: MIT
// Properties every membrane model must have: forces are minus the finite-difference gradient of
// its energy, net force and torque vanish, rigid motions of the rest shape cost nothing.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>

#include "membrane/model_registry.hpp"
#include "test_meshes.hpp"

namespace dld::membrane {
namespace {

/// One instance of each registered model on `ref`, with moduli of order one (its for_test()).
std::vector<std::pair<std::string, AnyModel>> all_models(const TriMesh& ref) {
  std::vector<std::pair<std::string, AnyModel>> models;
  for (const ModelEntry& m : model_registry()) models.emplace_back(m.name, m.for_test(ref));
  return models;
}

double energy(const AnyModel& m, const Points& x) {
  return std::visit([&](const auto& model) { return model.energy(x); }, m);
}
/// Minus the central-difference gradient of energy(x) with step h.
template <typename Energy>
Points finite_difference_forces(Energy energy_of, const Points& x, double h) {
  Points fd(3, x.cols());
  for (int i = 0; i < x.size(); ++i) {
    Points xp = x, xm = x;
    xp.data()[i] += h;
    xm.data()[i] -= h;
    fd.data()[i] = -(energy_of(xp) - energy_of(xm)) / (2 * h);
  }
  return fd;
}
Points forces(const AnyModel& m, const Points& x) {
  Points f = Points::Zero(3, x.cols());
  std::visit([&](const auto& model) { model.add_forces(x, f); }, m);
  return f;
}

class EveryModel : public ::testing::TestWithParam<int> {
 protected:
  static void SetUpTestSuite() { ref_ = new TriMesh(test::cell_mesh(300, 4.0)); }
  static TriMesh* ref_;
};
TriMesh* EveryModel::ref_ = nullptr;

TEST_P(EveryModel, RegistryCoversEveryVariantAlternative) {
  EXPECT_EQ(model_registry().size(), std::variant_size_v<AnyModel>);
}

TEST_P(EveryModel, ForceIsMinusFiniteDifferenceGradient) {
  const auto [name, model] = all_models(*ref_)[GetParam()];
  SCOPED_TRACE(name);
  for (unsigned seed : {1u, 2u}) {
    // Random deformation: an affine stretch plus node noise of 10 % of an edge.
    Points x = *&ref_->nodes;
    x.row(0) *= 1.3;
    x.row(2) *= 0.8;
    x = test::perturbed(x, 0.05, seed);
    const Points f = forces(model, x);
    const AnyModel& m = model;  // a lambda cannot capture a structured binding before C++20
    const Points fd =
        finite_difference_forces([&m](const Points& y) { return energy(m, y); }, x, 1e-5);
    const double rel = (f - fd).norm() / f.norm();
    std::printf("%s seed %u: |F + grad E_fd| / |F| = %.2e\n", name.c_str(), seed, rel);
    EXPECT_LT(rel, 1e-6);
  }
}

TEST_P(EveryModel, NetForceAndTorqueVanish) {
  const auto [name, model] = all_models(*ref_)[GetParam()];
  SCOPED_TRACE(name);
  Points x = test::perturbed(ref_->nodes * 1.1, 0.1, 7);
  x.row(1) *= 0.7;
  const Points f = forces(model, x);
  const double scale = f.colwise().norm().sum();
  ASSERT_GT(scale, 0.0);
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  for (int i = 0; i < x.cols(); ++i) torque += x.col(i).cross(f.col(i));
  const double size = x.colwise().norm().maxCoeff();
  EXPECT_LT(f.rowwise().sum().norm(), 1e-12 * scale);
  EXPECT_LT(torque.norm(), 1e-12 * scale * size);
}

TEST_P(EveryModel, RigidMotionOfRestShapeGivesNoForce) {
  const auto [name, model] = all_models(*ref_)[GetParam()];
  SCOPED_TRACE(name);
  // Compare with the force of a 5 % stretch (or, for a model that resists compression only, a
  // 5 % compression) so that "zero" is measured against a real force.
  Points stretched = ref_->nodes, compressed = ref_->nodes;
  stretched.row(0) *= 1.05;
  compressed.row(0) *= 0.95;
  const double typical = std::max(forces(model, stretched).colwise().norm().maxCoeff(),
                                  forces(model, compressed).colwise().norm().maxCoeff());
  ASSERT_GT(typical, 0.0);
  const Eigen::Matrix3d rot =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Points moved = (rot * ref_->nodes).colwise() + Eigen::Vector3d(3, -2, 5);
  EXPECT_LT(forces(model, moved).colwise().norm().maxCoeff(), 1e-9 * typical);
  EXPECT_NEAR(energy(model, moved), 0.0,
              1e-12 * std::max(energy(model, stretched), energy(model, compressed)));
}

// Every model of the registry, without a list here: a new model is tested as soon as it is in
// AnyModel.
INSTANTIATE_TEST_SUITE_P(Models, EveryModel,
                         ::testing::Range(0, static_cast<int>(std::variant_size_v<AnyModel>)));

TEST(BendingModel, AngleIsSignedAndZeroWhenFlat) {
  // Hinge a=(0,0,0), b=(1,0,0); c on one side in the plane; d folded up or down.
  Points x(3, 4);
  x << 0, 1, 0.5, 0.5, 0, 0, 1, -1, 0, 0, 0, 0;
  const Hinge h{0, 1, 2, 3};
  EXPECT_NEAR(BendingModel::angle(h, x), 0.0, 1e-15);
  x(2, 3) = 1.0;  // d lifted: the faces fold by 45 degrees
  const double up = BendingModel::angle(h, x);
  x(2, 3) = -1.0;
  const double down = BendingModel::angle(h, x);
  EXPECT_NEAR(std::abs(up), M_PI / 4, 1e-12);
  EXPECT_NEAR(up, -down, 1e-12);
}

// The bending forces take a series for hinges near their rest angle and atan2 for the others
// (membrane/bending_model.cpp): on a mesh crumpled so that many hinges are of each kind, the
// forces are still minus the gradient of the energy (which always uses atan2).
TEST(BendingModel, ForcesOfStronglyBentHingesAreMinusTheEnergyGradient) {
  const TriMesh ref = test::cell_mesh(300, 4.0);
  const BendingModel model(ref, {1.0});
  const Points x = test::perturbed(ref.nodes, 0.25, 7);
  int near = 0, far = 0;
  for (const Hinge& h : hinges(ref)) {
    const double d = BendingModel::angle(h, x) - BendingModel::angle(h, ref.nodes);
    near += std::abs(d) < 0.2 ? 1 : 0;  // series (|tan| <= 1/4 is |d| <= 0.245)
    far += std::abs(d) > 0.25 ? 1 : 0;  // atan2
  }
  EXPECT_GT(near, 50);
  EXPECT_GT(far, 50);
  Points f = Points::Zero(3, x.cols());
  model.add_forces(x, f);
  const Points fd =
      finite_difference_forces([&](const Points& y) { return model.energy(y); }, x, 1e-6);
  EXPECT_LT((f - fd).norm() / f.norm(), 1e-6);
}

TEST(VolumePenalty, VolumeOfOctahedron) {
  const TriMesh m = test::octahedron();
  EXPECT_NEAR(enclosed_volume(m), 4.0 / 3.0, 1e-14);
  EXPECT_NEAR(surface_area(m), 4.0 * std::sqrt(3.0), 1e-14);
}

}  // namespace
}  // namespace dld::membrane

namespace dld::membrane {
namespace {

TEST(SpringNetwork, UniformStretchHasTheHarmonicEnergy) {
  // Every edge stretched by 10 %: E = (k/2) sum (0.1 l0)^2; each node pulled back to the centre.
  const TriMesh m = test::octahedron();
  const SpringNetwork s(m, {2.0});
  double sum_l0_squared = 0.0;
  for (const auto& [i, j] : edges(m))
    sum_l0_squared += (m.nodes.col(i) - m.nodes.col(j)).squaredNorm();
  const Points x = 1.1 * m.nodes;  // the octahedron is centred at the origin
  EXPECT_NEAR(s.energy(x), 0.5 * 2.0 * 0.01 * sum_l0_squared, 1e-12);
  Points f = Points::Zero(3, x.cols());
  EXPECT_NEAR(s.add_forces(x, f), s.energy(x), 1e-15);
  for (int n = 0; n < x.cols(); ++n) EXPECT_LT(f.col(n).dot(x.col(n)), 0.0) << "node " << n;
}

}  // namespace
}  // namespace dld::membrane
