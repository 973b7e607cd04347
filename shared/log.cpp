// SPDX-License-Identifier: MIT
#include "shared/log.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

namespace dld {
void setup_logging(const std::string& program, bool verbose) {
  auto logger = spdlog::stderr_color_mt(program);
  logger->set_pattern("[%n] %v");
  logger->set_level(verbose ? spdlog::level::debug : spdlog::level::info);
  spdlog::set_default_logger(logger);
}
}  // namespace dld
