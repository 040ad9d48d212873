// The mesh's own ARAP energy over the selected graph's subspace (`--energy=arap`;
// docs/method.md §9): the deformed vertices are the graph's skinning (Eq. 9),
// linear in the free nodes' (R_j, t_j), and the energy is the cotangent ARAP
// energy of the whole mesh (core/cotangent_weights.h) with one best rotation
// per cluster of vertices instead of Eq. 17. FAST (Jacobson et al. 2012)
// minimises it over a skinning subspace; here the subspace is the one the
// multi-scale method picks from the handle layout, with its node classes
// (Totally Free: R and t; Half Free: R; Fixed: none).
//
// The energy, with x'_i the deformed vertices and c(i) the cluster of i:
//   E = 1/2 sum_i sum_{k in N(i)} w_ik |(x'_i - x'_k) - R_c(i) (x_i - x_k)|^2 / unit^2
//     (+ 1/2 soft_weight sum |x'_i - q_i|^2 / unit^2 over the handle and fixed
//        vertices when the constraints are soft),
// minimised over the free nodes and the cluster rotations.
//
// Kronecker form. With t'_j = g_j + t_j, coordinate d of a skinned vertex is
//   x'_i[d] = sum_j w_ij [R_j(d, :), t'_j[d]] . [x_i - g_j; 1],
// the same coefficients b_i (4 per node) for d = 0, 1, 2. So every column
// ("slot") of the unknowns is shared by the three coordinates: slot 4j + m
// holds R_j(d, m) (m < 3) or t'_j[d] (m = 3) in coordinate d. Pseudo-nodes
// complete it: one a handle group g (slots 4(n+g)..4(n+g)+3: [A_g(d, :),
// t_g[d]], coefficients [x_i; 1]) and the rest pose after them (slots
// 4(n+G)..4(n+G)+3: [e_d, 0]). With exact constraints a moveable-handle
// vertex is its group's pseudo-node and a fixed vertex the rest's: both are constants outside the subspace, exact by
// construction. Per coordinate d, with u_d the vector of all slots,
//   2 unit^2 E = sum_d u_d^T Q u_d - 2 sum_c tr(R_c^T S_c) + C,
//   S_c(d, :) = (K_c u_d)^T,  S_c = sum_{i in c} sum_k w_ik (x'_i - x'_k)(x_i - x_k)^T,
// Q, K_c and C fixed per layout. A frame touches only these (the local step
// fits R_c = polar(S_c); the global step solves Q_vv v_d = sum_c K_c^T R_c(d, :)^T
// - Q_vk k_d over the variable slots v with one factorisation per layout),
// then skins the mesh once: its cost does not grow with the vertex count.
//
// Only "active" vertices enter (those that can move, and their neighbours):
// every other vertex's spokes are rest edges with R = I and add 0.

#ifndef MSDEFORM_SOLVERS_SUBSPACE_ARAP_H_
#define MSDEFORM_SOLVERS_SUBSPACE_ARAP_H_

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>

#include "msdeform/core/cotangent_weights.h"
#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"
#include "msdeform/core/option_table.h"
#include "msdeform/solvers/node_class.h"

namespace msdeform {

// How the active vertices share rotations: k-means on the skinning weights
// (FAST), one cluster per node's support (each vertex with its heaviest
// node), or one rotation per vertex (the ARAP energy as metrics measure it).
enum class RotationClusters { kWeights, kNodes, kVertices };
// Handle and fixed vertices: constants outside the subspace (exact), or
// skinned and pulled by soft position terms.
enum class ArapConstraints { kExact, kSoft };
// How --backend=gauss_newton minimises it (solvers/arap_solver.h): local/global
// iterations (the rotations refitted, then the nodes solved with the
// rotations held) or Gauss-Newton on the nodes and the cluster rotations
// jointly.
enum class ArapSolver { kLocalGlobal, kGaussNewton };

const EnumNames<RotationClusters>& RotationClustersNames();
const EnumNames<ArapConstraints>& ArapConstraintsNames();
const EnumNames<ArapSolver>& ArapSolverNames();  // "local_global", "gauss_newton"

struct ArapOptions {
  RotationClusters clusters = RotationClusters::kWeights;
  // kWeights: clusters over the active vertices (fewer when there are fewer
  // active vertices).
  int num_clusters = 300;
  // kWeights: Lloyd iterations of the k-means.
  int kmeans_iterations = 8;
  ArapConstraints constraints = ArapConstraints::kExact;
  // kSoft: weight of |x'_i - q_i|^2 against the cotangent-weighted spokes.
  double soft_weight = 1000.0;
  // The solver of --backend=gauss_newton (Ceres runs its own).
  ArapSolver solver = ArapSolver::kLocalGlobal;
  // solver=local_global: Anderson acceleration's window (solvers/
  // anderson_acceleration.h, with the energy safeguard), the number of past
  // iterates combined; 0 runs the plain local/global iteration.
  int anderson_window = 0;

  bool Check(std::string* error) const;  // messages name the field
};

// The terms of one layout's subspace energy, as data: what the solvers read.
// scales/subspace_arap_build.h builds them from the mesh, the graph and the
// handle layout; SubspaceArap answers the solvers' questions about them. The
// mesh, cotangent and graph pointers must outlive the data, which `owner`,
// kept with it, can guarantee.
struct SubspaceArapData {
  // Per vertex: how its position is formed (see SubspaceArap::Basis).
  enum class VertexKind : char { kSkinned, kHandle, kRest };

  ArapOptions options;
  int num_nodes = 0;
  // Handle groups (core/handles.h), each a pseudo-node after the nodes.
  int num_handle_groups = 1;
  // Per vertex: its handle group when the layout has several (else empty).
  std::vector<int> vertex_handle_group;
  double length_unit = 1.0;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  int num_active_vertices = 0;
  std::vector<VertexKind> kind;  // per vertex
  std::shared_ptr<const void> owner;  // keeps mesh, cotangent, graph alive
  const Mesh* mesh = nullptr;
  const CotangentWeights* cotangent = nullptr;
  const DeformationGraph* graph = nullptr;
  std::vector<int> cluster_of_vertex;
  std::vector<int> cluster_offsets;   // clusters' vertices in cluster_vertices
  std::vector<int> cluster_vertices;
  std::vector<int> exact_moveable, exact_fixed;
  std::vector<int> variable_slot;     // per variable
  std::vector<int> variable_of_slot;  // per slot, -1 when known
  // Q over every slot (symmetric, both halves) and its variable block.
  Eigen::SparseMatrix<double> q;
  Eigen::SparseMatrix<double> q_vv;
  Eigen::SparseMatrix<double> q_vk;  // variable rows, known columns (others 0)
  // K_c as (slot, 3-vector) entries, clusters in k_offsets.
  std::vector<int> k_offsets;
  std::vector<int> k_slot;
  Eigen::Matrix3Xd k_vector;
  std::vector<Eigen::Matrix3d> covariance;  // Cov_c
  double constant = 0.0;  // C

  // The nodes', each handle group's and the rest pose's 4 slots.
  int num_slots() const { return 4 * (num_nodes + num_handle_groups + 1); }
  // The rest pose's pseudo-node; handle group g's is num_nodes + g.
  int rest_node() const { return num_nodes + num_handle_groups; }
  int num_slot_variables() const { return static_cast<int>(variable_slot.size()); }
  int num_clusters() const { return static_cast<int>(cluster_offsets.size()) - 1; }
  // The pseudo-node a vertex is (num_nodes + g for handle group g,
  // rest_node() for the rest pose), or -1 for a skinned vertex.
  int PseudoNode(int vertex) const;
};

// A vertex's basis entry: a node or pseudo-node and its 4 coefficients.
struct SubspaceNodeCoefficient {
  int node;
  Eigen::Vector4d coefficient;
};

// Appends vertex v's basis to *out: the pseudo-node `pseudo_node` with
// coefficients [x_v - origin; 1] (the handle or the rest pose), or, for a
// skinned vertex (pseudo_node < 0), w_j [x_v - g_j; 1] per node j of non-zero
// weight, a node in two slots once.
void AppendSubspaceBasis(int v, int pseudo_node, const Mesh& mesh, const DeformationGraph& graph,
                         const Eigen::Vector3d& origin,
                         std::vector<SubspaceNodeCoefficient>* out);

// R maximising tr(R^T S) over rotations (no reflection): the local step.
Eigen::Matrix3d BestRotation(const Eigen::Matrix3d& s);

class SubspaceArap {
 public:
  // Per coordinate: one column per slot, 3 columns (d = 0, 1, 2).
  using Slots = Eigen::Matrix<double, Eigen::Dynamic, 3>;
  using Rotations = std::vector<Eigen::Matrix3d>;

  explicit SubspaceArap(SubspaceArapData data) : data_(std::move(data)) {}

  const ArapOptions& options() const { return data_.options; }
  int num_nodes() const { return data_.num_nodes; }
  int num_handle_groups() const { return data_.num_handle_groups; }
  int num_slots() const { return data_.num_slots(); }
  // Variable slots per coordinate (4 a Totally Free node, 3 a Half Free one);
  // the solve has 3 times as many variables.
  int num_slot_variables() const { return data_.num_slot_variables(); }
  int num_variables() const { return 3 * num_slot_variables(); }
  int num_clusters() const { return data_.num_clusters(); }
  int num_active_vertices() const { return data_.num_active_vertices; }
  // Per mesh vertex: its rotation cluster, or -1 outside the active set.
  const std::vector<int>& cluster_of_vertex() const { return data_.cluster_of_vertex; }
  // The vertices the exact constraints set (moveable: the handle transform
  // times rest; fixed: rest), outside still components. Empty when soft.
  const std::vector<int>& exact_moveable() const { return data_.exact_moveable; }
  const std::vector<int>& exact_fixed() const { return data_.exact_fixed; }
  // The slot of each variable, ascending.
  const std::vector<int>& variable_slots() const { return data_.variable_slot; }

  // u at `transforms` (Fixed nodes and Half Free translations from it, as
  // the layout holds them) with the handle at `handle`.
  void Gather(const NodeTransforms& transforms, const HandleTransforms& handles, Slots* u) const;
  // Writes the variable slots of u into *transforms (R_j rows, t_j = t'_j - g_j).
  void Scatter(const Slots& u, NodeTransforms* transforms) const;
  // S_c at u.
  Eigen::Matrix3d Covariance(const Slots& u, int c) const;
  // The local step: R_c maximising tr(R_c^T S_c) (no reflection). Returns
  // sum_c tr(R_c^T S_c), for EnergyFromTrace.
  double FitRotations(const Slots& u, Rotations* rotations) const;
  // The energy at u given sum_c tr(R_c^T S_c).
  double EnergyFromTrace(const Slots& u, double trace) const;
  // Energy at u with the best rotations.
  double Cost(const Slots& u) const;
  // The global step's right-hand side over the variable slots:
  // sum_c K_c,v^T R_c(d, :)^T - Q_vk k_d, one column per coordinate.
  void GlobalRhs(const Slots& u, const Rotations& rotations, Slots* rhs) const;
  // Q_vv: the global step's matrix (per coordinate), lower and upper parts.
  const Eigen::SparseMatrix<double>& system_matrix() const { return data_.q_vv; }
  // The variable values of u, one row per variable slot.
  void Variables(const Slots& u, Slots* v) const;
  void SetVariables(const Slots& v, Slots* u) const;

  // The slots a vertex's deformed position x'_i = sum b . u (per coordinate)
  // reads: (first slot of a node or pseudo-node, 4 coefficients).
  struct BasisEntry {
    int slot;
    Eigen::Vector4d coefficient;
  };
  std::vector<BasisEntry> Basis(int vertex) const;
  // The vertices of cluster c.
  std::vector<int> ClusterVertices(int c) const;
  double length_unit() const { return data_.length_unit; }
  // The origin of the slots' positions (the active vertices' centroid): a
  // vertex's sum_b b . u is x'_i - origin(), slot 4j + 3 holds
  // g_j + t_j - origin(), and the handle's holds A origin + t - origin.
  const Eigen::Vector3d& origin() const { return data_.origin; }
  const CotangentWeights& cotangent() const { return *data_.cotangent; }

  // For solvers beyond the local/global one (solvers/arap_solver.h, the Ceres
  // backend). Q over every slot (both halves; the cluster spokes' and the
  // soft terms').
  const Eigen::SparseMatrix<double>& full_matrix() const { return data_.q; }
  // K_c: entries k_offsets()[c] .. k_offsets()[c + 1] - 1 are (slot
  // k_slots()[e], 3-vector k_vectors().col(e)), each slot at most once per
  // cluster; S_c(d, :) = sum_e u(slot, d) k^T.
  const std::vector<int>& k_offsets() const { return data_.k_offsets; }
  const std::vector<int>& k_slots() const { return data_.k_slot; }
  const Eigen::Matrix3Xd& k_vectors() const { return data_.k_vector; }
  // Cov_c = sum over the spokes of cluster c of w e e^T (rest edges e), per
  // cluster: the rotations' block of the Gauss-Newton normal equations is
  // tr(Cov_c) I - Cov_c.
  const std::vector<Eigen::Matrix3d>& cluster_covariances() const { return data_.covariance; }
  // The variable of a slot, or -1 when the slot is known.
  int variable_of_slot(int slot) const { return data_.variable_of_slot[slot]; }

 private:
  SubspaceArapData data_;
};

// ArapOptions' rows (core/option_table.h), declared in its header beside the fields: a new field is
// the field above and its row here. ArapOptionTable() (subspace_arap.cc) builds the table from them
// once; a template, so that only that file compiles the rows.
template <typename Table>
void DeclareArapOptionRows(Table& t) {
  using A = ArapOptions;
  t.Enum("clusters", &A::clusters, RotationClustersNames(),
         "Rotation clusters of the subspace ARAP energy: weights (k-means on the skinning "
         "weights, FAST), nodes (one per node's support) or vertices (one per vertex).");
  t.Int("num_clusters", &A::num_clusters, "clusters=weights: clusters over the active vertices.")
      .Range(1, kOptionIntMax, "an integer >= 1");
  t.Int("kmeans_iterations", &A::kmeans_iterations,
        "clusters=weights: Lloyd iterations of the k-means.")
      .Range(0, kOptionIntMax, "an integer >= 0");
  t.Enum("constraints", &A::constraints, ArapConstraintsNames(),
         "Handle and fixed vertices of the subspace ARAP energy: exact (constants outside "
         "the subspace) or soft (skinned, pulled by position terms of soft_weight).");
  t.Double("soft_weight", &A::soft_weight,
           "constraints=soft: weight of |x' - q|^2 against the cotangent-weighted edges.")
      .Above(0, "a finite weight > 0");
  t.Enum("solver", &A::solver, ArapSolverNames(),
         "The subspace ARAP energy's solver under backend=gauss_newton: local_global "
         "(rotations fitted, then the nodes solved) or gauss_newton (nodes and cluster "
         "rotations jointly, the rotations eliminated per cluster).");
  t.Int("anderson_window", &A::anderson_window,
        "solver=local_global: Anderson acceleration's window (past iterates combined, "
        "with the energy safeguard); 0 runs plain local/global.")
      .Range(0, 50, "an integer in 0..50");
}
const OptionTable<ArapOptions>& ArapOptionTable();

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_SUBSPACE_ARAP_H_
