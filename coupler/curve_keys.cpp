// SPDX-License-Identifier: MIT
#include "coupler/curve_keys.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zmq.h>

#include <array>
#include <fstream>
#include <stdexcept>

#include "shared/input_error.hpp"

namespace dld::coupler {

namespace {

constexpr std::size_t kZ85KeyChars = 40;

bool is_z85_key(const std::string& text) {
  std::array<std::uint8_t, 32> binary{};
  return text.size() == kZ85KeyChars && zmq_z85_decode(binary.data(), text.c_str()) != nullptr;
}

std::string trimmed(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

// Created with its final mode (a secret key is never readable by others, not even for a moment);
// fchmod for a file that existed with other permissions.
void write_file(const std::string& path, const std::string& text, mode_t mode) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, mode);
  bool ok = fd >= 0 && ::fchmod(fd, mode) == 0;
  for (std::size_t done = 0; ok && done < text.size();) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    ok = n > 0;
    done += ok ? static_cast<std::size_t>(n) : 0;
  }
  if (fd >= 0 && ::close(fd) != 0) ok = false;
  if (!ok) throw InputError(fmt::format("{}: cannot write the key file", path));
}

}  // namespace

KeyPair new_key_pair() {
  std::array<char, kZ85KeyChars + 1> pub{}, sec{};
  if (zmq_curve_keypair(pub.data(), sec.data()) != 0) {
    throw std::runtime_error("zmq_curve_keypair failed: libzmq built without CURVE");
  }
  return {pub.data(), sec.data()};
}

void write_key_files(const std::string& stem, const KeyPair& keys) {
  const std::string head = "# CURVE key (ZeroMQ Z85), made by dld-keys or dld-run\n";
  const std::string pub = fmt::format("public-key = \"{}\"\n", keys.public_key);
  write_file(stem + ".key", head + pub + fmt::format("secret-key = \"{}\"\n", keys.secret_key),
             S_IRUSR | S_IWUSR);
  write_file(stem + ".pub", head + pub, S_IRUSR | S_IWUSR | S_IRGRP | S_IROTH);
}

KeyPair read_key_file(const std::string& path, bool need_secret) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot read the CURVE key file", path));
  KeyPair keys;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    line = trimmed(line);
    if (line.empty() || line[0] == '#' || line == "curve" || line == "metadata") continue;
    const auto eq = line.find('=');
    const std::string name = trimmed(line.substr(0, eq));
    std::string value = eq == std::string::npos ? "" : trimmed(line.substr(eq + 1));
    if (value.size() >= 2 && value.front() == '"' && value.back() == '"')
      value = value.substr(1, value.size() - 2);
    if (name != "public-key" && name != "secret-key") {
      throw InputError(
          fmt::format("{}: line {}: expected public-key = \"...\" or secret-key = "
                      "\"...\", got '{}'",
                      path, number, line));
    }
    if (!is_z85_key(value)) {
      throw InputError(fmt::format(
          "{}: line {}: {}: expected 40 Z85 characters (a ZeroMQ CURVE key)", path, number, name));
    }
    (name == "public-key" ? keys.public_key : keys.secret_key) = value;
  }
  if (keys.public_key.empty()) throw InputError(fmt::format("{}: no public-key", path));
  if (need_secret && keys.secret_key.empty()) {
    throw InputError(
        fmt::format("{}: no secret-key (this side needs its own key pair, the "
                    ".key file, not the .pub)",
                    path));
  }
  return keys;
}

std::vector<std::string> read_public_keys(const std::vector<std::string>& paths) {
  std::vector<std::string> keys;
  keys.reserve(paths.size());
  for (const std::string& p : paths) keys.push_back(read_key_file(p, false).public_key);
  return keys;
}

std::string z85_key(const unsigned char* key32) {
  std::array<char, kZ85KeyChars + 1> text{};
  zmq_z85_encode(text.data(), key32, 32);
  return text.data();
}

}  // namespace dld::coupler
