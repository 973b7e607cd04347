// SPDX-License-Identifier: MIT
// The coupled mode of dld-membrane: the cells of this process (an equal share of the scene's
// [[cells.cell]] list) exchange positions and forces for velocities with dld-fluid every step,
// and move with the fluid (no-slip: X += U dt, dt = 1 in lattice units).
// Output (membrane/cells_part_file): per-cell centroid (device frame, um: cells are never folded
// into the box) and volume every `sample_every` steps, and with [output] mesh_every the nodes of
// every cell every that many steps (membrane/mesh_output), each appended and flushed as taken.
// Progress lines give pillars passed, steps/s, the ETA to the pillar target and the modes.
#include "membrane/coupled_main.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "coupler/endpoint.hpp"
#include "coupler/error.hpp"
#include "coupler/membrane_side.hpp"
#include "coupler/scene_identity.hpp"
#include "membrane/cells_part_file.hpp"
#include "membrane/mesh_output.hpp"
#include "membrane/run_checkpoint.hpp"
#include "membrane/stability_guard.hpp"
#include "membrane/triangle_watch.hpp"
#include "membrane/volume_correction.hpp"
#include "shared/column_tracker.hpp"
#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {

volatile sig_atomic_t g_stop = 0;
void on_sigint(int) {
  g_stop = 1;
}

std::optional<double> capillary_number(const Scene& scene) {
  if (const auto* v =
          scene.document->root().at_path("membrane.capillary_number").as_floating_point())
    return v->get();
  return std::nullopt;
}

using Clock = std::chrono::steady_clock;

/// This machine's name, printable ASCII only (it goes into every coupler message about this
/// process: with processes on several hosts, a fault names where it happened).
std::string host_name() {
  char buf[65] = {};
  if (gethostname(buf, sizeof buf - 1) != 0 || buf[0] == 0) return "unknown-host";
  std::string h(buf);
  for (char& c : h)
    if (c < 0x21 || c > 0x7e) c = '?';
  return h;
}

/// This process's share of the scene's cells: [first, last) of all of them. Contact with cells of
/// other processes goes through the contact halo the fluid sends (coupler/halo.hpp).
struct Share {
  CellSet cells;
  int total = 0, first = 0;
};

Share share_of(const Scene& scene, const MembraneScene& m, const CoupledArgs& a) {
  const CellSet all = build_cells(m, scene);
  const int total = all.cell_count();
  const int first = total * a.peer / a.peers, last = total * (a.peer + 1) / a.peers;
  CellSet cells(all.reference(), all.mechanics(), all.contact());
  for (int k = first; k < last; ++k) cells.add_cell(Points(all.cell_positions(k)));
  cells.set_ghosts({first, {}, {}});
  return {std::move(cells), total, first};
}

/// The contact halo this process needs: other processes' cells can touch its own only with cell
/// contact on and the cells split over several processes.
double halo_width(const Share& s, const CoupledArgs& a) {
  const auto& contact = s.cells.contact();
  if (a.peers == 1 || s.total == s.cells.cell_count() || !contact || !contact->params().cells)
    return 0.0;
  return contact->halo_width();
}

/// One coupled run of this process's cells, in named steps: set-up (connect, resume), the step
/// loop, and its samples, checkpoints, progress lines and summary.
class CoupledRun {
 public:
  CoupledRun(const Scene& scene, const MembraneScene& m, const CoupledArgs& a);
  int run();

 private:
  coupler::MembraneConfig config() const;
  void resume();
  void open_output();
  std::string step_loop(std::int64_t& s);
  std::int64_t held_steps(std::int64_t s) const;
  void after_steps(std::int64_t e, std::string& stop);
  void sample(std::int64_t step);
  void sample_mesh(std::int64_t step) {
    if (mesh_) mesh_->append(step, cells_.positions() * dx_um_);
  }
  void checkpoint(std::int64_t step);
  void apply_halo();
  void progress(std::int64_t step) const;
  void summary() const;
  std::string state_at_stop(std::int64_t step);
  void restore_volumes();
  double slowest_columns() const;
  std::vector<Eigen::Vector3d> centroids_um() const;
  std::vector<Eigen::Vector3d> row_centroids(std::size_t r) const;

  const Scene& scene_;
  const CoupledArgs& a_;
  Share share_;
  CellSet& cells_ = share_.cells;
  const int first_ = share_.first;
  const double dx_um_;
  const double halo_;  // contact halo width [lattice lengths], 0: none
  std::vector<double> v0_;
  std::vector<double>
      restored_;         // each cell's volume given back ([coupling] volume_correction_every)
  std::int64_t at_ = 0;  // the step cells_'s positions are at (for an error's state_at_stop)
  coupler::MembraneSide side_;
  RunFacts facts_;
  RunCheckpoint expected_;
  std::int64_t offset_ = 0;
  std::int64_t checkpointed_ = -1;  ///< step of the last checkpoint written
  std::vector<double> rows_;  ///< samples: step, then per cell centroid [um] and volume [um^3]
  std::size_t width_;
  std::optional<ColumnTracker> tracker_;
  double done_at_start_ = 0;
  // Stops the run at once when a cell goes unstable; no checkpoint is written after that, so the
  // last one on disk is the last good state.
  std::optional<StabilityGuard> guard_;
  std::optional<TriangleWatch> watch_;  // smallest triangle area ratios, for warnings and lines
  std::optional<CellsPartFile> part_;   // made once connected: an error then reaches the fluid
  std::optional<MeshOutput> mesh_;
  Clock::time_point start_;
  double t_membrane_ = 0, t_exchange_ = 0;
  std::int64_t halo_steps_ = 0, halo_cells_ = 0;
  long halo_pairs_ = 0;  // most contact pairs with ghost nodes in one step
};

std::vector<double> volumes(const CellSet& cells) {
  std::vector<double> v;
  v.reserve(static_cast<std::size_t>(cells.cell_count()));
  for (int k = 0; k < cells.cell_count(); ++k) v.push_back(cells.volume(k));
  return v;
}

CoupledRun::CoupledRun(const Scene& scene, const MembraneScene& m, const CoupledArgs& a)
    : scene_(scene),
      a_(a),
      share_(share_of(scene, m, a)),
      dx_um_(scene.lattice.dx_um),
      halo_(halo_width(share_, a)),
      v0_(volumes(cells_)),
      side_(config()),
      facts_{cells_.cell_count(), first_,     scene.units().dt_s(),    scene.cell_um.lambda,
             scene.cell_um.shift, scene.name, capillary_number(scene), m.expected_mode},
      expected_{0, scene.hash, first_, cells_.cell_count(), cells_.nodes_per_cell(), {}, {}},
      width_(1 + 4 * static_cast<std::size_t>(cells_.cell_count())) {
  // Another process's cells reach this one's contact as halos made from positions before a
  // correction: the split run would differ from the one-process run (and a resume from both).
  if (scene.coupling.volume_correction_every > 0 && halo_ > 0)
    throw InputError(fmt::format(
        "{}: [coupling] volume_correction_every: not with cells in contact across {} membrane "
        "processes (their contact halos would miss the correction); run one membrane process",
        scene.file, a.peers));
  // Every cell shares the reference mesh's triangles; the fluid needs them for the inside/outside
  // viscosity field (protocol v2), so they are sent once, in the hello.
  side_.set_cell_surfaces(
      std::vector<std::uint32_t>(static_cast<std::size_t>(cells_.cell_count()),
                                 static_cast<std::uint32_t>(cells_.reference().face_count())),
      face_indices(cells_.reference(), cells_.cell_count()));
  resume();
  guard_.emplace(scene.cell_lu(), dx_um_, GuardLimits{}, v0_);
  watch_.emplace(cells_.reference());
}

coupler::MembraneConfig CoupledRun::config() const {
  coupler::MembraneConfig mc;
  mc.scene = coupler::scene_identity(scene_, static_cast<std::uint32_t>(share_.total));
  mc.endpoint = coupler::peer_endpoints(a_.endpoint, static_cast<std::size_t>(a_.peers))[a_.peer];
  mc.name = fmt::format("membrane-{}@{}", a_.peer, host_name());  // messages name the host too
  mc.peer_index = static_cast<std::uint32_t>(a_.peer);
  mc.peer_count = static_cast<std::uint32_t>(a_.peers);
  mc.contact_halo = halo_;
  mc.first_cell = static_cast<std::uint32_t>(first_);
  mc.cell_nodes.assign(static_cast<std::size_t>(cells_.cell_count()),
                       static_cast<std::uint32_t>(cells_.nodes_per_cell()));
  mc.options.timeout =
      std::chrono::milliseconds(static_cast<long>(scene_.coupling.timeout_s * 1000));
  mc.options.curve =
      coupler::curve_for(mc.endpoint, a_.security, coupler::Side::client, "dld-membrane");
  return mc;
}

std::vector<Eigen::Vector3d> CoupledRun::centroids_um() const {
  std::vector<Eigen::Vector3d> c;
  c.reserve(static_cast<std::size_t>(cells_.cell_count()));
  for (int k = 0; k < cells_.cell_count(); ++k) c.push_back(cells_.centroid(k) * dx_um_);
  return c;
}

std::vector<Eigen::Vector3d> CoupledRun::row_centroids(std::size_t r) const {
  std::vector<Eigen::Vector3d> c;
  for (int k = 0; k < cells_.cell_count(); ++k) {
    const double* v = &rows_[r * width_ + 1 + 4 * static_cast<std::size_t>(k)];
    c.emplace_back(v[0], v[1], v[2]);
  }
  return c;
}

double CoupledRun::slowest_columns() const {  // columns of the slowest cell, fractional
  double done = 0;
  for (int k = 0; k < cells_.cell_count(); ++k)
    done =
        k == 0 ? tracker_->fractional_columns(k) : std::min(done, tracker_->fractional_columns(k));
  return done;
}

// Resuming: the cells' nodes and the samples so far come from the checkpoint, and the tracker
// replays the samples from the cells' starts.
void CoupledRun::resume() {
  if (!a_.resume.empty()) {
    RunCheckpoint c = read_run_checkpoints(a_.resume, expected_);
    cells_.positions() = c.positions;
    rows_ = std::move(c.rows);
    offset_ = c.step;
    spdlog::info("resumed from {} at step {}", fmt::join(a_.resume, " "), offset_);
  }
  tracker_.emplace(facts_.lambda_um, facts_.row_shift_um,
                   rows_.empty() ? centroids_um() : row_centroids(0));
  for (std::size_t r = 1; r < rows_.size() / width_; ++r) tracker_->update(row_centroids(r));
  done_at_start_ = slowest_columns();
}

void CoupledRun::checkpoint(std::int64_t step) {
  // Once per step: a second write would push the older checkpoint out of .prev.
  if (a_.checkpoint.empty() || step == checkpointed_) return;
  checkpointed_ = step;
  RunCheckpoint c = expected_;
  c.step = step;
  c.positions = cells_.positions();
  c.rows = rows_;
  write_run_checkpoint(a_.checkpoint, c);
}

// The other processes' cells near this one's, at the positions of the next force computation.
void CoupledRun::apply_halo() {
  if (halo_ == 0) return;
  const coupler::Halo& h = side_.halo();
  ContactGhosts g{first_, std::vector<int>(h.cells.begin(), h.cells.end()), Points()};
  for (std::size_t i = 0; i < h.cells.size(); ++i) {
    if (h.nodes[i] != static_cast<std::uint32_t>(cells_.nodes_per_cell()))
      throw InputError(fmt::format(
          "contact halo: cell {} has {} nodes, this process's cells {} (every membrane process "
          "must use the same mesh)",
          h.cells[i], h.nodes[i], cells_.nodes_per_cell()));
  }
  g.x = Eigen::Map<const Points>(h.positions.data(), 3,
                                 static_cast<Eigen::Index>(h.positions.size() / 3));
  halo_cells_ += std::ssize(h.cells);
  ++halo_steps_;
  cells_.set_ghosts(std::move(g));
}

void CoupledRun::open_output() {
  const std::int64_t mesh_every = scene_.output.mesh_every;
  if (a_.output.empty()) {
    if (mesh_every > 0) spdlog::warn("[output] mesh_every: no output file (-o), no meshes");
    return;
  }
  part_.emplace(a_.output, facts_, rows_,
                a_.resume.empty() ? std::nullopt : std::optional<std::int64_t>(offset_));
  if (mesh_every > 0) {
    mesh_.emplace(part_->file(), cells_.reference(), cells_.cell_count(), first_, facts_.dt_s);
  } else {
    // An earlier run's XDMF would name meshes this part file does not hold.
    std::error_code ignored;
    std::filesystem::remove(mesh_xdmf_path(a_.output), ignored);
  }
}

void CoupledRun::sample(std::int64_t step) {
  const std::size_t begin = rows_.size();
  rows_.push_back(static_cast<double>(step));
  const auto c = centroids_um();
  for (int k = 0; k < cells_.cell_count(); ++k)
    rows_.insert(rows_.end(),
                 {c[k].x(), c[k].y(), c[k].z(), cells_.volume(k) * dx_um_ * dx_um_ * dx_um_});
  tracker_->update(c);
  if (part_)
    part_->append(
        std::vector<double>(rows_.begin() + static_cast<std::ptrdiff_t>(begin), rows_.end()));
}

void CoupledRun::progress(std::int64_t step) const {
  const double secs = std::chrono::duration<double>(Clock::now() - start_).count();
  const double done = slowest_columns();
  std::string eta;
  if (a_.pillars > 0 && done - done_at_start_ > 0.05)
    eta = fmt::format("  ETA {:.0f} s", secs * (a_.pillars - done) / (done - done_at_start_));
  std::string modes;
  for (int k = 0; k < cells_.cell_count() && k < 4; ++k)
    modes += fmt::format(
        " {}:{}{}", first_ + k, to_string(tracker_->mode(k)),
        tracker_->mode(k) != TransportMode::kUndecided && !tracker_->certain(k) ? "?" : "");
  const int worst = watch_->worst_cell_now();
  const std::string triangles =
      worst < 0 ? std::string()
                : fmt::format("  smallest triangle {:.2f} of rest area (cell {})",
                              watch_->now(worst), first_ + worst);
  spdlog::info("step {:>9}  pillars passed {:.2f}{}  {:.1f} steps/s{}  modes{}{}", step, done,
               a_.pillars > 0 ? fmt::format("/{}", a_.pillars) : std::string(),
               static_cast<double>(step - offset_) / secs, eta, modes, triangles);
}

// The membranes when a run stops on an error: collapsed triangles came before every late stop of
// the dense runs (docs/results-history.md, "Why the dense runs go unstable late"), so the error
// line names the cells that have them. Reads positions only.
std::string CoupledRun::state_at_stop(std::int64_t step) {
  try {  // called in the error handlers: nothing here may replace the error it adds to
    if (!cells_.positions().allFinite())
      return fmt::format("; membranes at step {}: node positions not finite", step);
    watch_->update(cells_, step, first_);  // its first-time warnings would repeat what follows
    const int worst = watch_->worst_cell_now();
    if (worst < 0) return "";
    std::string below;
    for (int k = 0; k < cells_.cell_count(); ++k)
      if (watch_->now(k) < TriangleWatch::kSkalakPeak)
        below +=
            fmt::format("{}{} ({:.3f})", below.empty() ? "" : ", ", first_ + k, watch_->now(k));
    return fmt::format("; membranes at step {}: smallest triangle {:.3f} of rest area (cell {}){}",
                       step, watch_->now(worst), first_ + worst,
                       below.empty()
                           ? std::string()
                           : "; cells with triangles below 1/sqrt(3) of rest area, where Skalak's "
                             "area term weakens: " +
                                 below);
  } catch (...) {
    return "";
  }
}

void CoupledRun::summary() const {
  for (int k = 0; k < cells_.cell_count(); ++k)
    spdlog::info(
        "summary: cell {}  mode {}  columns {}  lateral shift per column {:.3f} um "
        "(d = {} um)  volume change {:+.3f} % (largest {:.3f} %)  deepest node in a wall or "
        "the pillar {:.3f} um  smallest triangle {:.3f} of rest area",
        first_ + k, to_string(tracker_->final_mode(k)), tracker_->columns(k),
        tracker_->shift_per_column(k), facts_.row_shift_um,
        100 * (cells_.volume(k) / v0_[static_cast<std::size_t>(k)] - 1),
        100 * guard_->worst_volume_change(k), guard_->worst_penetration_um(k), watch_->smallest(k));
  if (!restored_.empty())
    for (int k = 0; k < cells_.cell_count(); ++k)
      spdlog::info(
          "summary: cell {}  volume given back since this start {:+.4f} % ([coupling] "
          "volume_correction_every {})",
          first_ + k, 100 * restored_[static_cast<std::size_t>(k)],
          scene_.coupling.volume_correction_every);
}

// Steps from s to the next one at which this program has work: a force update, a sample, a mesh,
// a checkpoint, a progress line or the last step. With forces held ([coupling] force_every > 1)
// the fluid runs the steps in between and moves the nodes itself (coupler/membrane_side.hpp,
// advance_held): the same sums, bit for bit, without waking this program every step.
std::int64_t CoupledRun::held_steps(std::int64_t s) const {
  if (scene_.coupling.force_every == 1 || a_.exchange_every_step) return 1;
  std::int64_t next = a_.steps;
  const auto up_to_next = [&](std::int64_t every) {
    if (every > 0) next = std::min(next, (s / every + 1) * every);
  };
  // [coupling] volume_correction_every is a multiple of force_every (shared/scene.cpp): no wake-up
  // of its own.
  for (const std::int64_t every : std::initializer_list<std::int64_t>{
           scene_.coupling.force_every, a_.sample_every, scene_.output.mesh_every,
           a_.checkpoint_every, scene_.run.log_every})
    up_to_next(every);
  return next - s;
}

// The steps from s on: forces, the exchange (which includes waiting for the fluid's step), moving
// the nodes (no-slip: X += U dt, dt = 1), then samples, stop rules, checkpoints and progress; n > 1
// held steps at a time where the forces are held (held_steps()). Returns why it ended; wall time
// goes to t_membrane_ (forces, moving the nodes) and t_exchange_ (the exchange, which includes
// waiting for the fluid's steps).
std::string CoupledRun::step_loop(std::int64_t& s) {
  Points force;
  std::vector<double> u(static_cast<std::size_t>(3 * cells_.node_count()));
  const std::int64_t s0 = s;
  const std::int64_t force_every = scene_.coupling.force_every;
  // A run that is to end (interrupted, or a stop rule met) ends at the next step a resume from its
  // checkpoint repeats exactly; the fluid does the same on an interrupt (fluid/coupled_main.cpp).
  // Such steps are multiples of force_every, so a run of held steps never passes one.
  const std::int64_t exact_every = scene_.coupling.exact_resume_every();
  std::string stop;
  for (std::int64_t n = 1; s < a_.steps; s += n) {
    if (stop.empty() && g_stop) stop = "interrupted";
    if (!stop.empty() && s % exact_every == 0) return stop;
    const auto t0 = Clock::now();
    // Time-scale separation ([coupling] force_every): between updates the last forces are held.
    if (s % force_every == 0 || s == s0) {
      cells_.compute_forces(force);
      if (cells_.contact())
        halo_pairs_ = std::max(halo_pairs_, cells_.contact()->last_ghost_pair_count());
    }
    const std::span<const double> f(force.data(), static_cast<std::size_t>(force.size()));
    n = held_steps(s);
    const auto t1 = Clock::now();
    Points& x = cells_.positions();
    if (n == 1) {
      if (!side_.advance(cells_.flat_positions(), f, u)) return "the fluid ended the run";
    } else if (!side_.advance_held(
                   cells_.flat_positions(), f, static_cast<std::uint64_t>(n),
                   std::span<double>(x.data(), static_cast<std::size_t>(x.size())))) {
      return "the fluid ended the run";
    }
    const auto t2 = Clock::now();
    if (n == 1) cells_.move(std::span<const double>(u), 1.0);
    apply_halo();
    t_membrane_ += std::chrono::duration<double>(t1 - t0 + (Clock::now() - t2)).count();
    t_exchange_ += std::chrono::duration<double>(t2 - t1).count();
    after_steps(s + n, stop);
  }
  return stop.empty() ? "step limit reached" : stop;
}

// What follows the steps up to e: meshes, samples with the guard and the stop rules, checkpoints
// and the progress line, each at its own multiple.
void CoupledRun::after_steps(std::int64_t e, std::string& stop) {
  at_ = e;
  const std::int64_t mesh_every = scene_.output.mesh_every;
  if (mesh_every > 0 && e % mesh_every == 0) sample_mesh(e);
  if (e % a_.sample_every == 0) {
    sample(e);
    guard_->check(cells_, e, first_);
    for (const std::string& w : watch_->update(cells_, e, first_)) spdlog::warn("{}", w);
    if (stop.empty() && a_.pillars > 0 && tracker_->min_columns() >= a_.pillars)
      stop = fmt::format("every cell passed {} pillars", a_.pillars);
    if (stop.empty() && a_.stop_when_mode_certain && tracker_->all_modes_certain())
      stop = "every cell's mode is certain";
  }
  const std::int64_t correct_every = scene_.coupling.volume_correction_every;
  if (correct_every > 0 && e % correct_every == 0) restore_volumes();  // after the sample
  if (a_.checkpoint_every > 0 && e % a_.checkpoint_every == 0) checkpoint(e);
  if (e % scene_.run.log_every == 0) progress(e);
}

// Each cell's rest volume back ([coupling] volume_correction_every; numerics): the fluid gets the
// moved nodes with the next exchange, as it gets every position from here.
void CoupledRun::restore_volumes() {
  restored_.resize(static_cast<std::size_t>(cells_.cell_count()), 0.0);
  const Eigen::Index n = cells_.nodes_per_cell();
  for (int k = 0; k < cells_.cell_count(); ++k) {
    const auto i = static_cast<std::size_t>(k);  // v0_: the rest volumes the guard measures from
    restored_[i] += restore_volume(cells_.positions().middleCols(Eigen::Index{k} * n, n),
                                   cells_.reference().faces, v0_[i]);
  }
}

int CoupledRun::run() {
  auto finish = [&] {
    if (part_) part_->file().flush();
  };
  start_ = Clock::now();
  std::int64_t s = offset_;
  at_ = offset_;
  try {
    side_.initialize(cells_.flat_positions());
    apply_halo();
    signal(SIGINT, on_sigint);
    spdlog::info("{} cells ({} nodes) of {}, connected", cells_.cell_count(), cells_.node_count(),
                 share_.total);
    open_output();
    if (rows_.empty()) sample(0);
    // The start, and on resume the checkpoint's step when its sample was lost with the previous
    // part file.
    const std::int64_t mesh_every = scene_.output.mesh_every;
    if (mesh_ && offset_ % mesh_every == 0 &&
        (mesh_->samples().empty() || mesh_->samples().back().step < offset_))
      sample_mesh(offset_);
    const std::string reason = step_loop(s);
    side_.finalize();
    finish();
    checkpoint(s);
    spdlog::info("ran {} steps: {}", s, reason);
    if (s > offset_)
      spdlog::info("time per step [ms]: membrane {:.3f}, exchange and fluid {:.3f}",
                   1e3 * t_membrane_ / static_cast<double>(s - offset_),
                   1e3 * t_exchange_ / static_cast<double>(s - offset_));
    if (halo_ > 0 && halo_steps_ > 0) {
      const double cells = static_cast<double>(halo_cells_) / static_cast<double>(halo_steps_);
      spdlog::info(
          "contact halo (width {:.3g} dx): {:.2f} cells of other processes per step ({:.0f} kB), "
          "at most {} contact pairs with their nodes in one step",
          halo_, cells, cells * 24e-3 * cells_.nodes_per_cell(), halo_pairs_);
    }
    summary();
    return 0;
  } catch (const coupler::CouplerError& e) {
    finish();
    spdlog::error("{}{}", e.what(), state_at_stop(at_));
    return 3;
  } catch (const std::exception& e) {
    side_.abort(e.what());
    finish();
    spdlog::error("{}{}", e.what(), state_at_stop(at_));
    return 1;
  }
}

}  // namespace

int run_coupled(const Scene& scene, const MembraneScene& m, const CoupledArgs& a) {
  return CoupledRun(scene, m, a).run();
}

}  // namespace dld::membrane
