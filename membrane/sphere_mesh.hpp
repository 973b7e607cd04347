// SPDX-License-Identifier: MIT
// The initially spherical capsule: an icosahedron subdivided n times (each triangle into four,
// new nodes projected onto the sphere), 20 * 4^n faces. No CGAL: the mesh is a closed form of n,
// built in well under a millisecond, so it needs no cache (unlike the Evans-Fung meshes).
#pragma once
#include "membrane/mesh.hpp"

namespace dld::membrane {

/// Outward-oriented icosphere of radius `radius` [lattice lengths] centred at the origin:
/// 20 * 4^subdivisions faces, 10 * 4^subdivisions + 2 nodes. Throws InputError for subdivisions
/// outside [0, 7] or a non-positive radius.
TriMesh icosphere(int subdivisions, double radius);

/// The subdivision level whose face count 20 * 4^n is closest to `target_faces` (at least 20).
int icosphere_subdivisions(int target_faces);

}  // namespace dld::membrane
