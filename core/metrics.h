// Quality metrics of one edit: how well the handle is reached, how still the
// fixed and watched vertices stay, and how much the surface is distorted.
// Lengths are divided by the rest mesh's bounding-box diagonal ("_rel").
//
// Every function takes the rest mesh and the deformed positions (3 by #V,
// same vertex order) and is a small free function in the libigl style.

#ifndef MSDEFORM_CORE_METRICS_H_
#define MSDEFORM_CORE_METRICS_H_

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"

namespace msdeform {

// Root mean square of |deformed_v - deformed_from_rest * rest_v| over
// `vertices` (the moveable handle). 0 for an empty list.
double HandleRmsError(const Mesh& rest, const Eigen::Matrix3Xd& deformed,
                      const std::vector<int>& vertices, const Eigen::Affine3d& deformed_from_rest);
// The same over every moveable vertex of `layout`, each against its handle
// group's transform.
double HandleRmsError(const Mesh& rest, const Eigen::Matrix3Xd& deformed,
                      const HandleLayout& layout, const HandleTransforms& deformed_from_rest);

// Mean and max displacement |deformed_v - rest_v| over `vertices` (fixed
// vertices, or a watch region for leakage). Zeros for an empty list.
struct Displacement {
  double mean = 0.0;
  double max = 0.0;
};
Displacement VertexDisplacement(const Mesh& rest, const Eigen::Matrix3Xd& deformed,
                                const std::vector<int>& vertices);

// Cotangent-weighted as-rigid-as-possible energy (Sorkine & Alexa 2007) per
// vertex i:
//   E_i = sum_{j in N(i)} w_ij |(p'_i - p'_j) - R_i (p_i - p_j)|^2,
// with R_i the best rotation (polar part of sum_j w_ij (p'_i - p'_j)(p_i - p_j)^T,
// no reflection) and w_ij = (cot a_ij + cot b_ij) / 2 clamped at 0 (so every
// term is >= 0), and the normaliser N_i = sum_j w_ij |p_i - p_j|^2.
// A rigid motion gives E = 0; a uniform scale by s gives E / N = (s - 1)^2.
struct ArapTerms {
  Eigen::VectorXd energy;      // E_i, #V
  Eigen::VectorXd normaliser;  // N_i, #V
};
ArapTerms ArapEnergyPerVertex(const Mesh& rest, const Eigen::Matrix3Xd& deformed);

// sum_i E_i / sum_i N_i over `vertices` (all vertices when empty): a
// dimensionless distortion, the relative squared edge error after the best
// local rotations.
double NormalisedArapEnergy(const ArapTerms& terms, const std::vector<int>& vertices = {});

// Mean over the undirected edges of | |e'| / |e| - 1 | (edges of zero rest
// length are skipped).
double MeanEdgeStrain(const Mesh& rest, const Eigen::Matrix3Xd& deformed);

// Mean over `nodes` of ||R_j^T R_j - I||_F (0 for an empty list).
double OrthogonalityError(const NodeTransforms& transforms, const std::vector<int>& nodes);

// Vertices not in `sources` whose distance along mesh edges (Dijkstra) from
// the nearest vertex of `sources` is at most `radius`: the band around the
// fixed region where a limb bends at its joint.
std::vector<int> VerticesNear(const Mesh& mesh, const std::vector<int>& sources, double radius);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_METRICS_H_
