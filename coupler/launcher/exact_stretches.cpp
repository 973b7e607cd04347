// SPDX-License-Identifier: MIT
#include "coupler/launcher/exact_stretches.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "shared/input_error.hpp"

namespace dld::coupler {

std::vector<ExactStretch> read_exact_stretches(const std::string& path) {
  std::vector<ExactStretch> out;
  std::ifstream in(path);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.empty() || line.rfind("first_step", 0) == 0) continue;
    std::istringstream row(line);
    ExactStretch s;
    char comma = 0;
    row >> s.first >> comma >> s.last;
    if (!row || comma != ',' || s.last < s.first)
      throw InputError(
          fmt::format("{}:{}: expected first_step,last_step[,planned_last_step] "
                      "with first <= last, got '{}'",
                      path, n, line));
    if (!(row >> comma >> s.planned) || comma != ',') s.planned = s.last;
    out.push_back(s);
  }
  return out;
}

void append_exact_stretch(const std::string& path, const ExactStretch& s) {
  const bool fresh = !std::filesystem::exists(path);
  std::ofstream out(path, std::ios::app);
  if (fresh) out << "first_step,last_step,planned_last_step\n";
  out << s.first << ',' << s.last << ',' << s.planned << '\n';
  if (!out) throw std::runtime_error(path + ": cannot append the exact stretch");
}

std::int64_t pending_exact_end(const std::vector<ExactStretch>& stretches, std::int64_t from) {
  if (stretches.empty()) return 0;
  const ExactStretch& s = stretches.back();
  return s.last == from && s.planned > s.last ? s.planned : 0;
}

}  // namespace dld::coupler
