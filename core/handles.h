// Handle layouts: which vertices are held still and which regions the user
// drags (handle groups, each moved by its own transform), plus the
// Botsch-Sorkine file formats that describe a layout of one group.
//
// .sel (per-vertex status, in the mesh's vertex order):
//   # per vertex status: 0=fixed, 1=deformable-region, 2=handle
//   # 620 vertices
//   1
//   2
//   0
//   ...               exactly one integer per vertex; '#' lines are comments
//
// .def (the handle transform deformed_from_rest, a 4x4 affine matrix, row by
// row; '#' lines are comments; the last row must be 0 0 0 1):
//   # 4x4 handle transformation matrix
//   0.999641 0.021031 0.016579 -0.019322
//   ...
//   0.000000 0.000000 0.000000 1.000000

#ifndef MSDEFORM_CORE_HANDLES_H_
#define MSDEFORM_CORE_HANDLES_H_

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

namespace msdeform {

// Upper bound of the handle groups of one layout: a group is a handle the
// user drags on its own, and each adds 12 parameters to every frame's solve.
constexpr int kMaxHandleGroups = 64;

struct HandleLayout {
  // Vertices held at their rest position: the union of all fixed regions.
  // Sorted, unique; may be empty.
  std::vector<int> fixed;
  // The moveable handle vertices, of every group. Sorted, unique, not empty,
  // disjoint from `fixed`.
  std::vector<int> moveable;
  // Per entry of `moveable`: its handle group, 0 .. num_groups() - 1, every
  // group with at least one vertex. Each group follows its own transform
  // (HandleTransforms). Empty: one group (0) holds every moveable vertex.
  std::vector<int> group;

  int num_groups() const;
  // The group of moveable[index].
  int group_of(int index) const { return group.empty() ? 0 : group[index]; }
  // The group of vertex v, or -1 when v is not moveable (a binary search).
  int GroupOfVertex(int v) const;
};

// Checks a layout against a mesh with `num_vertices` vertices: ids in range,
// both lists sorted and unique, at least one moveable vertex, no vertex both
// fixed and moveable, `group` empty or one entry a moveable vertex with
// groups 0 .. G-1 each used (G at most kMaxHandleGroups). On failure *error
// names the first offending vertex or group.
bool ValidateHandles(const HandleLayout& layout, int num_vertices, std::string* error);

// Where the handle groups go in a frame: one transform deformed_from_rest a
// group (a group's vertex v goes to transform * rest(v)), or one transform
// that every group follows. One Eigen::Affine3d converts to the latter, so a
// caller with one handle writes Drag(T).
class HandleTransforms {
 public:
  HandleTransforms() = default;  // the identity, for every group
  HandleTransforms(const Eigen::Affine3d& every_group)  // NOLINT: implicit by design
      : transforms_(1, every_group) {}
  explicit HandleTransforms(std::vector<Eigen::Affine3d> per_group)
      : transforms_(std::move(per_group)) {}

  // Group g's transform (the one transform when one is given for all).
  const Eigen::Affine3d& operator[](int g) const {
    return transforms_.size() == 1 ? transforms_[0] : transforms_[g];
  }
  // 1 when one transform moves every group.
  int size() const { return static_cast<int>(transforms_.size()); }
  const std::vector<Eigen::Affine3d>& transforms() const { return transforms_; }

  // Every group at rest (each transform exactly the identity).
  bool IsIdentity() const;
  // Whether every entry is finite; else *error says which group is not.
  bool CheckFinite(std::string* error) const;
  // One transform, or one a group of `layout`; else *error says how many
  // were given and expected.
  bool Fits(const HandleLayout& layout, std::string* error) const;
  // The same for a layout of `num_groups` groups.
  bool Fits(int num_groups, std::string* error) const;

 private:
  std::vector<Eigen::Affine3d> transforms_ = {Eigen::Affine3d::Identity()};
};

// Per-vertex targets as handle transforms: `targets` (3 by #moveable, in the
// order of layout.moveable) says where each moveable vertex goes; each
// group's transform is the rigid motion that fits its vertices' targets best
// (least squares), or, when that misses some target by more than `tolerance`,
// the best affine map. False with a message naming the group when the
// affine map misses too (the targets do not move the group as one piece:
// give the independently moving parts their own groups), or when the
// targets are not finite or not one a moveable vertex.
bool HandleTransformsFromTargets(const Eigen::Matrix3Xd& rest, const HandleLayout& layout,
                                 const Eigen::Matrix3Xd& targets, double tolerance,
                                 HandleTransforms* transforms, std::string* error);

// A valid layout's moveable and fixed vertices as one sorted list, and per
// entry its handle group (moveable) or -1 (fixed, held at rest): the
// constrained vertices of the local/global ARAP solvers.
void ConstrainedVertices(const HandleLayout& layout, std::vector<int>* constrained,
                         std::vector<int>* handle_group);

// Where ConstrainedVertices' vertices go in a frame (3 by #constrained):
// handles[g] * rest for those of group g, rest for the fixed ones; `rest`
// holds every vertex's rest position.
Eigen::Matrix3Xd ConstrainedTargets(const Eigen::Matrix3Xd& rest,
                                    const std::vector<int>& constrained,
                                    const std::vector<int>& handle_group,
                                    const HandleTransforms& handles);

// The same with the moveable vertices' targets given one by one
// (`moveable_targets`: 3 by #moveable, in the layout's moveable order, which
// is the order of the constrained entries with a group).
Eigen::Matrix3Xd ConstrainedTargets(const Eigen::Matrix3Xd& rest,
                                    const std::vector<int>& constrained,
                                    const std::vector<int>& handle_group,
                                    const Eigen::Matrix3Xd& moveable_targets);

// Reads a .sel file (one handle group) for a mesh with `num_vertices` vertices: status 0 goes to
// `fixed`, 2 to `moveable`, 1 (free to deform) to neither. Errors (file, line
// and problem in *error): unreadable file, a line that is not one integer,
// a status outside 0..2, more or fewer statuses than vertices, no handle (2).
bool ReadSel(const std::string& path, int num_vertices, HandleLayout* layout, std::string* error);
// The same without a mesh: the vertex count is the file's (one status a
// vertex), returned in *num_vertices; a count is not checked.
bool ReadSel(const std::string& path, HandleLayout* layout, int* num_vertices,
             std::string* error);

// Writes `layout` as a .sel file for a mesh with `num_vertices` vertices,
// atomically. Fails (no file written) when the layout does not validate or
// has more than one handle group, which the format cannot hold.
bool WriteSel(const std::string& path, const HandleLayout& layout, int num_vertices,
              std::string* error);

// Reads a .def file: 16 finite numbers, row by row, whose last row is
// 0 0 0 1 within 1e-9.
bool ReadDef(const std::string& path, Eigen::Affine3d* deformed_from_rest, std::string* error);

// Writes a .def file atomically, with full double precision.
bool WriteDef(const std::string& path, const Eigen::Affine3d& deformed_from_rest,
              std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_HANDLES_H_
