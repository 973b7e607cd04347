// SPDX-License-Identifier: MIT
#include "naive_bgk.hpp"

namespace dld::bench {
namespace {
const int kC[19][3] = {{0, 0, 0},  {1, 0, 0},   {-1, 0, 0},  {0, 1, 0},   {0, -1, 0},
                       {0, 0, 1},  {0, 0, -1},  {1, 1, 0},   {-1, -1, 0}, {1, -1, 0},
                       {-1, 1, 0}, {1, 0, 1},   {-1, 0, -1}, {1, 0, -1},  {-1, 0, 1},
                       {0, 1, 1},  {0, -1, -1}, {0, 1, -1},  {0, -1, 1}};
double weight(int i) {
  int n = kC[i][0] * kC[i][0] + kC[i][1] * kC[i][1] + kC[i][2] * kC[i][2];
  return n == 0 ? 1.0 / 3.0 : (n == 1 ? 1.0 / 18.0 : 1.0 / 36.0);
}
}  // namespace

NaiveBgk::NaiveBgk(int nx, int ny, int nz, double tau)
    : nx_(nx),
      ny_(ny),
      nz_(nz),
      omega_(1.0 / tau),
      f_(static_cast<std::size_t>(nx) * ny * nz * 19) {
  for (std::size_t n = 0; n < f_.size() / 19; ++n)
    for (int i = 0; i < 19; ++i) f_[n * 19 + i] = weight(i) * (1.0 + 0.01 * ((n * 7 + i) % 5));
  g_ = f_;
}

void NaiveBgk::step() {
#pragma omp parallel for
  for (int z = 0; z < nz_; ++z)
    for (int y = 0; y < ny_; ++y)
      for (int x = 0; x < nx_; ++x) {
        const std::size_t n = (static_cast<std::size_t>(z) * ny_ + y) * nx_ + x;
        double rho = 0, ux = 0, uy = 0, uz = 0;
        for (int i = 0; i < 19; ++i) {
          rho += f_[n * 19 + i];
          ux += f_[n * 19 + i] * kC[i][0];
          uy += f_[n * 19 + i] * kC[i][1];
          uz += f_[n * 19 + i] * kC[i][2];
        }
        ux /= rho;
        uy /= rho;
        uz /= rho;
        for (int i = 0; i < 19; ++i) {
          double cu = kC[i][0] * ux + kC[i][1] * uy + kC[i][2] * uz;
          double feq =
              weight(i) * rho * (1 + 3 * cu + 4.5 * cu * cu - 1.5 * (ux * ux + uy * uy + uz * uz));
          int xn = (x + kC[i][0] + nx_) % nx_, yn = (y + kC[i][1] + ny_) % ny_,
              zn = (z + kC[i][2] + nz_) % nz_;
          std::size_t m = (static_cast<std::size_t>(zn) * ny_ + yn) * nx_ + xn;
          g_[m * 19 + i] = f_[n * 19 + i] + omega_ * (feq - f_[n * 19 + i]);
        }
      }
  f_.swap(g_);
}

double NaiveBgk::mass() const {
  double m = 0;
  for (double v : f_) m += v;
  return m;
}

}  // namespace dld::bench
