#include "msdeform/core/edge_collapse.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <tuple>
#include <utility>

#include <Eigen/Geometry>
#include <glog/logging.h>

namespace msdeform {

// A k-d tree over the DG1 node positions (the sites) in which sites are
// switched on and off; a query finds the on site nearest a point by the
// collapse's order: squared distance, then the id of the site's cluster.
class EdgeCollapse::SiteTree {
 public:
  explicit SiteTree(const Eigen::Matrix3Xd& sites) : sites_(sites) {
    order_.resize(sites.cols());
    std::iota(order_.begin(), order_.end(), 0);
    leaf_of_site_.resize(sites.cols());
    on_.assign(sites.cols(), false);
    if (!order_.empty()) Split(0, static_cast<int>(order_.size()), -1);
  }

  void Switch(int site, bool on) {
    const int change = on ? 1 : -1;
    for (int node = leaf_of_site_[site]; node >= 0; node = nodes_[node].parent) {
      nodes_[node].num_on += change;
    }
    on_[site] = on;
  }

  // The on site other than `skip` nearest site `from` by (squared distance as
  // `distance` computes it, cluster_of[site]); false when there is none.
  template <typename Distance>
  bool Nearest(int from, int skip, const std::vector<int>& cluster_of, const Distance& distance,
               int* nearest, double* squared_distance) const {
    Best best{std::numeric_limits<double>::infinity(), -1, -1};
    if (!nodes_.empty()) Search(0, sites_.col(from), skip, cluster_of, distance, &best);
    *nearest = best.site;
    *squared_distance = best.squared_distance;
    return best.site >= 0;
  }

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int begin, end;        // range of order_
    int left = -1, right = -1, parent = -1;
    int num_on = 0;
  };
  struct Best {
    double squared_distance;
    int cluster, site;
  };
  static constexpr int kLeafSize = 8;

  int Split(int begin, int end, int parent) {
    const int index = static_cast<int>(nodes_.size());
    nodes_.push_back(Node{Eigen::AlignedBox3d(), begin, end});
    nodes_[index].parent = parent;
    Eigen::AlignedBox3d box;
    for (int i = begin; i < end; ++i) box.extend(sites_.col(order_[i]));
    nodes_[index].box = box;
    if (end - begin <= kLeafSize) {
      for (int i = begin; i < end; ++i) leaf_of_site_[order_[i]] = index;
      return index;
    }
    int axis;
    box.sizes().maxCoeff(&axis);
    const int middle = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end,
                     [&](int x, int y) {
                       return std::make_pair(sites_(axis, x), x) <
                              std::make_pair(sites_(axis, y), y);
                     });
    const int left = Split(begin, middle, index);
    const int right = Split(middle, end, index);
    nodes_[index].left = left;
    nodes_[index].right = right;
    return index;
  }

  // A lower bound of the squared distance from `point` to the node's box,
  // shrunk by a relative 1e-9 so that rounding never prunes a tie.
  double LowerBound(int node, const Eigen::Vector3d& point) const {
    const Eigen::AlignedBox3d& box = nodes_[node].box;
    const Eigen::Vector3d gap =
        (box.min() - point).cwiseMax(point - box.max()).cwiseMax(Eigen::Vector3d::Zero());
    return gap.squaredNorm() * (1.0 - 1e-9);
  }

  template <typename Distance>
  void Search(int node, const Eigen::Vector3d& point, int skip, const std::vector<int>& cluster_of,
              const Distance& distance, Best* best) const {
    const Node& n = nodes_[node];
    if (n.num_on == 0 || LowerBound(node, point) > best->squared_distance) return;
    if (n.left < 0) {
      for (int i = n.begin; i < n.end; ++i) {
        const int site = order_[i];
        if (!on_[site] || site == skip) continue;
        const double d = distance(site);
        const int cluster = cluster_of[site];
        if (std::tie(d, cluster) < std::tie(best->squared_distance, best->cluster)) {
          *best = {d, cluster, site};
        }
      }
      return;
    }
    const bool left_first = LowerBound(n.left, point) <= LowerBound(n.right, point);
    Search(left_first ? n.left : n.right, point, skip, cluster_of, distance, best);
    Search(left_first ? n.right : n.left, point, skip, cluster_of, distance, best);
  }

  const Eigen::Matrix3Xd& sites_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
  std::vector<int> leaf_of_site_;
  std::vector<bool> on_;
};

bool EdgeCollapse::Entry::operator>(const Entry& other) const {
  return std::tie(squared_length, a, b) > std::tie(other.squared_length, other.a, other.b);
}

EdgeCollapse::EdgeCollapse(const DeformationGraph& dg1)
    : dg1_positions_(dg1.positions),
      dg1_vertex_(dg1.node_vertex),
      parent_(dg1.num_nodes()),
      stamp_(dg1.num_nodes(), 0),
      members_(dg1.num_nodes()),
      adjacency_(dg1.num_nodes()),
      sum_(dg1.positions),
      position_(dg1.positions),
      vertex_(dg1.node_vertex),
      site_(dg1.num_nodes()),
      num_clusters_(dg1.num_nodes()) {
  CHECK_EQ(dg1.neighbors.num_rows(), dg1.num_nodes()) << "DG1 is not connected (ConnectGraph)";
  for (int j = 0; j < num_clusters_; ++j) {
    parent_[j] = j;
    site_[j] = j;
    members_[j] = {j};
    adjacency_[j].assign(dg1.neighbors.begin(j), dg1.neighbors.end(j));
  }
  for (const auto& [a, b] : dg1.edges) Push(a, b, &edges_);
}

EdgeCollapse::~EdgeCollapse() = default;

void EdgeCollapse::CollapseTo(int target) {
  CHECK_GE(target, 1);
  while (num_clusters_ > target) {
    int a, b;
    if (!out_of_edges_) {
      if (PopValid(&edges_, &a, &b)) {
        Merge(a, b);
        continue;
      }
      StartPairs();
    }
    CHECK(PopNearestPair(&a, &b));
    Merge(a, b);
  }
}

DeformationGraph EdgeCollapse::Snapshot() {
  const int num_dg1 = static_cast<int>(parent_.size());
  DeformationGraph graph;
  graph.node_of_dg1.resize(num_dg1);
  std::vector<int> label(num_dg1, -1), root_of_label;
  root_of_label.reserve(num_clusters_);
  for (int i = 0; i < num_dg1; ++i) {
    const int root = Find(i);
    if (label[root] < 0) {
      label[root] = static_cast<int>(root_of_label.size());
      root_of_label.push_back(root);
    }
    graph.node_of_dg1[i] = label[root];
  }
  const int num_nodes = static_cast<int>(root_of_label.size());
  graph.positions.resize(3, num_nodes);
  graph.node_vertex.resize(num_nodes);
  graph.members.offsets.assign(num_nodes + 1, 0);
  for (int j = 0; j < num_nodes; ++j) {
    const int root = root_of_label[j];
    graph.positions.col(j) = position_.col(root);
    graph.node_vertex[j] = vertex_[root];
    graph.members.offsets[j + 1] =
        graph.members.offsets[j] + static_cast<int64_t>(members_[root].size());
  }
  graph.members.values.resize(num_dg1);
  std::vector<int64_t> fill(graph.members.offsets.begin(), graph.members.offsets.end() - 1);
  for (int i = 0; i < num_dg1; ++i) graph.members.values[fill[graph.node_of_dg1[i]]++] = i;
  return graph;
}

int EdgeCollapse::Find(int j) {
  while (parent_[j] != j) {
    parent_[j] = parent_[parent_[j]];
    j = parent_[j];
  }
  return j;
}

void EdgeCollapse::NoteQueued() {
  peak_queued_ =
      std::max(peak_queued_, static_cast<int64_t>(edges_.size()) + static_cast<int64_t>(pairs_.size()));
}

void EdgeCollapse::Push(int a, int b, Queue* queue) {
  if (a > b) std::swap(a, b);
  queue->push({(position_.col(a) - position_.col(b)).squaredNorm(), a, b, stamp_[a], stamp_[b]});
  NoteQueued();
}

bool EdgeCollapse::PopValid(Queue* queue, int* a, int* b) {
  while (!queue->empty()) {
    const Entry entry = queue->top();
    queue->pop();
    if (parent_[entry.a] == entry.a && parent_[entry.b] == entry.b &&
        stamp_[entry.a] == entry.stamp_a && stamp_[entry.b] == entry.stamp_b) {
      *a = entry.a;
      *b = entry.b;
      return true;
    }
  }
  return false;
}

// Every cluster's nearest other cluster is the pair the old all-pairs queue
// would pop first when it is the nearest pair of all: the heap below pops
// pairs in the same (squared length, a, b) order. An entry whose far side
// has changed since is looked up again; one whose own side (the cluster it
// was looked up for) has changed is dropped, the change having pushed a new one.
void EdgeCollapse::StartPairs() {
  out_of_edges_ = true;
  sites_ = std::make_unique<SiteTree>(dg1_positions_);
  root_of_site_.assign(parent_.size(), -1);
  for (int j = 0; j < static_cast<int>(parent_.size()); ++j) {
    if (parent_[j] != j) continue;
    root_of_site_[site_[j]] = j;
    sites_->Switch(site_[j], true);
  }
  for (int j = 0; j < static_cast<int>(parent_.size()); ++j) {
    if (parent_[j] == j) PushNearest(j);
  }
}

void EdgeCollapse::PushNearest(int root) {
  const auto distance = [&](int site) {
    const int other = root_of_site_[site];
    return root < other ? (position_.col(root) - position_.col(other)).squaredNorm()
                        : (position_.col(other) - position_.col(root)).squaredNorm();
  };
  int site;
  double squared_distance;
  if (!sites_->Nearest(site_[root], site_[root], root_of_site_, distance, &site,
                       &squared_distance)) {
    return;
  }
  const int other = root_of_site_[site];
  const int a = std::min(root, other), b = std::max(root, other);
  NearestEntry entry;
  static_cast<Entry&>(entry) = {squared_distance, a, b, stamp_[a], stamp_[b]};
  entry.owner = root;
  pairs_.push(entry);
  NoteQueued();
}

bool EdgeCollapse::PopNearestPair(int* a, int* b) {
  const auto live = [&](int root, int stamp) {
    return parent_[root] == root && stamp_[root] == stamp;
  };
  while (!pairs_.empty()) {
    const NearestEntry entry = pairs_.top();
    pairs_.pop();
    const bool owner_is_a = entry.owner == entry.a;
    if (!live(entry.owner, owner_is_a ? entry.stamp_a : entry.stamp_b)) continue;
    if (!live(owner_is_a ? entry.b : entry.a, owner_is_a ? entry.stamp_b : entry.stamp_a)) {
      PushNearest(entry.owner);  // its nearest cluster has changed since
      continue;
    }
    *a = entry.a;
    *b = entry.b;
    return true;
  }
  return false;
}

void EdgeCollapse::Merge(int a, int b) {
  const int keep = members_[a].size() >= members_[b].size() ? a : b;
  const int gone = keep == a ? b : a;
  parent_[gone] = keep;
  ++stamp_[keep];
  ++stamp_[gone];
  --num_clusters_;
  members_[keep].insert(members_[keep].end(), members_[gone].begin(), members_[gone].end());
  std::vector<int>().swap(members_[gone]);
  sum_.col(keep) += sum_.col(gone);

  // Placed on the member node vertex nearest the members' centroid.
  const Eigen::Vector3d centroid = sum_.col(keep) / static_cast<double>(members_[keep].size());
  int best = -1;
  double best_distance = 0.0;
  for (const int member : members_[keep]) {
    const double distance = (dg1_positions_.col(member) - centroid).squaredNorm();
    if (best < 0 || distance < best_distance || (distance == best_distance && member < best)) {
      best = member;
      best_distance = distance;
    }
  }
  if (out_of_edges_) {
    sites_->Switch(site_[keep], false);
    sites_->Switch(site_[gone], false);
    root_of_site_[site_[gone]] = -1;
    root_of_site_[best] = keep;
    sites_->Switch(best, true);
  }
  site_[keep] = best;
  position_.col(keep) = dg1_positions_.col(best);
  vertex_[keep] = dg1_vertex_[best];

  std::vector<int> adjacency;
  adjacency.reserve(adjacency_[keep].size() + adjacency_[gone].size());
  for (const int side : {keep, gone}) {
    for (const int x : adjacency_[side]) {
      const int root = Find(x);
      if (root != keep) adjacency.push_back(root);
    }
    std::vector<int>().swap(adjacency_[side]);
  }
  std::sort(adjacency.begin(), adjacency.end());
  adjacency.erase(std::unique(adjacency.begin(), adjacency.end()), adjacency.end());
  adjacency_[keep] = std::move(adjacency);

  if (!out_of_edges_) {
    for (const int x : adjacency_[keep]) Push(keep, x, &edges_);
  } else {
    CHECK(adjacency_[keep].empty());
    PushNearest(keep);
  }
}

}  // namespace msdeform
