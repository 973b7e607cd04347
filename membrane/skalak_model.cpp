// SPDX-License-Identifier: MIT
#include "membrane/skalak_model.hpp"

#include <fmt/format.h>

#include <cmath>

#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {
const SkalakLaw& checked(const SkalakLaw& l) {
  if (!(l.p.kappa_s > 0.0) || !std::isfinite(l.p.kappa_s))
    throw InputError(fmt::format("skalak model: kappa_s must be positive, got {}", l.p.kappa_s));
  if (!(l.p.kappa_alpha >= 0.0) || !std::isfinite(l.p.kappa_alpha))
    throw InputError(
        fmt::format("skalak model: kappa_alpha must be >= 0, got {}", l.p.kappa_alpha));
  return l;
}
}  // namespace

SkalakModel::SkalakModel(const TriMesh& reference, const SkalakParams& p)
    : TriangleElements<SkalakLaw>(reference, checked(SkalakLaw{p}), "skalak") {}

}  // namespace dld::membrane
