// SPDX-License-Identifier: MIT
// A closed triangulated surface: node positions plus faces, with the checks a membrane mesh must
// pass (closed, manifold, consistently oriented outward, no degenerate triangles).
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace dld::membrane {

/// Node positions, one column per node (lattice units unless a caller says otherwise).
using Points = Eigen::Matrix3Xd;
using Face = std::array<int, 3>;

/// An edge shared by two faces: nodes a, b and the opposite nodes c (face a-b-c) and d
/// (face b-a-d), both faces counter-clockwise seen from outside.
struct Hinge {
  int a, b, c, d;
};

struct TriMesh {
  Points nodes;
  std::vector<Face> faces;

  int node_count() const { return static_cast<int>(nodes.cols()); }
  int face_count() const { return static_cast<int>(faces.size()); }
};

/// Checks that `mesh` is a closed, edge-manifold, vertex-manifold, consistently oriented surface
/// without degenerate or unused nodes, enclosing a positive volume (outward normals).
/// Throws InputError "<source>: <what is wrong>" otherwise.
void validate_closed_surface(const TriMesh& mesh, const std::string& source);

/// Hinges of a closed, oriented mesh (one per edge). Precondition: validate_closed_surface passed.
std::vector<Hinge> hinges(const TriMesh& mesh);
/// Unique undirected edges (i < j).
std::vector<std::array<int, 2>> edges(const TriMesh& mesh);

double surface_area(const TriMesh& mesh, const Points& x);
/// Enclosed volume by the divergence theorem (positive for outward faces).
/// The triangles as 3 node indices each, repeated for `copies` cells of this mesh (indices stay
/// local to each cell): the layout the coupler's handshake carries (docs/protocol.md).
std::vector<std::uint32_t> face_indices(const TriMesh& mesh, int copies = 1);

double enclosed_volume(const TriMesh& mesh, const Points& x);
inline double surface_area(const TriMesh& mesh) {
  return surface_area(mesh, mesh.nodes);
}
inline double enclosed_volume(const TriMesh& mesh) {
  return enclosed_volume(mesh, mesh.nodes);
}
Eigen::Vector3d centroid(const Points& x);

/// OFF reading/writing. Reading throws InputError naming the file on malformed content; it does
/// not validate the surface (call validate_closed_surface).
TriMesh read_off(const std::string& path);
/// Writes atomically (temporary file, then rename) with full double precision.
void write_off(const TriMesh& mesh, const std::string& path);

}  // namespace dld::membrane
