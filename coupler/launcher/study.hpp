// SPDX-License-Identifier: MIT
// A study file: one template scene and the axes along which it varies (SPEC section 6: 5 Ht x 3 d
// x 3 Ca = 45 runs), read into the list of runs, each with its own scene. The sweep knows no
// physics: an axis names scene keys and the values they take, a resolution names key overrides.
#pragma once
#include <toml++/toml.h>

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace dld::coupler {

/// One axis of the study: a name for tables and plots (Ht, d, Ca), its values, and the scene keys
/// (dotted paths) set at each value.
struct StudyAxis {
  std::string name;
  std::string column;  ///< its column in the sweep's summary.csv (default: name)
  std::vector<double> values;
  std::vector<std::pair<std::string, toml::array>> set;  ///< key -> one value per axis value
};

/// One run of the study: its name, its coordinates and its scene.
struct StudyRun {
  int index = 0;
  std::string name;                 ///< e.g. "Ht45.6-d6-Ca1"
  std::vector<double> coordinates;  ///< one value per axis
  std::filesystem::path dir;        ///< <output>/<resolution>/<name>
  toml::table scene;                ///< template + axis values + resolution + name/output
};

struct Study {
  std::string file, name;
  std::filesystem::path scene_template, output, modes;
  int pillars = 100;
  std::int64_t checkpoint_every = 0, max_steps = 0;
  std::vector<StudyAxis> axes;
  std::map<std::string, toml::table> resolutions;  ///< name -> overrides (dotted key -> value)
  std::string default_resolution;

  /// Every run of the Cartesian product of the axes (first axis slowest), at `resolution`.
  std::vector<StudyRun> runs(const std::string& resolution) const;
};

/// Reads a study file; errors name the file, line and key (InputError).
Study load_study(const std::string& path);

/// The runs a sweep does: all of `runs` in study order, or those that `names` lists (dld-sweep
/// --only), in the order it lists them (so a sweep can start its longest runs first); `index` >= 0
/// keeps only the run with that index (--index, SLURM arrays). A name the study has not, a name
/// given twice, an index out of range or one that `names` leaves out is an InputError naming it.
std::vector<const StudyRun*> select_runs(const std::vector<StudyRun>& runs, int index,
                                         const std::vector<std::string>& names);

/// The scene text of a run (TOML), as written into its directory.
std::string scene_text(const StudyRun& run);

}  // namespace dld::coupler
