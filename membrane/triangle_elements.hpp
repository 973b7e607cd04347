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
#include <cstddef>
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
    for (const auto& t : tri_) {
      corners_.insert(corners_.end(), t.nodes.begin(), t.nodes.end());
      d00_.push_back(t.d(0, 0));
      d10_.push_back(t.d(1, 0));
      d01_.push_back(t.d(0, 1));
      d11_.push_back(t.d(1, 1));
      area0_.push_back(t.area0);
    }
    gather_ = NodeGather(corners_, reference.node_count());
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
  /// One triangle per SIMD lane, in plain arrays: the same algebra as invariants() and the
  /// closed-form gradient below, to round-off.
  // NOLINTNEXTLINE(performance-unnecessary-value-param)
  double add_forces(const Eigen::Ref<const Points>& x, Eigen::Ref<Points> f) const {
    const int n = static_cast<int>(tri_.size());
    // Scratch per calling thread (cells may be evaluated concurrently): 3 corner slots each.
    static thread_local Eigen::Matrix3Xd scratch;
    scratch.resize(3, 3 * Eigen::Index{n});
    double* slot = scratch.data();
    const double* X = x.data();
    // 32-bit node offsets: GCC 12 gathers the corners only with those (a 64-bit product of the
    // node and the stride left this loop scalar). A cell's coordinates are far below 2^31.
    const int stride = static_cast<int>(x.outerStride());
    // Plain arrays (corners, then D and the area per triangle): GCC 12 does not vectorise the
    // loop over the triangle structs.
    const int* corner = corners_.data();
    const double *d00s = d00_.data(), *d10s = d10_.data(), *d01s = d01_.data(), *d11s = d11_.data(),
                 *area0s = area0_.data();
    const Law law = law_;
    double e = 0.0;
#pragma omp simd reduction(+ : e)
    for (int k = 0; k < n; ++k) {
      const int* nodes = corner + 3 * std::ptrdiff_t{k};
      const int a = nodes[0] * stride, b = nodes[1] * stride, c = nodes[2] * stride;
      const double e1[3] = {X[b] - X[a], X[b + 1] - X[a + 1], X[b + 2] - X[a + 2]};
      const double e2[3] = {X[c] - X[a], X[c + 1] - X[a + 1], X[c + 2] - X[a + 2]};
      const double g00 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
      const double g01 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
      const double g11 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
      // C = D^T G D (G symmetric), so I1 = tr C - 2, I2 = det C - 1.
      const double d00 = d00s[k], d01 = d01s[k], d10 = d10s[k], d11 = d11s[k];
      const double area0 = area0s[k];
      const double a00 = d00 * g00 + d10 * g01, a01 = d00 * g01 + d10 * g11;  // (D^T G) row 0
      const double a10 = d01 * g00 + d11 * g01, a11 = d01 * g01 + d11 * g11;  // row 1
      const double c00 = a00 * d00 + a01 * d10, c01 = a00 * d01 + a01 * d11;
      const double c10 = a10 * d00 + a11 * d10, c11 = a10 * d01 + a11 * d11;
      const double i1 = c00 + c11 - 2.0;
      const double i2 = c00 * c11 - c01 * c10 - 1.0;
      e += area0 * law.energy(i1, i2);
      double w1, w2;
      law.derivatives(i1, i2, w1, w2);
      // dw/dC = w1 I + w2 det(C) C^-1 = w1 I + w2 adj(C); then dw/dG = D (dw/dC) D^T.
      const double s00 = w1 + w2 * c11, s01 = -w2 * c01, s10 = -w2 * c10, s11 = w1 + w2 * c00;
      const double b00 = d00 * s00 + d01 * s10, b01 = d00 * s01 + d01 * s11;  // (D S) row 0
      const double b10 = d10 * s00 + d11 * s10, b11 = d10 * s01 + d11 * s11;  // row 1
      const double m00 = b00 * d00 + b01 * d01, m01 = b00 * d10 + b01 * d11;
      const double m11 = b10 * d10 + b11 * d11;
      double* out = slot + 9 * std::ptrdiff_t{k};
      for (int q = 0; q < 3; ++q) {
        const double f1 = -2.0 * area0 * (m00 * e1[q] + m01 * e2[q]);
        const double f2 = -2.0 * area0 * (m01 * e1[q] + m11 * e2[q]);
        out[q] = -(f1 + f2);
        out[3 + q] = f1;
        out[6 + q] = f2;
      }
    }
    gather_.add(scratch, f);
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
  std::vector<int> corners_;                           ///< tri_'s nodes, 3 per triangle
  std::vector<double> d00_, d10_, d01_, d11_, area0_;  ///< tri_'s D and area0, per triangle
  NodeGather gather_;
};

}  // namespace dld::membrane
