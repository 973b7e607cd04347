// SPDX-License-Identifier: MIT
#include "membrane/mesh.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {

using Vec3 = Eigen::Vector3d;

[[noreturn]] void refuse(const std::string& source, const std::string& what) {
  throw InputError(fmt::format("{}: {}", source, what));
}

/// Directed edge (i -> j) packed into one key.
std::int64_t key(int i, int j) {
  return (static_cast<std::int64_t>(i) << 32) | static_cast<std::uint32_t>(j);
}

}  // namespace

void validate_closed_surface(const TriMesh& mesh, const std::string& source) {
  const int n = mesh.node_count();
  if (n < 4 || mesh.face_count() < 4)
    refuse(source, fmt::format("a closed surface needs at least 4 nodes and 4 faces, got {} and {}",
                               n, mesh.face_count()));
  if (!mesh.nodes.allFinite()) refuse(source, "node coordinates must be finite numbers");
  // Directed edges: each must appear once; its reverse must appear once (closed, oriented).
  std::map<std::int64_t, int> directed;
  std::vector<int> used(n, 0);
  double longest = 0.0;
  for (int f = 0; f < mesh.face_count(); ++f) {
    const Face& t = mesh.faces[f];
    for (int k = 0; k < 3; ++k) {
      if (t[k] < 0 || t[k] >= n)
        refuse(source, fmt::format("face {} refers to node {} (nodes are 0..{})", f, t[k], n - 1));
      used[t[k]]++;
    }
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      refuse(source, fmt::format("face {} repeats a node (degenerate triangle)", f));
    for (int k = 0; k < 3; ++k) {
      longest = std::max(longest, (mesh.nodes.col(t[k]) - mesh.nodes.col(t[(k + 1) % 3])).norm());
      if (!directed.emplace(key(t[k], t[(k + 1) % 3]), f).second)
        refuse(source, fmt::format("edge {}-{} is used twice in the same direction (face {}): "
                                   "non-manifold or inconsistently oriented faces",
                                   t[k], t[(k + 1) % 3], f));
    }
  }
  for (int f = 0; f < mesh.face_count(); ++f) {
    const Face& t = mesh.faces[f];
    const Vec3 n2 = (mesh.nodes.col(t[1]) - mesh.nodes.col(t[0]))
                        .cross(mesh.nodes.col(t[2]) - mesh.nodes.col(t[0]));
    if (n2.norm() <= 1e-10 * longest * longest)
      refuse(source, fmt::format("face {} has (nearly) zero area (degenerate triangle)", f));
  }
  for (const auto& [k, f] : directed) {
    int i = static_cast<int>(k >> 32), j = static_cast<int>(k & 0xffffffff);
    if (!directed.count(key(j, i)))
      refuse(source, fmt::format("edge {}-{} of face {} has no neighbour face: the surface is open "
                                 "(or its faces are not consistently oriented)",
                                 i, j, f));
  }
  for (int i = 0; i < n; ++i)
    if (used[i] == 0) refuse(source, fmt::format("node {} belongs to no face", i));
  // Vertex manifoldness: the faces around each node form one fan (one cycle of directed edges).
  std::vector<std::vector<std::array<int, 2>>> fan(n);
  for (const Face& t : mesh.faces)
    for (int k = 0; k < 3; ++k) fan[t[k]].push_back({t[(k + 1) % 3], t[(k + 2) % 3]});
  for (int i = 0; i < n; ++i) {
    std::map<int, int> next;
    for (auto [b, c] : fan[i]) next[b] = c;
    int start = fan[i][0][0], cur = start, steps = 0;
    do {
      cur = next.at(cur);
      ++steps;
    } while (cur != start && steps <= static_cast<int>(fan[i].size()));
    if (steps != static_cast<int>(fan[i].size()))
      refuse(source, fmt::format("node {} joins two or more separate fans of faces (non-manifold "
                                 "vertex)",
                                 i));
  }
  // Euler characteristic 2 for a sphere-like cell.
  const long euler =
      static_cast<long>(n) - static_cast<long>(directed.size() / 2) + mesh.face_count();
  if (euler != 2)
    refuse(source,
           fmt::format("Euler characteristic V - E + F = {} (expected 2: one closed surface "
                       "of sphere topology)",
                       euler));
  if (!(enclosed_volume(mesh) > 0.0))
    refuse(source,
           "the enclosed volume is not positive: faces are oriented inward (inverted mesh)");
}

std::vector<Hinge> hinges(const TriMesh& mesh) {
  std::map<std::int64_t, int> opposite;  // directed edge i->j -> third node of its face
  for (const Face& t : mesh.faces)
    for (int k = 0; k < 3; ++k) opposite[key(t[k], t[(k + 1) % 3])] = t[(k + 2) % 3];
  std::vector<Hinge> out;
  out.reserve(opposite.size() / 2);
  for (const auto& [k, c] : opposite) {
    int a = static_cast<int>(k >> 32), b = static_cast<int>(k & 0xffffffff);
    if (a < b) out.push_back({a, b, c, opposite.at(key(b, a))});
  }
  return out;
}

std::vector<std::array<int, 2>> edges(const TriMesh& mesh) {
  std::vector<std::array<int, 2>> out;
  for (const Hinge& h : hinges(mesh)) out.push_back({h.a, h.b});
  return out;
}

double surface_area(const TriMesh& mesh, const Points& x) {
  double a = 0.0;
  for (const Face& t : mesh.faces)
    a += 0.5 * (x.col(t[1]) - x.col(t[0])).cross(x.col(t[2]) - x.col(t[0])).norm();
  return a;
}

double enclosed_volume(const TriMesh& mesh, const Points& x) {
  double v = 0.0;
  for (const Face& t : mesh.faces) v += x.col(t[0]).dot(x.col(t[1]).cross(x.col(t[2])));
  return v / 6.0;
}

Eigen::Vector3d centroid(const Points& x) {
  return x.rowwise().mean();
}

TriMesh read_off(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open mesh file", path));
  std::string magic;
  in >> magic;
  if (magic != "OFF") refuse(path, "not an OFF file (first word must be 'OFF')");
  long nv = -1, nf = -1, ne = -1;
  in >> nv >> nf >> ne;
  if (!in || nv < 0 || nf < 0 || nv > 10'000'000 || nf > 20'000'000)
    refuse(path, "bad OFF header (expected node, face and edge counts)");
  TriMesh m;
  m.nodes.resize(3, nv);
  for (long i = 0; i < nv; ++i) in >> m.nodes(0, i) >> m.nodes(1, i) >> m.nodes(2, i);
  if (!in) refuse(path, fmt::format("file ends before the {} node coordinates", nv));
  m.faces.resize(nf);
  for (long f = 0; f < nf; ++f) {
    int k = 0;
    in >> k;
    if (in && k != 3)
      refuse(path, fmt::format("face {} has {} corners (only triangles allowed)", f, k));
    in >> m.faces[f][0] >> m.faces[f][1] >> m.faces[f][2];
  }
  if (!in) refuse(path, fmt::format("file ends before the {} faces", nf));
  return m;
}

void write_off(const TriMesh& mesh, const std::string& path) {
  namespace fs = std::filesystem;
  fs::path p(path);
  if (p.has_parent_path()) fs::create_directories(p.parent_path());
  fs::path tmp = p;
  tmp += fmt::format(".tmp{}", static_cast<long>(::getpid()));
  {
    std::ofstream out(tmp);
    if (!out) throw InputError(fmt::format("{}: cannot write mesh file", tmp.string()));
    out << "OFF\n" << mesh.node_count() << ' ' << mesh.face_count() << " 0\n";
    for (int i = 0; i < mesh.node_count(); ++i)
      out << fmt::format("{:.17g} {:.17g} {:.17g}\n", mesh.nodes(0, i), mesh.nodes(1, i),
                         mesh.nodes(2, i));
    for (const Face& t : mesh.faces) out << fmt::format("3 {} {} {}\n", t[0], t[1], t[2]);
    if (!out) throw InputError(fmt::format("{}: write failed", tmp.string()));
  }
  fs::rename(tmp, p);
}

std::vector<std::uint32_t> face_indices(const TriMesh& mesh, int copies) {
  std::vector<std::uint32_t> out;
  out.reserve(3 * mesh.faces.size() * static_cast<std::size_t>(std::max(copies, 0)));
  for (int k = 0; k < copies; ++k) {
    for (const Face& f : mesh.faces) {
      for (int v : f) {
        out.push_back(static_cast<std::uint32_t>(v));
      }
    }
  }
  return out;
}

}  // namespace dld::membrane
