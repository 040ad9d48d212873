// The edge collapse that makes the coarse deformation graphs DG_2 .. DG_N from
// DG1 (paper §3.2; core/deformation_graph.h): one pass over the DG1 edge
// graph, shortest edge first, with a snapshot at each node count.
//
// Edges never join two mesh components, so when no edge is left the two
// clusters whose nodes are nearest each other are merged instead (ties: the
// pair of smaller cluster ids). Each cluster keeps its nearest other cluster,
// found in a k-d tree over the DG1 node positions, in one heap: O(C) memory
// and O(C log C) time for C clusters on a fragmented scan, and the same merges
// as queueing every pair of clusters would give.

#ifndef MSDEFORM_CORE_EDGE_COLLAPSE_H_
#define MSDEFORM_CORE_EDGE_COLLAPSE_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <queue>
#include <vector>

#include <Eigen/Core>

#include "msdeform/core/deformation_graph.h"

namespace msdeform {

class EdgeCollapse {
 public:
  // `dg1` with its edges and neighbours (ConnectGraph).
  explicit EdgeCollapse(const DeformationGraph& dg1);
  ~EdgeCollapse();

  int num_clusters() const { return num_clusters_; }
  // Merges clusters until `target` (>= 1) are left; no-op when there are no more.
  void CollapseTo(int target);
  // The current clusters as a graph without weights or edges; nodes numbered
  // by their smallest DG1 member.
  DeformationGraph Snapshot();
  // The most entries its queues held at once (edges, then clusters' nearest
  // clusters, stale ones included): what the collapse's memory grows with.
  int64_t peak_queued() const { return peak_queued_; }

 private:
  struct Entry {
    double squared_length;
    int a, b;  // a < b
    int stamp_a, stamp_b;
    bool operator>(const Entry& other) const;
  };
  struct NearestEntry : Entry {
    int owner;  // the cluster (a or b) it was looked up for
  };
  using Queue = std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>>;
  using NearestQueue =
      std::priority_queue<NearestEntry, std::vector<NearestEntry>, std::greater<Entry>>;
  class SiteTree;

  int Find(int j);
  void Push(int a, int b, Queue* queue);
  bool PopValid(Queue* queue, int* a, int* b);
  void Merge(int a, int b);
  void StartPairs();
  void PushNearest(int root);
  bool PopNearestPair(int* a, int* b);
  void NoteQueued();

  const Eigen::Matrix3Xd dg1_positions_;
  const std::vector<int> dg1_vertex_;
  std::vector<int> parent_;  // Union-find over DG1 ids; a cluster is named by its root.
  std::vector<int> stamp_;   // Bumped whenever a cluster changes.
  std::vector<std::vector<int>> members_;
  std::vector<std::vector<int>> adjacency_;  // May hold stale (merged) ids.
  Eigen::Matrix3Xd sum_;       // Sum of member DG1 positions, per root.
  Eigen::Matrix3Xd position_;  // Node position, per root.
  std::vector<int> vertex_;    // Node vertex, per root.
  std::vector<int> site_;      // DG1 node the node position is taken from, per root.
  int num_clusters_;
  Queue edges_;
  bool out_of_edges_ = false;
  // Once out of edges: the clusters' node positions (their sites), and per
  // cluster one live entry to its nearest other cluster.
  std::unique_ptr<SiteTree> sites_;
  std::vector<int> root_of_site_;
  NearestQueue pairs_;
  int64_t peak_queued_ = 0;
};

}  // namespace msdeform

#endif  // MSDEFORM_CORE_EDGE_COLLAPSE_H_
