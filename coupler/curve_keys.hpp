// SPDX-License-Identifier: MIT
// CURVE key files (docs/protocol.md, "Security"): ZeroMQ's Z85 text, 40 characters per key, in
// the curve section's format of a ZeroMQ certificate:
//   public-key = "rq:rM>}U?@Lns47E1%kR.o@n%FcmmsL/@{H8]yf7"
//   secret-key = "JTKVSB%%)wK0E.X)V>+}o?pNmC{O&4W4b!Ni{Lh6"
// STEM.key holds both keys (mode 0600), STEM.pub the public key only.
#pragma once
#include <string>
#include <vector>

namespace dld::coupler {

struct KeyPair {
  std::string public_key;
  std::string secret_key;  ///< empty when read from a .pub file
};

/// A fresh pair from libzmq (zmq_curve_keypair); throws std::runtime_error if libzmq has no CURVE.
KeyPair new_key_pair();

/// Writes STEM.key (both keys, readable by the owner only) and STEM.pub (the public key).
void write_key_files(const std::string& stem, const KeyPair& keys);

/// Reads a key file; with need_secret, a missing secret-key is an error. Throws dld::InputError
/// naming the file and line: unreadable, unknown key, not 40 Z85 characters, missing key.
KeyPair read_key_file(const std::string& path, bool need_secret);

/// The public keys of a list of key files (.pub or .key): the clients a server admits.
std::vector<std::string> read_public_keys(const std::vector<std::string>& paths);

/// Z85 text of a 32-byte binary key (as ZAP requests carry them).
std::string z85_key(const unsigned char* key32);

}  // namespace dld::coupler
