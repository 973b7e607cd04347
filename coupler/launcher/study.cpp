// SPDX-License-Identifier: MIT
#include "coupler/launcher/study.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <set>
#include <sstream>

#include "shared/input_error.hpp"
#include "shared/toml_section.hpp"

namespace dld::coupler {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> split_key(const std::string& key) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(key);
  while (std::getline(in, part, '.')) {
    parts.push_back(part);
  }
  return parts;
}

/// Sets the dotted `key` of `scene` to `value`, creating tables on the way.
void set_key(toml::table& scene, const std::string& key, const toml::node& value,
             const std::string& origin) {
  const auto parts = split_key(key);
  if (parts.empty() || std::any_of(parts.begin(), parts.end(), [](auto& p) { return p.empty(); })) {
    throw InputError(fmt::format("{}: '{}' is not a scene key (a.b.c)", origin, key));
  }
  toml::table* t = &scene;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    if (t->get(parts[i]) == nullptr) {
      t->insert(parts[i], toml::table{});
    }
    t = t->get(parts[i])->as_table();
    if (t == nullptr) {
      throw InputError(fmt::format("{}: scene key '{}': '{}' is not a table in the template",
                                   origin, key, parts[i]));
    }
  }
  value.visit([&](auto&& v) { t->insert_or_assign(parts.back(), v); });
}

std::string run_name(const std::vector<StudyAxis>& axes, const std::vector<double>& at) {
  std::string name;
  for (std::size_t a = 0; a < axes.size(); ++a) {
    name += fmt::format("{}{}{:g}", a ? "-" : "", axes[a].name, at[a]);
  }
  return name;
}

StudyAxis read_axis(const TomlSection& s) {
  StudyAxis axis;
  axis.name = s.string("name");
  if (axis.name.empty() || axis.name.find_first_of("/ -") != std::string::npos) {
    s.fail("name", "expected a short name without spaces, '-' or '/' (it names run directories)");
  }
  axis.column = s.string("column", "");
  axis.values = s.numbers("values");
  if (axis.values.empty()) {
    s.fail("values", "expected at least one value");
  }
  if (std::set<double>(axis.values.begin(), axis.values.end()).size() != axis.values.size()) {
    s.fail("values", "expected distinct values");
  }
  for (auto&& [k, v] : s.raw_table("set")) {
    const std::string key(k.str());
    const auto* arr = v.as_array();
    if (arr == nullptr || arr->size() != axis.values.size()) {
      s.fail("set", fmt::format("key \"{}\": expected an array of {} values (one per axis value)",
                                key, axis.values.size()));
    }
    axis.set.emplace_back(key, *arr);
  }
  if (axis.set.empty()) {
    s.fail("set", "expected at least one scene key to set");
  }
  return axis;
}

/// The [NAME] tables of `table_of.resolution` into `out`; a name defined twice is an error.
void read_resolutions(const TomlSection& table_of, std::map<std::string, toml::table>& out) {
  for (auto&& [k, v] : table_of.raw_table("resolution")) {
    if (!v.is_table()) {
      table_of.fail("resolution", fmt::format("'{}': expected a table of scene keys", k.str()));
    }
    if (!out.emplace(std::string(k.str()), *v.as_table()).second) {
      table_of.fail("resolution", fmt::format("'{}': defined twice", k.str()));
    }
  }
}

}  // namespace

Study load_study(const std::string& path) {
  auto doc = TomlDocument::load(path);
  const TomlSection root = TomlSection::root(doc);
  const TomlSection st = root.section("study");
  const fs::path here = fs::path(path).parent_path();
  Study s;
  s.file = path;
  s.name = st.string("name");
  s.scene_template = here / st.string("scene");
  s.output = st.string("output");
  if (st.has("modes")) {
    s.modes = here / st.string("modes");
  }
  s.pillars = static_cast<int>(st.integer("pillars", 100));
  if (s.pillars < 1) {
    st.fail("pillars", "expected a positive number of pillars");
  }
  s.checkpoint_every = st.integer("checkpoint_every", 20000);
  s.max_steps = st.integer("max_steps", 0);
  if (s.checkpoint_every < 0) {
    st.fail("checkpoint_every", "expected >= 0 steps (0: only at the end)");
  }
  if (s.max_steps < 0) {
    st.fail("max_steps", "expected >= 0 steps (0: no limit)");
  }
  std::set<std::string> names;
  for (const TomlSection& a : st.sections("axis")) {
    s.axes.push_back(read_axis(a));
    if (!names.insert(s.axes.back().name).second) {
      a.fail("name", "expected a name used once");
    }
  }
  if (s.axes.empty()) {
    st.fail("axis", "expected at least one [[study.axis]]");
  }
  if (st.has("resolution")) read_resolutions(st, s.resolutions);
  if (st.has("resolutions")) {  // a file of [resolution.NAME] tables shared by study files
    const fs::path shared = here / st.string("resolutions");
    if (!fs::exists(shared)) {
      st.fail("resolutions", fmt::format("{}: no such file", shared.string()));
    }
    auto settings = TomlDocument::load(shared.string());
    const TomlSection root_of_settings = TomlSection::root(settings);
    read_resolutions(root_of_settings, s.resolutions);
    settings->reject_unknown();
  }
  s.default_resolution = st.string("default_resolution", "");
  if (!s.default_resolution.empty() && s.resolutions.count(s.default_resolution) == 0) {
    st.fail("default_resolution", "expected the name of a [study.resolution.*] table");
  }
  doc->reject_unknown();
  if (!fs::exists(s.scene_template)) {
    st.fail("scene", fmt::format("{}: no such scene file", s.scene_template.string()));
  }
  return s;
}

std::vector<StudyRun> Study::runs(const std::string& resolution) const {
  const auto tmpl = TomlDocument::load(scene_template.string());
  const toml::table* overrides = nullptr;
  if (!resolution.empty()) {
    const auto r = resolutions.find(resolution);
    if (r == resolutions.end()) {
      std::string known;
      for (const auto& [n, t] : resolutions) {
        known += " " + n;
      }
      throw InputError(fmt::format("{}: no resolution '{}' (known:{})", file, resolution,
                                   known.empty() ? " none" : known));
    }
    overrides = &r->second;
  }
  std::size_t total = 1;
  for (const auto& a : axes) {
    total *= a.values.size();
  }
  std::vector<StudyRun> out;
  for (std::size_t i = 0; i < total; ++i) {
    StudyRun run;
    run.index = static_cast<int>(i);
    run.scene = tmpl->root();
    if (overrides) {
      for (auto&& [k, v] : *overrides) {
        set_key(run.scene, std::string(k.str()), v, file + ": resolution " + resolution);
      }
    }
    // First axis slowest: index = ((i0 * n1) + i1) * n2 + i2 ...
    std::size_t rest = i, stride = total;
    for (const auto& a : axes) {
      stride /= a.values.size();
      const std::size_t j = rest / stride;
      rest %= stride;
      run.coordinates.push_back(a.values[j]);
      for (const auto& [key, values] : a.set) {
        set_key(run.scene, key, *values.get(j), file + ": axis " + a.name);
      }
    }
    run.name = run_name(axes, run.coordinates);
    run.dir = output / (resolution.empty() ? std::string("default") : resolution) / run.name;
    set_key(run.scene, "scene.name", toml::value<std::string>(run.name), file);
    set_key(run.scene, "output.file", toml::value<std::string>((run.dir / "run.h5").string()),
            file);
    out.push_back(std::move(run));
  }
  return out;
}

std::vector<const StudyRun*> select_runs(const std::vector<StudyRun>& runs, int index,
                                         const std::vector<std::string>& names) {
  if (index >= static_cast<int>(runs.size())) {
    throw InputError(fmt::format("--index {}: the study has {} runs (0..{})", index, runs.size(),
                                 runs.size() - 1));
  }
  std::vector<const StudyRun*> listed;
  for (const auto& n : names) {
    const auto r = std::find_if(runs.begin(), runs.end(), [&](auto& run) { return run.name == n; });
    if (r == runs.end()) throw InputError(fmt::format("--only {}: no such run (see --list)", n));
    if (std::count(names.begin(), names.end(), n) > 1)
      throw InputError(fmt::format("--only {}: named twice (each run is run once)", n));
    listed.push_back(&*r);
  }
  if (names.empty())
    for (const auto& r : runs) listed.push_back(&r);
  std::vector<const StudyRun*> chosen;
  for (const StudyRun* r : listed)
    if (index < 0 || r->index == index) chosen.push_back(r);
  if (index >= 0 && chosen.empty())
    throw InputError(fmt::format("--index {} (run {}): not among --only's runs", index,
                                 runs[static_cast<std::size_t>(index)].name));
  return chosen;
}

namespace {

/// The same TOML text with every float outside quotes in its shortest form that reads back as the
/// same double (toml++ writes either 17 digits or 6): a run's scene is exactly its study's.
std::string shortest_floats(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  char quote = 0;
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (quote) {
      if (c == '\\' && i + 1 < text.size()) {
        out += text.substr(i, 2), i += 2;
        continue;
      }
      if (c == quote) quote = 0;
      out += c, ++i;
      continue;
    }
    if (c == '"' || c == '\'') quote = c;
    if (c == '#') quote = '\n';  // a comment runs to the end of the line
    const bool starts_number =
        std::isdigit(static_cast<unsigned char>(c)) &&
        (i == 0 || !std::isalnum(static_cast<unsigned char>(text[i - 1])) || text[i - 1] == '-');
    if (!starts_number) {
      out += c, ++i;
      continue;
    }
    std::size_t end = i;
    while (end < text.size() &&
           (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '.' ||
            text[end] == '+' || text[end] == '-' || text[end] == '_'))
      ++end;
    const std::string token = text.substr(i, end - i);
    const bool is_float = token.find_first_of(".eE") != std::string::npos &&
                          token.find_first_of("xob_:") == std::string::npos;
    std::string shortest = token;
    if (is_float) {
      shortest = fmt::format("{}", std::stod(token));
      if (shortest.find_first_of(".e") == std::string::npos) shortest += ".0";
    }
    out += shortest;
    i = end;
  }
  return out;
}

}  // namespace

std::string scene_text(const StudyRun& run) {
  std::ostringstream s;
  s << "# Written by dld-sweep for run " << run.name
    << " of its study; resuming checks that it is unchanged.\n"
    << toml::toml_formatter(run.scene) << "\n";
  return shortest_floats(s.str());
}

}  // namespace dld::coupler
