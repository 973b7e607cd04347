// SPDX-License-Identifier: MIT
// Harmonic spring network on the mesh edges: E = (k/2) sum over edges of (l - l0)^2, l0 the rest
// length of each edge. The simplest discrete membrane (Dao, Li & Suresh, Mater. Sci. Eng. C 26
// (2006) 1232, with linear instead of worm-like-chain springs); an equilateral triangular
// network of such springs has the in-plane shear modulus sqrt(3) k / 4 (Seung & Nelson, Phys.
// Rev. A 38 (1988) 1005). Added as the proof that a model is one file plus its line in
// membrane/model_registry.hpp (issue 15).
#pragma once
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "membrane/mesh.hpp"
#include "membrane/model_context.hpp"

namespace dld::membrane {

struct SpringParams {
  double k = 0.0;  ///< spring constant [lattice modulus, energy / length^2]
};

class SpringNetwork {
 public:
  static constexpr std::string_view kName = "springs";
  static constexpr std::string_view kSummary = "harmonic springs on the mesh edges (k)";
  /// Throws InputError unless k >= 0.
  SpringNetwork(const TriMesh& reference, const SpringParams& p);
  /// Reads [membrane.springs] modulus_rel = k / kappa_s (docs/membrane-scene-keys.md).
  static SpringNetwork from_scene(const std::optional<TomlSection>& table, const ModelContext& ctx);
  static SpringNetwork for_test(const TriMesh& reference);
  std::string describe() const;

  double energy(const Eigen::Ref<const Points>& x) const;
  double add_forces(const Eigen::Ref<const Points>& x, Eigen::Ref<Points> f) const;
  const SpringParams& params() const { return p_; }

 private:
  SpringParams p_;
  std::vector<std::array<int, 2>> edges_;
  std::vector<double> rest_;  ///< l0 of each edge [lattice lengths]
};

}  // namespace dld::membrane
