// SPDX-License-Identifier: MIT
// Hyperelastic membrane finite elements on linear triangles, shared by the in-plane laws.
// Each triangle maps its reference shape (2-D local frame) to its current 3-D shape with a
// constant deformation gradient F = [e1 e2] D, D = inverse of the reference edge matrix. With the
// metric G = [e_i . e_j], the right Cauchy-Green tensor is C = D^T G D, so I1 = tr C - 2 and
// I2 = det C - 1 (Charrier et al. 1989; Krueger's thesis, 2012, ch. 3). The element energy is
// A0 w(I1, I2); differentiating through G gives the corner forces in closed form without local
// rotations, and the forces are rotation-equivariant by construction (zero net torque).
#pragma once
#include <Eigen/Core>
#include <vector>

#include "membrane/mesh.hpp"
#include "membrane/node_gather.hpp"

namespace dld::membrane {

struct TriangleReference {
  Face nodes;
  Eigen::Matrix2d d;  ///< inverse reference edge matrix
  double area0;       ///< reference area
};

/// Throws InputError if the reference mesh has a degenerate triangle.
std::vector<TriangleReference> triangle_references(const TriMesh& reference,
                                                   const std::string& model);

/// Strain invariants and their use by a law: Law must provide
///   double energy(double i1, double i2) const           (per reference area)
///   void derivatives(double i1, double i2, double& w1, double& w2) const   (dw/dI1, dw/dI2)
template <class Law>
class TriangleElements {
 public:
  TriangleElements(const TriMesh& reference, const Law& law, const char* name)
      : law_(law), tri_(triangle_references(reference, name)) {
    std::vector<int> corners;
    for (const auto& t : tri_) {
      corners.insert(corners.end(), t.nodes.begin(), t.nodes.end());
    }
    gather_ = NodeGather(corners, reference.node_count());
  }

  const Law& law() const { return law_; }

  double energy(const Eigen::Ref<const Points>& x) const {
    double e = 0.0;
    const int n = static_cast<int>(tri_.size());
#pragma omp parallel for reduction(+ : e) schedule(static) if (n > 8192)
    for (int k = 0; k < n; ++k) {
      double i1, i2;
      Eigen::Matrix2d c;
      invariants(tri_[k], x, i1, i2, c);
      e += tri_[k].area0 * law_.energy(i1, i2);
    }
    return e;
  }

  /// Adds -dE/dx to f, returns E. (Eigen::Ref by value: Eigen's idiom for a writable view.)
  // NOLINTNEXTLINE(performance-unnecessary-value-param)
  double add_forces(const Eigen::Ref<const Points>& x, Eigen::Ref<Points> f) const {
    const int n = static_cast<int>(tri_.size());
    // Scratch per calling thread (cells may be evaluated concurrently); the reference makes the
    // caller's buffer shared by the threads of the loop below.
    static thread_local Eigen::Matrix3Xd scratch;
    scratch.resize(3, 3 * Eigen::Index{n});
    Eigen::Matrix3Xd& slot = scratch;
    double e = 0.0;
#pragma omp parallel for reduction(+ : e) schedule(static) if (n > 8192)
    for (int k = 0; k < n; ++k) {
      const TriangleReference& t = tri_[k];
      double i1, i2;
      Eigen::Matrix2d c;
      invariants(t, x, i1, i2, c);
      e += t.area0 * law_.energy(i1, i2);
      double w1, w2;
      law_.derivatives(i1, i2, w1, w2);
      // dw/dC = w1 I + w2 det(C) C^-1 = w1 I + w2 adj(C); then dw/dG = D (dw/dC) D^T.
      Eigen::Matrix2d adj;
      adj << c(1, 1), -c(0, 1), -c(1, 0), c(0, 0);
      const Eigen::Matrix2d s = w1 * Eigen::Matrix2d::Identity() + w2 * adj;
      const Eigen::Matrix2d g = t.d * s * t.d.transpose();
      const Eigen::Vector3d e1 = x.col(t.nodes[1]) - x.col(t.nodes[0]);
      const Eigen::Vector3d e2 = x.col(t.nodes[2]) - x.col(t.nodes[0]);
      const Eigen::Vector3d f1 = -2.0 * t.area0 * (g(0, 0) * e1 + g(0, 1) * e2);
      const Eigen::Vector3d f2 = -2.0 * t.area0 * (g(0, 1) * e1 + g(1, 1) * e2);
      const Eigen::Index base = 3 * Eigen::Index{k};
      slot.col(base) = -(f1 + f2);
      slot.col(base + 1) = f1;
      slot.col(base + 2) = f2;
    }
    gather_.add(slot, f);
    return e;
  }

 private:
  static void invariants(const TriangleReference& t, const Eigen::Ref<const Points>& x, double& i1,
                         double& i2, Eigen::Matrix2d& c) {
    const Eigen::Vector3d e1 = x.col(t.nodes[1]) - x.col(t.nodes[0]);
    const Eigen::Vector3d e2 = x.col(t.nodes[2]) - x.col(t.nodes[0]);
    Eigen::Matrix2d g;
    g << e1.dot(e1), e1.dot(e2), e1.dot(e2), e2.dot(e2);
    c = t.d.transpose() * g * t.d;
    i1 = c.trace() - 2.0;
    i2 = c(0, 0) * c(1, 1) - c(0, 1) * c(1, 0) - 1.0;
  }

  Law law_;
  std::vector<TriangleReference> tri_;
  NodeGather gather_;
};

}  // namespace dld::membrane
