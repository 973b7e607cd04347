// SPDX-License-Identifier: MIT
#include "analysis/report.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "shared/input_error.hpp"

namespace dld::analysis {
namespace {

std::string outlet_name(int o) {
  return o == 0 ? "below O1" : o == 5 ? "above O4" : o < 0 ? "-" : fmt::format("O{}", o);
}

/// A number for the CSVs: empty when it is not a number (undefined std, no p_f).
std::string csv_number(double v) {
  return std::isfinite(v) ? fmt::format("{:.9g}", v) : std::string();
}

std::string csv_text(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    q += c == '"' ? std::string("\"\"") : std::string(1, c);
  }
  return q + "\"";
}

void write_file(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p);
  out << text;
  if (!out) {
    throw InputError(fmt::format("{}: cannot write", p.string()));
  }
}

}  // namespace

std::string failure_name(const ExpectedMode& expected) {
  if (expected.mode == TransportMode::kZigzag) {
    return "p_fZ";
  }
  if (expected.mode == TransportMode::kDisplacement) {
    return "p_fD";
  }
  return "p_f";
}

bool correct_outlet(const ExpectedMode& expected, int outlet) {
  if (expected.mode == TransportMode::kZigzag) {
    return outlet == 1 || outlet == 2;
  }
  if (expected.mode == TransportMode::kDisplacement) {
    return outlet == 3 || outlet == 4;
  }
  return false;
}

std::string format_report(const Run& run, const RunAnalysis& a) {
  std::string s = fmt::format(
      "run {} (scene {}): {} cell(s) in {} file(s), lambda = {} um, d = {} um (d/lambda = {:.4f}), "
      "Ca = {}\n",
      run.stem, run.scene_name, run.cells.size(), run.files.size(), run.lambda_um, run.row_shift_um,
      run.row_shift_um / run.lambda_um,
      run.capillary_number ? fmt::format("{}", *run.capillary_number) : std::string("not given"));
  for (const auto& f : run.skipped) {
    s += fmt::format("note: skipped {} (a checkpoint, not a run file)\n", f);
  }
  s += fmt::format("expected mode: {} ({})\n",
                   a.expected.known() ? to_string(a.expected.mode) : "unknown", a.expected.source);
  if (!a.expected.known()) {
    s += "no failure probability: the expected mode is not known\n";
  }
  s += fmt::format("evaluated at N = {} pillars from each cell's start\n", a.pillars_requested);
  for (const auto& n : a.notes) {
    s += "note: " + n + "\n";
  }
  const std::string pf = failure_name(a.expected);
  s += fmt::format("{:>5} {:>8} {:>15} {:>12} {:>8} {:>10} {:>10} {:>9} {:>8}\n", "cell", "columns",
                   "shift/col [um]", "mode", "pillars", "y0 [um]", "y(N) [um]", pf, "outlet");
  for (std::size_t k = 0; k < a.cells.size(); ++k) {
    const CellResult& r = a.cells[k];
    s += fmt::format("{:>5} {:>8} {:>15.3f} {:>12} {:>8} {:>10.3f} {:>10} {:>9} {:>8}\n", r.id,
                     r.columns, r.shift_per_column, to_string(r.mode), r.pillars, r.y0,
                     r.pillars > 0 ? fmt::format("{:.3f}", r.y_end) : "-",
                     r.p_f ? fmt::format("{:.4f}", *r.p_f) : "-", outlet_name(a.outlet_of_cell[k]));
  }
  if (a.expected.known()) {
    s += fmt::format(
        "{} over {} cell(s): mean +- standard deviation {:.4f} +- {}; ceiling of p_fD: "
        "d/lambda = {:.4f}\n",
        pf, a.p_f.n, a.p_f.mean,
        std::isfinite(a.p_f.std) ? fmt::format("{:.4f}", a.p_f.std) : "n/a (one cell)",
        run.row_shift_um / run.lambda_um);
  }
  s += fmt::format(
      "outlets after {} columns (inlet band [{}, {}] um, outlets span [{:.1f}, {:.1f}] um):",
      a.outlet_pillars, a.bins.y_in, a.bins.y_in + run.lambda_um, a.bins.edges.front(),
      a.bins.edges.back());
  for (int o = 1; o <= 4; ++o) {
    s += fmt::format(
        "  O{} {:.3f}{}", o, a.outlets.fraction(o),
        a.expected.known() ? (correct_outlet(a.expected, o) ? " (correct)" : " (wrong)") : "");
  }
  s += "\n";
  if (a.outlets.count[0] + a.outlets.count[5] > 0) {
    s += fmt::format("outside the outlets: {} below O1, {} above O4\n", a.outlets.count[0],
                     a.outlets.count[5]);
  }
  s += fmt::format(
      "run: {:.0f} steps, slowest cell {:.2f} pillars, largest volume change {:.3f} %\n",
      a.last_step, a.slowest_advance, 100 * a.volume_change);
  return s;
}

std::vector<std::string> write_csvs(const Run& run, const RunAnalysis& a, const std::string& dir,
                                    const std::string& base) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    throw InputError(fmt::format("{}: cannot create output directory ({})", dir, ec.message()));
  }
  const fs::path root(dir);
  const std::string pf = failure_name(a.expected);

  std::string cells = fmt::format(
      "cell,x0_um,y0_um,columns,pillars,y_end_um,shift_per_column_um,mode,{},outlet\n", pf);
  for (std::size_t k = 0; k < a.cells.size(); ++k) {
    const CellResult& r = a.cells[k];
    cells += fmt::format("{},{},{},{},{},{},{},{},{},{}\n", r.id, csv_number(r.x0),
                         csv_number(r.y0), r.columns, r.pillars,
                         r.pillars > 0 ? csv_number(r.y_end) : "", csv_number(r.shift_per_column),
                         to_string(r.mode), r.p_f ? csv_number(*r.p_f) : "",
                         a.outlet_of_cell[k] < 0 ? "" : outlet_name(a.outlet_of_cell[k]));
  }

  std::string summary =
      "scene_name,pillar_spacing_um,row_shift_um,capillary_number,cells,pillars,expected_mode,"
      "expected_source,failure,p_f_mean,p_f_std,p_f_cells,p_fD_ceiling,outlet_pillars,O1,O2,O3,"
      "O4,outside,steps,slowest_cell_pillars,largest_volume_change_percent\n";
  summary +=
      fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.0f},{:.3f},{:.4f}\n",
                  csv_text(run.scene_name), csv_number(run.lambda_um), csv_number(run.row_shift_um),
                  run.capillary_number ? csv_number(*run.capillary_number) : "", run.cells.size(),
                  a.pillars_requested, a.expected.known() ? to_string(a.expected.mode) : "unknown",
                  csv_text(a.expected.source), pf, a.expected.known() ? csv_number(a.p_f.mean) : "",
                  a.expected.known() ? csv_number(a.p_f.std) : "", a.p_f.n,
                  csv_number(run.row_shift_um / run.lambda_um), a.outlet_pillars,
                  csv_number(a.outlets.fraction(1)), csv_number(a.outlets.fraction(2)),
                  csv_number(a.outlets.fraction(3)), csv_number(a.outlets.fraction(4)),
                  csv_number(a.outlets.fraction(0) + a.outlets.fraction(5)), a.last_step,
                  a.slowest_advance, 100 * a.volume_change);

  std::string outlets = "outlet,y_low_um,y_high_um,count,fraction,correct\n";
  for (int o = 1; o <= 4; ++o) {
    outlets += fmt::format(
        "O{},{},{},{},{},{}\n", o, csv_number(a.bins.edges[static_cast<std::size_t>(o - 1)]),
        csv_number(a.bins.edges[static_cast<std::size_t>(o)]),
        a.outlets.count[static_cast<std::size_t>(o)], csv_number(a.outlets.fraction(o)),
        a.expected.known() ? (correct_outlet(a.expected, o) ? "yes" : "no") : "");
  }
  outlets += fmt::format("outside,,,{},{},{}\n", a.outlets.count[0] + a.outlets.count[5],
                         csv_number(a.outlets.fraction(0) + a.outlets.fraction(5)),
                         a.expected.known() ? "no" : "");

  std::vector<std::string> paths;
  for (const auto& [suffix, text] :
       {std::pair{"-cells.csv", &cells}, std::pair{"-summary.csv", &summary},
        std::pair{"-outlets.csv", &outlets}}) {
    const fs::path p = root / (base + suffix);
    write_file(p, *text);
    paths.push_back(p.string());
  }
  return paths;
}

}  // namespace dld::analysis
