// SPDX-License-Identifier: MIT
// dld-keys: makes CURVE key pairs for coupled runs over tcp (docs/protocol.md, "Security"):
// STEM.key (both keys, owner-only) and STEM.pub (the public key to hand to the other side).
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <filesystem>

#include "coupler/curve_keys.hpp"
#include "shared/guarded_main.hpp"
#include "shared/input_error.hpp"

static int run_main(int argc, char** argv) {
  CLI::App app{"dld-keys: CURVE key pairs for dld-fluid --serve / dld-membrane --connect over tcp"};
  std::vector<std::string> stems;
  bool force = false;
  app.add_option("stems", stems, "one key pair per STEM: STEM.key and STEM.pub")->required();
  app.add_flag("--force", force, "overwrite existing key files");
  CLI11_PARSE(app, argc, argv);
  for (const std::string& stem : stems) {
    for (const char* ext : {".key", ".pub"}) {
      if (!force && std::filesystem::exists(stem + ext))
        throw dld::InputError(fmt::format("{}{}: exists (--force overwrites it)", stem, ext));
    }
    dld::coupler::write_key_files(stem, dld::coupler::new_key_pair());
    fmt::print("{0}.key (secret, keep it on the host of its program), {0}.pub\n", stem);
  }
  return 0;
}

int main(int argc, char** argv) {
  return dld::guarded_main("dld-keys", run_main, argc, argv);
}
