#include "msdeform/core/deformation_graph.h"

#include <algorithm>
#include <random>
#include <sstream>

#include <glog/logging.h>
#include <omp.h>

#include "msdeform/core/edge_collapse.h"

namespace msdeform {
namespace {

// DG1 without weights: one node per surface cell on a random vertex of it.
DeformationGraph MakeFinestGraph(const Mesh& mesh, const Lattice& lattice, uint64_t seed) {
  const int num_cells = lattice.num_surface_particles();
  const CompressedLists& cell_vertices = lattice.vertices_of_particle();
  DeformationGraph graph;
  graph.positions.resize(3, num_cells);
  graph.node_vertex.resize(num_cells);
  graph.node_of_dg1.resize(num_cells);
  graph.members.offsets.resize(num_cells + 1);
  graph.members.values.resize(num_cells);
  // rng() % n rather than std::uniform_int_distribution: the latter's output
  // differs between standard libraries, and the bias of % is below 1e-15.
  std::mt19937_64 rng(seed);
  for (int c = 0; c < num_cells; ++c) {
    const int count = cell_vertices.size(c);
    CHECK_GT(count, 0) << "surface cell " << c << " holds no vertex";
    const int vertex = cell_vertices.begin(c)[rng() % static_cast<uint64_t>(count)];
    graph.node_vertex[c] = vertex;
    graph.positions.col(c) = mesh.vertices.col(vertex);
    graph.node_of_dg1[c] = c;
    graph.members.offsets[c] = c;
    graph.members.values[c] = c;
  }
  graph.members.offsets[num_cells] = num_cells;
  return graph;
}

}  // namespace

void DeformationGraph::Disconnect() {
  std::vector<std::pair<int, int>>().swap(edges);
  neighbors = CompressedLists();
  weights = SkinningWeights();
}

void ConnectGraph(const Mesh& mesh, const Lattice& lattice, const GraphOptions& options,
                  DeformationGraph* graph) {
  ComputeNearestNodes(mesh.vertices, lattice, graph->positions, graph->node_of_dg1,
                      options.nearest_nodes(),
                      &graph->weights, &graph->edges);
  const int num_nodes = graph->num_nodes();
  CompressedLists& neighbors = graph->neighbors;
  neighbors.offsets.assign(num_nodes + 1, 0);
  for (const auto& [a, b] : graph->edges) {
    ++neighbors.offsets[a + 1];
    ++neighbors.offsets[b + 1];
  }
  for (int j = 0; j < num_nodes; ++j) neighbors.offsets[j + 1] += neighbors.offsets[j];
  neighbors.values.resize(neighbors.offsets[num_nodes]);
  std::vector<int64_t> fill(neighbors.offsets.begin(), neighbors.offsets.end() - 1);
  for (const auto& [a, b] : graph->edges) {
    neighbors.values[fill[a]++] = b;
    neighbors.values[fill[b]++] = a;
  }
  for (int j = 0; j < num_nodes; ++j) {
    std::sort(neighbors.values.begin() + neighbors.offsets[j],
              neighbors.values.begin() + neighbors.offsets[j + 1]);
  }
}

NearestNodeOptions GraphOptions::nearest_nodes() const {
  NearestNodeOptions nearest;
  nearest.k = k;
  nearest.extra_rings = extra_rings;
  nearest.num_threads = num_threads;
  return nearest;
}

bool GraphOptions::Check(std::string* error) const {
  // The rows' ranges (GraphOptionTable(), deformation_graph.h), then the
  // nearest-node search's own checks.
  if (!GraphOptionTable().CheckRanges(*this, error)) return false;
  return nearest_nodes().Check(error);
}

NodeTransforms NodeTransforms::Identity(int num_nodes) {
  CHECK_GE(num_nodes, 0);
  NodeTransforms transforms;
  transforms.rotations.resize(9, num_nodes);
  for (int j = 0; j < num_nodes; ++j) {
    transforms.rotations.col(j) << 1, 0, 0, 0, 1, 0, 0, 0, 1;
  }
  transforms.translations.setZero(3, num_nodes);
  return transforms;
}

int NumScales(int num_dg1_nodes, int nodes_per_scale) {
  CHECK_GE(num_dg1_nodes, 0);
  CHECK_GE(nodes_per_scale, 1);
  return std::max(1, num_dg1_nodes / nodes_per_scale);
}

int NodesAtScale(int num_dg1_nodes, int scale) {
  CHECK_GE(num_dg1_nodes, 0);
  CHECK_GE(scale, 1);
  return static_cast<int>((2 * static_cast<int64_t>(num_dg1_nodes) + scale) /
                          (2 * static_cast<int64_t>(scale)));
}

bool BuildMultiScaleGraphs(const Mesh& mesh, const Lattice& lattice, const GraphOptions& options,
                           std::vector<DeformationGraph>* graphs, std::string* error,
                           Connect connect, StageTimes* times) {
  if (!options.Check(error)) return false;
  const int num_dg1 = lattice.num_surface_particles();
  const int num_scales = NumScales(num_dg1, options.nodes_per_scale);
  std::vector<int> node_counts;
  for (int i = 2; i <= num_scales; ++i) node_counts.push_back(NodesAtScale(num_dg1, i));
  return BuildCollapsedGraphs(mesh, lattice, options, node_counts, graphs, error, connect, times);
}

bool BuildCollapsedGraphs(const Mesh& mesh, const Lattice& lattice, const GraphOptions& options,
                          const std::vector<int>& node_counts,
                          std::vector<DeformationGraph>* graphs, std::string* error,
                          Connect connect, StageTimes* times) {
  CHECK(graphs != nullptr);
  if (!options.Check(error)) return false;
  CHECK_EQ(static_cast<int>(lattice.particle_of_vertex().size()), mesh.num_vertices())
      << "the lattice was built from another mesh";
  const int num_dg1 = lattice.num_surface_particles();
  for (size_t i = 0; i < node_counts.size(); ++i) {
    const int previous = i == 0 ? num_dg1 : node_counts[i - 1];
    if (node_counts[i] < 1 || node_counts[i] > previous) {
      std::ostringstream message;
      message << "node count " << i << " is " << node_counts[i]
              << "; node counts must be non-increasing and in [1, D1 = " << num_dg1 << "]";
      *error = message.str();
      return false;
    }
  }

  graphs->clear();
  graphs->reserve(node_counts.size() + 1);
  {
    ScopedStage stage(times, "dg1_nodes");
    graphs->push_back(MakeFinestGraph(mesh, lattice, options.seed));
  }
  {
    ScopedStage stage(times, "dg1_nearest_nodes");
    ConnectGraph(mesh, lattice, options, &graphs->front());
  }
  {
    ScopedStage stage(times, "edge_collapses");
    EdgeCollapse collapse(graphs->front());
    for (const int count : node_counts) {
      collapse.CollapseTo(count);
      graphs->push_back(collapse.Snapshot());
    }
  }
  if (connect == Connect::kFinestOnly) return true;
  ScopedStage stage(times, "coarse_nearest_nodes");
  // The coarse scales are independent: with enough of them, one thread per
  // scale also shares out the serial parts (candidate search, edge lists).
  const int num_coarse = static_cast<int>(graphs->size()) - 1;
  const int num_threads = options.num_threads > 0 ? options.num_threads : omp_get_max_threads();
  if (num_threads > 1 && num_coarse >= 2 * num_threads) {
    GraphOptions one_thread = options;
    one_thread.num_threads = 1;
#pragma omp parallel for num_threads(num_threads) schedule(dynamic, 1)
    for (int i = 1; i <= num_coarse; ++i) ConnectGraph(mesh, lattice, one_thread, &(*graphs)[i]);
  } else {
    for (int i = 1; i <= num_coarse; ++i) ConnectGraph(mesh, lattice, options, &(*graphs)[i]);
  }
  return true;
}

const OptionTable<GraphOptions>& GraphOptionTable() {
  static const OptionTable<GraphOptions>& table =
      MakeOptionTable<GraphOptions>([](auto& t) { DeclareGraphOptionRows(t); });
  return table;
}

}  // namespace msdeform
