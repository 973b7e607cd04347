// SPDX-License-Identifier: MIT
// Discrete bending: E_b = sqrt(3) kappa_b sum over edges (theta - theta0)^2, theta the signed
// angle between the normals of the two faces sharing the edge and theta0 its rest value
// (Krueger's membrane model; equals Helfrich bending with modulus kappa_b on a fine regular mesh,
// Gompper & Kroll, J. Phys. I France 6 (1996) 1305). Angle gradients: Bridson, Marino, Fedkiw,
// SCA 2003, section 4.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "membrane/mesh.hpp"
#include "membrane/model_context.hpp"
#include "membrane/node_gather.hpp"

namespace dld::membrane {

struct BendingParams {
  double kappa_b = 0.0;  ///< bending modulus [lattice energy]
};

class BendingModel {
 public:
  static constexpr std::string_view kName = "bending";
  /// Throws InputError unless kappa_b >= 0.
  BendingModel(const TriMesh& reference, const BendingParams& p);
  static constexpr std::string_view kSummary = "dihedral-angle bending (kappa_b)";
  /// Reads [membrane.{kName}] (keys: docs/membrane-scene-keys.md) into lattice parameters.
  static BendingModel from_scene(const std::optional<TomlSection>& table, const ModelContext& ctx);
  /// Moduli of order one on `reference`, for the tests every model must pass.
  static BendingModel for_test(const TriMesh& reference);
  /// One line with its lattice parameters, e.g. "skalak: kappa_s 1e-4, kappa_alpha 0.5".
  std::string describe() const;
  double energy(const Eigen::Ref<const Points>& x) const;
  double add_forces(const Eigen::Ref<const Points>& x, Eigen::Ref<Points> f) const;
  /// Signed dihedral angle of hinge h (for tests).
  static double angle(const Hinge& h, const Eigen::Ref<const Points>& x);
  const BendingParams& params() const { return p_; }

 private:
  BendingParams p_;
  std::vector<Hinge> hinges_;
  std::vector<double> theta0_;
  std::vector<double> cos0_, sin0_;  ///< of theta0: the deviation without an atan2 (see .cpp)
  std::vector<int> corners_;         ///< a, b, c, d of each hinge
  NodeGather gather_;
};

}  // namespace dld::membrane
