// SPDX-License-Identifier: MIT
// dld-capsule-shear: one capsule-in-shear run (tests/validation/capsule_shear.hpp); writes the
// shape time series as CSV and prints the steady Taylor deformation.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <fstream>
#include <iostream>
#include <stdexcept>

#include "capsule_shear.hpp"
#include "fluid/ib_kernel.hpp"
#include "shared/guarded_main.hpp"

static int run_main(int argc, char** argv) {
  using namespace dld::validation;
  CapsuleShearSetup s;
  std::string transport = "inproc", law = "neo_hookean", csv, kernel = "peskin4", collision = "trt";
  int box = 0;
  double settled = 0.3;
  CLI::App app{
      "Initially spherical capsule in simple shear (fluid and membrane as two threads "
      "over the coupler); lattice units"};
  app.add_option("--ca", s.capillary, "Ca = mu gammadot a / E_s, E_s = 3 G_s")->required();
  app.add_option("--radius", s.radius, "capsule radius a [lattice lengths]");
  app.add_option("--box", box, "cubic box edge [nodes] (sets nx, ny, nz)");
  app.add_option("--nx", s.nx);
  app.add_option("--ny", s.ny);
  app.add_option("--nz", s.nz, "wall distance H [nodes]");
  app.add_option("--faces", s.faces, "icosphere faces (20 * 4^n, nearest used)");
  app.add_option("--re", s.reynolds, "Re = gammadot a^2 / nu");
  app.add_option("--tau", s.tau, "relaxation time");
  app.add_option("--strain", s.strain, "run until gammadot t");
  app.add_option("--steps", s.steps, "run exactly this many steps instead");
  app.add_option("--sample-every", s.sample_every, "steps between shape samples");
  app.add_option("--law", law, "neo_hookean or skalak");
  app.add_option("--skalak-c", s.skalak_c, "Skalak C = kappa_alpha / kappa_s");
  app.add_option("--viscosity-ratio", s.viscosity_ratio, "lambda = inner / outer viscosity")
      ->check(CLI::PositiveNumber);
  app.add_option("--transport", transport, "inproc, ipc or tcp");
  app.add_option("--ib-kernel", kernel, "peskin2, peskin3 or peskin4");
  app.add_option("--collision", collision, "trt, bgk or mrt");
  app.add_option("--force-every", s.force_every,
                 "membrane forces every N steps, held in between ([coupling] force_every)")
      ->check(CLI::PositiveNumber);
  app.add_flag("--spread-held", s.spread_held,
               "spread force field held with the forces ([coupling] spread_held)");
  app.add_flag("--interpolation-held", s.interpolation_held,
               "with --spread-held, its interpolation weights too ([coupling] interpolation_held)");
  app.add_option("--settled", settled, "steady D: mean over the last fraction of the strain");
  app.add_option("--csv", csv, "write gammadot_t, D, inclination, volume ratio here");
  CLI11_PARSE(app, argc, argv);
  if (box > 0) s.nx = s.ny = s.nz = box;
  if (s.interpolation_held && !s.spread_held) {
    std::cerr << "dld-capsule-shear: error: --interpolation-held needs --spread-held\n";
    return 2;
  }
  try {
    s.transport = transport_from_name(transport);
    s.kernel = dld::fluid::ib_kernel_from_name(kernel);
    const auto& names = dld::kCollisionNames;
    const auto it = std::find(names.begin(), names.end(), collision);
    if (it == names.end())
      throw std::invalid_argument("--collision '" + collision + "': expected trt, bgk or mrt");
    s.collision = static_cast<dld::CollisionKind>(it - names.begin());
  } catch (const std::exception& e) {
    std::cerr << "dld-capsule-shear: error: " << e.what() << "\n";
    return 2;
  }
  if (law == "skalak")
    s.law = MembraneLaw::skalak;
  else if (law != "neo_hookean") {
    std::cerr << "dld-capsule-shear: error: --law must be neo_hookean or skalak\n";
    return 2;
  }
  try {
    const CapsuleShearRun r = run_capsule_shear(s);
    const double end = r.strain.back();
    const double from = (1.0 - settled) * end;
    if (!csv.empty()) {
      std::ofstream out(csv);
      out << "# capsule in shear: " << law << " Ca " << s.capillary << " a " << s.radius << " box "
          << s.nx << "x" << s.ny << "x" << s.nz << " faces " << r.faces << " Re " << s.reynolds
          << " tau " << s.tau << "\n# columns: gammadot_t, D, inclination_rad, volume_ratio\n";
      for (std::size_t i = 0; i < r.strain.size(); ++i)
        out << fmt::format("{:.6f}, {:.8f}, {:.8f}, {:.10f}\n", r.strain[i], r.deformation[i],
                           r.inclination[i], r.volume[i]);
    }
    fmt::print(
        "capsule {} Ca {} a {} box {}x{}x{} (a/H {:.4f}) faces {} nodes {} Re {} tau {} "
        "gammadot {:.4e} G_s {:.4e} transport {} kernel {} forces every {}\n",
        law, s.capillary, s.radius, s.nx, s.ny, s.nz, s.radius / s.nz, r.faces, r.nodes, s.reynolds,
        s.tau, r.gammadot, r.shear_modulus, name(s.transport), kernel, s.force_every);
    fmt::print(
        "steps {} wall {:.3f} s ({:.2f} ms/step); volume change {:.2e}; spread error {:.1e}\n",
        r.steps, r.wall_seconds, 1e3 * r.wall_seconds / r.steps, r.volume.back() - 1.0,
        r.spread_error);
    fmt::print(
        "steady D (mean over gammadot t >= {:.2f}) = {:.5f}; D at end {:.5f}; inclination "
        "{:.2f} deg\n",
        from, mean_deformation(r, from), r.deformation.back(), r.inclination.back() * 180.0 / M_PI);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "dld-capsule-shear: error: " << e.what() << "\n";
    return 1;
  }
}

int main(int argc, char** argv) {
  return dld::guarded_main("dld-capsule-shear", run_main, argc, argv);
}
