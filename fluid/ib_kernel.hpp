// SPDX-License-Identifier: MIT
// Regularised delta kernels of the immersed-boundary method, one axis; the 3-D weight is the
// product over axes. r = |x| in lattice units. Peskin, Acta Numerica 11 (2002) 479, sec. 6;
// formulas as collected in ../shared/reference/README.md.
#pragma once
#include <cmath>
#include <string>

namespace dld::fluid {

enum class IbKernel { kPeskin2 = 2, kPeskin3 = 3, kPeskin4 = 4 };

/// Half-width of the kernel's support: phi(r) = 0 for r >= half_width.
inline double half_width(IbKernel k) {
  return 0.5 * static_cast<int>(k);
}

inline double phi(IbKernel k, double x) {
  const double r = std::abs(x);
  switch (k) {
    case IbKernel::kPeskin2:
      return r < 1.0 ? 1.0 - r : 0.0;
    case IbKernel::kPeskin3:
      if (r <= 0.5) return (1.0 + std::sqrt(1.0 - 3.0 * r * r)) / 3.0;
      if (r < 1.5) return (5.0 - 3.0 * r - std::sqrt(-2.0 + 6.0 * r - 3.0 * r * r)) / 6.0;
      return 0.0;
    case IbKernel::kPeskin4:
      if (r < 1.0) return (3.0 - 2.0 * r + std::sqrt(1.0 + 4.0 * r - 4.0 * r * r)) / 8.0;
      if (r < 2.0) return (5.0 - 2.0 * r - std::sqrt(-7.0 + 12.0 * r - 4.0 * r * r)) / 8.0;
      return 0.0;
  }
  return 0.0;
}

/// "peskin2", "peskin3", "peskin4".
IbKernel ib_kernel_from_name(const std::string& name);

}  // namespace dld::fluid
