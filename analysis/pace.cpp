// SPDX-License-Identifier: MIT
#include "analysis/pace.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "shared/input_error.hpp"

namespace dld::analysis {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// The step at which a cell reaches n pillars at its pace; the current step if it is there.
double step_at(const CellPace& c, double n, double first_step, double last_step) {
  if (c.pillars >= n) return last_step;
  return std::isfinite(c.steps_per_pillar) ? first_step + n * c.steps_per_pillar : kInf;
}

/// "12 345 678" (thin groups, as docs/ writes step counts), "-" for +inf.
std::string steps_text(double s) {
  if (!std::isfinite(s)) return "-";
  std::string digits = fmt::format("{:.0f}", s), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ' ';
    out += digits[i];
  }
  return out;
}

/// The first sample step from which on the track's x stays within `band` of its last x.
double still_since(const CellTrack& t, double band) {
  const double x_last = t.position.back()[0];
  std::size_t i = t.position.size() - 1;
  while (i > 0 && std::abs(t.position[i - 1][0] - x_last) < band) --i;
  return t.step[i];
}

}  // namespace

double RunPace::mean_steps_per_pillar() const {
  return mean_pillars > 0 ? (last_step - first_step) / mean_pillars : kInf;
}

double RunPace::step_every_cell_at(double n, int* slowest) const {
  double last = -kInf;
  for (const CellPace& c : cells) {
    const double s = step_at(c, n, first_step, last_step);
    if (s > last) {
      last = s;
      if (slowest) *slowest = c.id;
    }
  }
  return cells.empty() ? last_step : last;
}

std::vector<CellPace> RunPace::held_cells(double factor) const {
  std::vector<CellPace> held;
  const double pillar = mean_steps_per_pillar();
  if (!std::isfinite(pillar)) return held;
  for (const CellPace& c : cells)
    if (last_step - c.still_since > factor * pillar) held.push_back(c);
  return held;
}

RunPace run_pace(const Run& run) {
  RunPace p;
  std::vector<double> pillars;
  for (const CellTrack& t : run.cells) {
    if (t.step.size() < 2) {
      throw InputError(fmt::format("{}: cell {} has {} samples: the pace needs at least two",
                                   run.files.front(), t.id, t.step.size()));
    }
    p.first_step = t.step.front();
    p.last_step = t.step.back();
    CellPace c;
    c.id = t.id;
    c.pillars = (t.position.back()[0] - t.position.front()[0]) / run.lambda_um;
    const double elapsed = t.step.back() - t.step.front();
    c.steps_per_pillar = c.pillars > 0 ? elapsed / c.pillars : kInf;
    c.still_since = still_since(t, 0.25 * run.lambda_um);
    c.x_um = t.position.back()[0];
    c.y_um = t.position.back()[1];
    pillars.push_back(c.pillars);
    p.cells.push_back(c);
  }
  double sum = 0;
  for (const double v : pillars) sum += v;
  p.mean_pillars = pillars.empty() ? 0 : sum / static_cast<double>(pillars.size());
  p.median_pillars = median(pillars);
  return p;
}

std::string format_pace(const Run& run, const RunPace& p, int n) {
  std::string s = fmt::format(
      "run {} ({} cells): pace from step {} to {}, pillars as (x - x0) / lambda\n"
      "cell  pillars  steps per pillar  step at {} pillars\n",
      run.scene_name, p.cells.size(), steps_text(p.first_step), steps_text(p.last_step), n);
  for (const CellPace& c : p.cells) {
    s += fmt::format("{:4}  {:7.3f}  {:>16}  {:>17}\n", c.id, c.pillars,
                     steps_text(c.steps_per_pillar),
                     steps_text(step_at(c, n, p.first_step, p.last_step)));
  }
  int slowest = -1;
  const double end = p.step_every_cell_at(n, &slowest);
  s += fmt::format(
      "mean {:.3f} pillars ({} steps per pillar), median {:.3f}\n"
      "every cell at {} pillars (the stop rule) at the pace so far: step {} (cell {} last)\n",
      p.mean_pillars, steps_text(p.mean_steps_per_pillar()), p.median_pillars, n, steps_text(end),
      slowest);
  for (const CellPace& c : p.held_cells()) {
    s += fmt::format(
        "held: cell {} has stayed within lambda/4 in x since step {} ({} steps, {:.1f} times the "
        "mean cell's steps per pillar), at ({:.1f}, {:.1f}) um: its pace so far is no forecast\n",
        c.id, steps_text(c.still_since), steps_text(p.last_step - c.still_since),
        (p.last_step - c.still_since) / p.mean_steps_per_pillar(), c.x_um, c.y_um);
  }
  return s;
}

std::string write_pace_csv(const RunPace& p, int n, const std::string& dir,
                           const std::string& base) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  std::string path = (std::filesystem::path(dir) / (base + "-pace.csv")).string();
  std::ofstream out(path);
  out << "cell,pillars,steps_per_pillar,step_at_" << n << "_pillars,still_since_step\n";
  for (const CellPace& c : p.cells) {
    const double at = step_at(c, n, p.first_step, p.last_step);
    out << fmt::format(
        "{},{:.4f},{},{},{:.0f}\n", c.id, c.pillars,
        std::isfinite(c.steps_per_pillar) ? fmt::format("{:.0f}", c.steps_per_pillar) : "",
        std::isfinite(at) ? fmt::format("{:.0f}", at) : "", c.still_since);
  }
  if (!out) throw InputError(fmt::format("{}: cannot write", path));
  return path;
}

}  // namespace dld::analysis
