#include "msdeform/core/nearest_nodes.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>

#include <glog/logging.h>
#include <omp.h>

namespace msdeform {

SkinningWeights::SkinningWeights(int k, int num_vertices, int num_nodes, Unset)
    : k_(k), num_vertices_(num_vertices), has_16bit_ids_(num_nodes <= kMaxNodesFor16BitIds) {
  CHECK(k >= 1 && k <= kMaxK) << "k = " << k;
  CHECK_GE(num_vertices, 0);
  CHECK_GE(num_nodes, 1);
  const size_t slots = static_cast<size_t>(k) * num_vertices;
  if (has_16bit_ids_) {
    ids16_.resize(slots);
  } else {
    ids32_.resize(slots);
  }
  weights_.resize(slots);
}

SkinningWeights::SkinningWeights(int k, int num_vertices, int num_nodes)
    : SkinningWeights(k, num_vertices, num_nodes, Unset()) {
  std::fill(ids16_.begin(), ids16_.end(), 0);
  std::fill(ids32_.begin(), ids32_.end(), 0);
  std::fill(weights_.begin(), weights_.end(), 0.0f);
}

void SkinningWeights::SetVertex(int v, const int* nodes, const double* weights) {
  DCHECK(v >= 0 && v < num_vertices_);
  // Rounded to multiples of 2^-24, the correction to an exact sum of 2^24 on
  // the largest: every value is an integer <= 2^24 times 2^-24, exact in a
  // float, and so is every partial sum (nearest_nodes.h).
  constexpr double kGrid = 16777216.0;  // 2^24
  int64_t q[kMaxK];
  q[0] = 0;  // k_ >= 1 sets it again; for the compiler's uninitialised-use analysis
  int64_t sum = 0;
  int largest = 0;
  for (int s = 0; s < k_; ++s) {
    DCHECK(weights[s] >= 0.0 && weights[s] <= 1.0 + 1e-9) << "weight " << weights[s];
    q[s] = static_cast<int64_t>(weights[s] * kGrid + 0.5);  // weights are >= 0
    sum += q[s];
    if (q[s] > q[largest]) largest = s;
  }
  q[largest] += static_cast<int64_t>(kGrid) - sum;
  CHECK_GE(q[largest], 0) << "weights of vertex " << v << " do not sum to 1";
  const size_t first = static_cast<size_t>(k_) * v;
  for (int s = 0; s < k_; ++s) {
    weights_[first + s] = static_cast<float>(static_cast<double>(q[s]) / kGrid);
  }
  if (has_16bit_ids_) {
    for (int s = 0; s < k_; ++s) {
      DCHECK(nodes[s] >= 0 && nodes[s] < kMaxNodesFor16BitIds);
      ids16_[first + s] = static_cast<uint16_t>(nodes[s]);
    }
  } else {
    std::copy(nodes, nodes + k_, ids32_.begin() + first);
  }
}

bool NearestNodeOptions::Check(std::string* error) const {
  if (k < 1 || k > SkinningWeights::kMaxK) {
    *error = "k (nearest nodes per vertex) must be in [1, " +
             std::to_string(SkinningWeights::kMaxK) + "], got " + std::to_string(k);
    return false;
  }
  if (extra_rings < 0) {
    *error = "extra_rings must be >= 0, got " + std::to_string(extra_rings);
    return false;
  }
  if (num_threads < 0 || num_threads > kMaxThreads) {
    *error = "num_threads must be in 0.." + std::to_string(kMaxThreads) +
             " (0: OpenMP default), got " + std::to_string(num_threads);
    return false;
  }
  return true;
}

CompressedLists CandidateNodesOfCells(const Lattice& lattice, const std::vector<int>& node_of_cell,
                                      int num_nodes, int min_count, int extra_rings) {
  const int num_cells = lattice.num_surface_particles();
  CHECK_EQ(static_cast<int>(node_of_cell.size()), num_cells);
  CHECK_GE(min_count, 1);
  CHECK_GE(extra_rings, 0);
  const CompressedLists& ring = lattice.neighborhood();

  // Layer r adds to cell c the nodes at hop distance exactly r: those found at
  // distance r - 1 by an L-neighbour and not yet known to c. A cell stops
  // accepting after layer r* + extra_rings, r* being the first layer at which
  // it knows min_count nodes. This is exact: if c needs node X at distance
  // r + 1 through neighbour c', then r + 1 <= r*(c) + extra <= r*(c') + 1 +
  // extra, so c' kept X at distance r.
  std::vector<std::vector<int>> found(num_cells);
  std::vector<int> layer_begin(num_cells, 0), layer_end(num_cells, 1);
  std::vector<int> pending_begin(num_cells, 0), touched_at(num_cells, 0);
  std::vector<int> last_layer(num_cells, INT_MAX);
  std::vector<int> frontier(num_cells), next;
  for (int c = 0; c < num_cells; ++c) {
    CHECK(node_of_cell[c] >= 0 && node_of_cell[c] < num_nodes) << "cell " << c;
    found[c].push_back(node_of_cell[c]);
    if (min_count <= 1) last_layer[c] = extra_rings;
    frontier[c] = c;
  }
  for (int layer = 1; !frontier.empty(); ++layer) {
    next.clear();
    for (const int from : frontier) {
      for (const int* to = ring.begin(from); to != ring.end(from); ++to) {
        if (layer > last_layer[*to]) continue;
        std::vector<int>& list = found[*to];
        for (int i = layer_begin[from]; i < layer_end[from]; ++i) {
          const int node = found[from][i];
          if (std::find(list.begin(), list.end(), node) != list.end()) continue;
          if (touched_at[*to] != layer) {
            touched_at[*to] = layer;
            pending_begin[*to] = static_cast<int>(list.size());
            next.push_back(*to);
          }
          list.push_back(node);
        }
      }
    }
    for (const int c : next) {
      layer_begin[c] = pending_begin[c];
      layer_end[c] = static_cast<int>(found[c].size());
      if (last_layer[c] == INT_MAX && layer_end[c] >= min_count) {
        last_layer[c] = layer + extra_rings;
      }
    }
    frontier.swap(next);
  }

  CompressedLists candidates;
  candidates.offsets.resize(num_cells + 1);
  candidates.offsets[0] = 0;
  for (int c = 0; c < num_cells; ++c) {
    candidates.offsets[c + 1] = candidates.offsets[c] + static_cast<int64_t>(found[c].size());
  }
  candidates.values.reserve(candidates.offsets[num_cells]);
  for (int c = 0; c < num_cells; ++c) {
    std::sort(found[c].begin(), found[c].end());
    candidates.values.insert(candidates.values.end(), found[c].begin(), found[c].end());
  }
  return candidates;
}

namespace {

// Vertices per chunk of ComputeNearestNodes' parallel loop.
constexpr int kVertexChunk = 1024;

}  // namespace

void ComputeNearestNodes(const Eigen::Matrix3Xd& vertices, const Lattice& lattice,
                         const Eigen::Matrix3Xd& node_positions,
                         const std::vector<int>& node_of_cell, const NearestNodeOptions& options,
                         SkinningWeights* weights, std::vector<std::pair<int, int>>* edges) {
  CHECK(weights != nullptr);
  CHECK(edges != nullptr);
  std::string error;
  CHECK(options.Check(&error)) << error;
  const int num_vertices = static_cast<int>(vertices.cols());
  const int num_nodes = static_cast<int>(node_positions.cols());
  CHECK_EQ(static_cast<int>(lattice.particle_of_vertex().size()), num_vertices)
      << "the lattice was built from another mesh";
  const int k = options.k;
  const CompressedLists candidates =
      CandidateNodesOfCells(lattice, node_of_cell, num_nodes, k + 1, options.extra_rings);
  const int num_cells = lattice.num_surface_particles();
  const int num_threads = options.num_threads > 0 ? options.num_threads : omp_get_max_threads();

  *weights = SkinningWeights(k, num_vertices, num_nodes, SkinningWeights::Unset());
  std::vector<int> pair_count(num_nodes + 1, 0);
  std::vector<std::vector<std::pair<int, int>>> thread_pairs(num_threads);

  // Edges are recorded per cell as bits over pairs of its candidates (bit
  // a * m + b for candidates a < b), in one bit table per thread.
  std::vector<int64_t> word_offset(num_cells + 1, 0);
  for (int c = 0; c < num_cells; ++c) {
    const int64_t m = candidates.size(c);
    word_offset[c + 1] = word_offset[c] + (m * m + 63) / 64;
  }
  std::vector<std::vector<uint64_t>> thread_bits(num_threads);
  const std::vector<int>& particle_of_vertex = lattice.particle_of_vertex();

  // Vertices in chunks handed out one at a time: a vertex costs in proportion
  // to its cell's candidates, which vary over the mesh (a static split left
  // one thread 10% behind on the 1.66M armadillo). Every output of a vertex
  // is its own and the bit tables are merged by OR, so which thread runs a
  // chunk changes nothing. One chunk or less: no team.
  const int team = num_vertices > kVertexChunk ? num_threads : 1;
#pragma omp parallel num_threads(team)
  {
    std::vector<uint64_t>& bits = thread_bits[omp_get_thread_num()];
    bits.assign(word_offset[num_cells], 0);
    std::vector<double> best_distance(k + 1);  // Squared, ascending.
    std::vector<int> best(k + 1);              // Candidate indices.
    std::vector<int> nearest(k);
    std::vector<int> node_out(k);
    std::vector<double> weight_out(k);
    // Vertices in id order within a chunk: inputs and outputs stream through
    // memory, and the node positions (tens of KB) stay in cache.
#pragma omp for schedule(dynamic, kVertexChunk)
    for (int v = 0; v < num_vertices; ++v) {
      const int c = particle_of_vertex[v];
      // Candidates are sorted by node id, so ranking by (distance, index)
      // breaks ties by node id.
      const int* candidate = candidates.begin(c);
      const int m = candidates.size(c);
      const int ranked = std::min(k + 1, m);
      const int used = std::min(k, m);
      const double px = vertices(0, v), py = vertices(1, v), pz = vertices(2, v);
      // The k + 1 nearest candidates, by insertion into a sorted array.
      int count = 0;
      for (int i = 0; i < m; ++i) {
        const double* g = node_positions.col(candidate[i]).data();
        const double dx = g[0] - px, dy = g[1] - py, dz = g[2] - pz;
        const double d2 = dx * dx + dy * dy + dz * dz;
        if (count == ranked && !(d2 < best_distance[ranked - 1])) continue;
        int slot = count < ranked ? count++ : ranked - 1;
        for (; slot > 0 && d2 < best_distance[slot - 1]; --slot) {
          best_distance[slot] = best_distance[slot - 1];
          best[slot] = best[slot - 1];
        }
        best_distance[slot] = d2;
        best[slot] = i;
      }
      // d_max is the (k+1)-th distance; a vertex with at most k candidates
      // uses twice its farthest candidate's distance, so all keep a weight.
      const double d_max =
          m > k ? std::sqrt(best_distance[k]) : 2.0 * std::sqrt(best_distance[m - 1]);
      double sum = 0.0;
      for (int i = 0; i < k; ++i) {
        double w = 0.0;
        if (i < used && d_max > 0.0) {
          const double u = std::max(0.0, 1.0 - std::sqrt(best_distance[i]) / d_max);
          w = u * u;
        }
        weight_out[i] = w;
        node_out[i] = candidate[best[i < used ? i : 0]];
        sum += w;
      }
      if (sum > 0.0 && std::isfinite(sum)) {
        const double inverse = 1.0 / sum;
        for (int i = 0; i < k; ++i) weight_out[i] *= inverse;
      } else {  // d_max = 0 or all k nearest tie with d_max: nearest node only.
        for (int i = 0; i < k; ++i) weight_out[i] = i == 0 ? 1.0 : 0.0;
      }
      weights->SetVertex(v, node_out.data(), weight_out.data());
      std::copy(best.begin(), best.begin() + used, nearest.begin());
      std::sort(nearest.begin(), nearest.begin() + used);
      uint64_t* cell_bits = bits.data() + word_offset[c];
      for (int i = 0; i < used; ++i) {
        for (int j = i + 1; j < used; ++j) {
          const int64_t bit = static_cast<int64_t>(nearest[i]) * m + nearest[j];
          cell_bits[bit / 64] |= uint64_t{1} << (bit % 64);
        }
      }
    }

    // Merge the bit tables and list the pairs, cell by cell.
    std::vector<std::pair<int, int>>& local_pairs = thread_pairs[omp_get_thread_num()];
#pragma omp for schedule(static)
    for (int c = 0; c < num_cells; ++c) {
      const int* candidate = candidates.begin(c);
      const int m = candidates.size(c);
      for (int64_t word = word_offset[c]; word < word_offset[c + 1]; ++word) {
        uint64_t merged = 0;
        for (const std::vector<uint64_t>& table : thread_bits) {
          if (!table.empty()) merged |= table[word];  // Empty: the team had fewer threads.
        }
        for (; merged != 0; merged &= merged - 1) {
          const int64_t bit = (word - word_offset[c]) * 64 + __builtin_ctzll(merged);
          local_pairs.emplace_back(candidate[bit / m], candidate[bit % m]);
        }
      }
    }
  }

  // Bucket the pairs by their first node, then sort and deduplicate each bucket.
  for (const auto& local_pairs : thread_pairs) {
    for (const auto& pair : local_pairs) ++pair_count[pair.first + 1];
  }
  for (int j = 0; j < num_nodes; ++j) pair_count[j + 1] += pair_count[j];
  std::vector<int> second(pair_count[num_nodes]);
  std::vector<int> fill(pair_count.begin(), pair_count.end() - 1);
  for (const auto& local_pairs : thread_pairs) {
    for (const auto& [a, b] : local_pairs) second[fill[a]++] = b;
  }
  edges->clear();
  for (int a = 0; a < num_nodes; ++a) {
    auto begin = second.begin() + pair_count[a], end = second.begin() + pair_count[a + 1];
    std::sort(begin, end);
    end = std::unique(begin, end);
    for (auto b = begin; b != end; ++b) edges->emplace_back(a, *b);
  }
}

}  // namespace msdeform
