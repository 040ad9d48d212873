// Loop subdivision of a triangle mesh through OpenMesh's uniform Loop
// subdivider. msdeform uses it to make large variants of the real meshes for
// scaling work (the armadillo at about 104K and 416K vertices).
//
// Each step adds one vertex per edge and splits each triangle into four:
// #V' = #V + #E and #F' = 4 #F. Vertex ids are stable: the input vertices keep
// their ids (moved to their Loop positions) and the new edge vertices follow,
// so a vertex selection made on the input still indexes the same points.

#ifndef MSDEFORM_CORE_SUBDIVIDE_H_
#define MSDEFORM_CORE_SUBDIVIDE_H_

#include <string>

#include "msdeform/core/mesh.h"

namespace msdeform {

// Applies `iterations` (>= 0) Loop steps to `mesh` and stores the result in
// *subdivided. Returns false, with the face that could not be added named in
// *error, when `mesh` is not an oriented edge-manifold (OpenMesh cannot hold
// it). Isolated vertices are kept where they are.
bool LoopSubdivide(const Mesh& mesh, int iterations, Mesh* subdivided,
                   std::string* error);

// The same for a mesh known to be manifold; CHECK-fails otherwise.
Mesh LoopSubdivide(const Mesh& mesh, int iterations);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_SUBDIVIDE_H_
