// SPDX-License-Identifier: MIT
#include "shared/log.hpp"

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <memory>
#include <string_view>

namespace dld {
namespace {
/// "error: " / "warning: " before the message of those levels, nothing for the others.
class LevelMarker : public spdlog::custom_flag_formatter {
 public:
  void format(const spdlog::details::log_msg& msg, const std::tm&,
              spdlog::memory_buf_t& dest) override {
    const std::string_view m = msg.level >= spdlog::level::err    ? "error: "
                               : msg.level == spdlog::level::warn ? "warning: "
                                                                  : "";
    dest.append(m.data(), m.data() + m.size());
  }
  std::unique_ptr<custom_flag_formatter> clone() const override {
    return std::make_unique<LevelMarker>();
  }
};
}  // namespace

void setup_logging(const std::string& program, bool verbose) {
  auto logger = spdlog::stderr_color_mt(program);
  // Warnings and errors say so after the program's name, so that dld-run relays the error line
  // of a failed program (coupler/launcher/process.hpp: error_line), not its last line.
  auto formatter = std::make_unique<spdlog::pattern_formatter>();
  formatter->add_flag<LevelMarker>('*').set_pattern("[%n] %*%v");
  logger->set_formatter(std::move(formatter));
  logger->set_level(verbose ? spdlog::level::debug : spdlog::level::info);
  spdlog::set_default_logger(logger);
}
}  // namespace dld
