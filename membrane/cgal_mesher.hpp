// SPDX-License-Identifier: MIT
// Meshing of the Evans-Fung surface with CGAL. The only place that includes CGAL (it takes about
// a minute to compile); everything else sees a TriMesh.
#pragma once
#include "membrane/evans_fung.hpp"
#include "membrane/mesh.hpp"

namespace dld::membrane {

/// A closed, outward, quality triangulation of `shape` with about `target_faces` faces
/// (CGAL surface mesher on the implicit function, then isotropic remeshing to the edge length that
/// gives the face count, then nodes projected onto the exact surface). Throws InputError for
/// target_faces outside [100, 50000].
TriMesh mesh_evans_fung_cgal(const EvansFungShape& shape, int target_faces);

}  // namespace dld::membrane
