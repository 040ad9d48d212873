#include "msdeform/core/handles.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <limits>
#include <sstream>

#include <Eigen/QR>
#include <Eigen/SVD>

#include "msdeform/core/atomic_file.h"

namespace msdeform {
namespace {

bool Fail(const std::string& path, const std::string& problem, std::string* error) {
  *error = path + ": " + problem;
  return false;
}

std::string Quote(const std::string& token) {
  constexpr size_t kMax = 24;
  return "'" + (token.size() <= kMax ? token : token.substr(0, kMax) + "...") + "'";
}

// Splits a line into whitespace-separated tokens; strips a trailing '\r'.
std::vector<std::string> Tokens(const std::string& line) {
  std::istringstream stream(line);
  std::vector<std::string> tokens;
  std::string token;
  while (stream >> token) tokens.push_back(token);
  return tokens;
}

bool IsComment(const std::string& line) {
  const size_t first = line.find_first_not_of(" \t\r");
  return first != std::string::npos && line[first] == '#';
}

bool OpenForReading(const std::string& path, std::ifstream* in, std::string* error) {
  in->open(path);
  if (!*in) return Fail(path, "cannot open for reading (missing or unreadable file)", error);
  return true;
}

// Checks one id list: sorted, unique, in range. `what` names the list.
bool CheckIds(const std::vector<int>& ids, int num_vertices, const char* what, std::string* error) {
  std::ostringstream message;
  for (size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] < 0 || ids[i] >= num_vertices) {
      message << what << " vertex " << ids[i] << " is outside 0.." << num_vertices - 1;
      *error = message.str();
      return false;
    }
    if (i > 0 && ids[i] <= ids[i - 1]) {
      message << what << " vertex ids must be sorted and unique; " << ids[i] << " follows "
              << ids[i - 1];
      *error = message.str();
      return false;
    }
  }
  return true;
}

}  // namespace

int HandleLayout::num_groups() const {
  return group.empty() ? 1 : 1 + *std::max_element(group.begin(), group.end());
}

int HandleLayout::GroupOfVertex(int v) const {
  const auto it = std::lower_bound(moveable.begin(), moveable.end(), v);
  if (it == moveable.end() || *it != v) return -1;
  return group_of(static_cast<int>(it - moveable.begin()));
}

bool HandleTransforms::IsIdentity() const {
  for (const Eigen::Affine3d& transform : transforms_) {
    if (!transform.matrix().isIdentity(0.0)) return false;
  }
  return true;
}

bool HandleTransforms::CheckFinite(std::string* error) const {
  for (size_t g = 0; g < transforms_.size(); ++g) {
    if (!transforms_[g].matrix().allFinite()) {
      *error = transforms_.size() == 1
                   ? std::string("the handle transform is not finite")
                   : "the transform of handle group " + std::to_string(g) + " is not finite";
      return false;
    }
  }
  return true;
}

bool HandleTransforms::Fits(const HandleLayout& layout, std::string* error) const {
  return Fits(layout.num_groups(), error);
}

bool HandleTransforms::Fits(int num_groups, std::string* error) const {
  if (size() == 1 || size() == num_groups) return true;
  *error = std::to_string(size()) + " handle transforms for a layout of " +
           std::to_string(num_groups) + " handle groups (give one, or one a group)";
  return false;
}

namespace {

// The rigid motion x -> R (x - c) + d that maps `from` (3 by n, centroid c)
// onto `to` (centroid d) best in least squares (Kabsch: R from the SVD of the
// cross-covariance, its determinant kept positive). Points on a line leave
// the spin about it free: then R is the least rotation that turns the line
// onto its image (the identity for one point or no turn).
Eigen::Affine3d BestRigidMotion(const Eigen::Matrix3Xd& from, const Eigen::Matrix3Xd& to) {
  const Eigen::Vector3d c = from.rowwise().mean(), d = to.rowwise().mean();
  const Eigen::Matrix3d covariance = (to.colwise() - d) * (from.colwise() - c).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance,
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d& sigma = svd.singularValues();
  Eigen::Affine3d motion = Eigen::Affine3d::Identity();
  if (!(sigma[1] > 1e-12 * sigma[0])) {
    if (sigma[0] > 0.0) {
      motion.linear() =
          Eigen::Quaterniond::FromTwoVectors(svd.matrixV().col(0), svd.matrixU().col(0))
              .toRotationMatrix();
    }
  } else {
    Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
    if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) flip(2, 2) = -1.0;
    motion.linear() = svd.matrixU() * flip * svd.matrixV().transpose();
  }
  motion.translation() = d - motion.linear() * c;
  return motion;
}

// The affine map x -> A (x - c) + d that maps `from` onto `to` best in least
// squares, as `rigid`'s linear part R plus the least correction: A = R + D,
// D by a complete orthogonal decomposition (its minimum-norm solution), so
// that where the points span less than 3 dimensions A acts as R does across
// them (not flattening a lattice cell driven by it).
Eigen::Affine3d BestAffineMap(const Eigen::Matrix3Xd& from, const Eigen::Matrix3Xd& to,
                              const Eigen::Affine3d& rigid) {
  const Eigen::Vector3d c = from.rowwise().mean(), d = to.rowwise().mean();
  const Eigen::Matrix3Xd centred = from.colwise() - c;
  const Eigen::MatrixXd x = centred.transpose();  // n by 3
  const Eigen::MatrixXd y =
      ((to.colwise() - d) - rigid.linear() * centred).transpose();  // what R leaves
  const Eigen::Matrix3d a =
      rigid.linear() + Eigen::Matrix3d(x.completeOrthogonalDecomposition().solve(y).transpose());
  Eigen::Affine3d map = Eigen::Affine3d::Identity();
  map.linear() = a;
  map.translation() = d - a * c;
  return map;
}

double LargestMiss(const Eigen::Affine3d& map, const Eigen::Matrix3Xd& from,
                   const Eigen::Matrix3Xd& to) {
  double miss = 0.0;
  for (Eigen::Index i = 0; i < from.cols(); ++i) {
    miss = std::max(miss, (map * Eigen::Vector3d(from.col(i)) - to.col(i)).norm());
  }
  return miss;
}

}  // namespace

bool HandleTransformsFromTargets(const Eigen::Matrix3Xd& rest, const HandleLayout& layout,
                                 const Eigen::Matrix3Xd& targets, double tolerance,
                                 HandleTransforms* transforms, std::string* error) {
  if (targets.cols() != static_cast<Eigen::Index>(layout.moveable.size())) {
    *error = std::to_string(targets.cols()) + " targets for " +
             std::to_string(layout.moveable.size()) + " moveable vertices";
    return false;
  }
  if (!targets.allFinite()) {
    *error = "the targets are not finite";
    return false;
  }
  const int num_groups = layout.num_groups();
  std::vector<std::vector<int>> members(num_groups);  // entries of layout.moveable
  for (int i = 0; i < static_cast<int>(layout.moveable.size()); ++i) {
    members[layout.group_of(i)].push_back(i);
  }
  std::vector<Eigen::Affine3d> fitted;
  for (int g = 0; g < num_groups; ++g) {
    Eigen::Matrix3Xd from(3, members[g].size()), to(3, members[g].size());
    for (size_t k = 0; k < members[g].size(); ++k) {
      from.col(k) = rest.col(layout.moveable[members[g][k]]);
      to.col(k) = targets.col(members[g][k]);
    }
    Eigen::Affine3d map = BestRigidMotion(from, to);
    if (!(LargestMiss(map, from, to) <= tolerance)) map = BestAffineMap(from, to, map);
    const double miss = LargestMiss(map, from, to);
    if (!(miss <= tolerance)) {
      std::ostringstream message;
      message << "the targets of handle group " << g << " are no affine map of its rest "
              << "positions (the best misses by " << miss << ", tolerance " << tolerance
              << "): give the parts that move independently their own handle groups";
      *error = message.str();
      return false;
    }
    fitted.push_back(map);
  }
  *transforms = num_groups == 1 ? HandleTransforms(fitted[0]) : HandleTransforms(fitted);
  return true;
}

void ConstrainedVertices(const HandleLayout& layout, std::vector<int>* constrained,
                         std::vector<int>* handle_group) {
  constrained->clear();
  handle_group->clear();
  // Merge the two sorted, disjoint lists.
  size_t f = 0, m = 0;
  while (f < layout.fixed.size() || m < layout.moveable.size()) {
    const bool take_moveable =
        f == layout.fixed.size() ||
        (m < layout.moveable.size() && layout.moveable[m] < layout.fixed[f]);
    handle_group->push_back(take_moveable ? layout.group_of(static_cast<int>(m)) : -1);
    constrained->push_back(take_moveable ? layout.moveable[m++] : layout.fixed[f++]);
  }
}

Eigen::Matrix3Xd ConstrainedTargets(const Eigen::Matrix3Xd& rest,
                                    const std::vector<int>& constrained,
                                    const std::vector<int>& handle_group,
                                    const HandleTransforms& handles) {
  Eigen::Matrix3Xd targets(3, constrained.size());
  for (size_t j = 0; j < constrained.size(); ++j) {
    const Eigen::Vector3d at_rest = rest.col(constrained[j]);
    targets.col(j) =
        handle_group[j] >= 0 ? Eigen::Vector3d(handles[handle_group[j]] * at_rest) : at_rest;
  }
  return targets;
}

Eigen::Matrix3Xd ConstrainedTargets(const Eigen::Matrix3Xd& rest,
                                    const std::vector<int>& constrained,
                                    const std::vector<int>& handle_group,
                                    const Eigen::Matrix3Xd& moveable_targets) {
  Eigen::Matrix3Xd targets(3, constrained.size());
  Eigen::Index next = 0;  // the next moveable vertex's target
  for (size_t j = 0; j < constrained.size(); ++j) {
    targets.col(j) =
        handle_group[j] >= 0 ? moveable_targets.col(next++) : rest.col(constrained[j]);
  }
  return targets;
}

bool ValidateHandles(const HandleLayout& layout, int num_vertices, std::string* error) {
  if (!CheckIds(layout.fixed, num_vertices, "fixed", error)) return false;
  if (!CheckIds(layout.moveable, num_vertices, "moveable", error)) return false;
  if (layout.moveable.empty()) {
    *error = "the moveable handle has no vertex";
    return false;
  }
  std::vector<int> both;
  std::set_intersection(layout.fixed.begin(), layout.fixed.end(), layout.moveable.begin(),
                        layout.moveable.end(), std::back_inserter(both));
  if (!both.empty()) {
    *error = "vertex " + std::to_string(both.front()) + " is both fixed and moveable (" +
             std::to_string(both.size()) + " such vertices)";
    return false;
  }
  if (layout.group.empty()) return true;
  if (layout.group.size() != layout.moveable.size()) {
    *error = "the handle groups list " + std::to_string(layout.group.size()) +
             " entries for " + std::to_string(layout.moveable.size()) + " moveable vertices";
    return false;
  }
  std::vector<int> count;
  for (size_t i = 0; i < layout.group.size(); ++i) {
    const int g = layout.group[i];
    if (g < 0 || g >= kMaxHandleGroups) {
      *error = "moveable vertex " + std::to_string(layout.moveable[i]) + " has handle group " +
               std::to_string(g) + ", outside 0.." + std::to_string(kMaxHandleGroups - 1);
      return false;
    }
    if (g >= static_cast<int>(count.size())) count.resize(g + 1, 0);
    ++count[g];
  }
  for (size_t g = 0; g < count.size(); ++g) {
    if (count[g] == 0) {
      *error = "handle group " + std::to_string(g) + " has no vertex (groups are 0.." +
               std::to_string(count.size() - 1) + ", each used)";
      return false;
    }
  }
  return true;
}

namespace {

// ReadSel for `num_vertices` statuses, or (-1) as many as the file has;
// *count is the number read.
bool ReadSelStatuses(const std::string& path, int num_vertices, HandleLayout* layout, int* count,
                     std::string* error) {
  std::ifstream in;
  if (!OpenForReading(path, &in, error)) return false;
  HandleLayout result;
  std::string line;
  int line_number = 0;
  int vertex = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (IsComment(line)) continue;
    const std::vector<std::string> tokens = Tokens(line);
    if (tokens.empty()) continue;
    const std::string at = "line " + std::to_string(line_number) + ": ";
    if (tokens.size() != 1) {
      return Fail(path,
                  at + "expected one status (0, 1 or 2) per line, found " +
                      std::to_string(tokens.size()) + " values",
                  error);
    }
    int status = -1;
    const std::string& token = tokens[0];
    const auto parsed = std::from_chars(token.data(), token.data() + token.size(), status);
    if (parsed.ec != std::errc() || parsed.ptr != token.data() + token.size()) {
      return Fail(path, at + Quote(token) + " is not a vertex status (0, 1 or 2)", error);
    }
    if (status < 0 || status > 2) {
      return Fail(path,
                  at + "status " + token + " for vertex " + std::to_string(vertex) +
                      " is outside 0 (fixed), 1 (deformable), 2 (handle)",
                  error);
    }
    if (num_vertices >= 0 && vertex >= num_vertices) {
      return Fail(path,
                  at + "more statuses than the mesh's " + std::to_string(num_vertices) +
                      " vertices (is this .sel for another mesh?)",
                  error);
    }
    if (status == 0) result.fixed.push_back(vertex);
    if (status == 2) result.moveable.push_back(vertex);
    ++vertex;
  }
  if (in.bad()) return Fail(path, "read error", error);
  if (num_vertices >= 0 && vertex != num_vertices) {
    return Fail(path,
                "has " + std::to_string(vertex) + " statuses but the mesh has " +
                    std::to_string(num_vertices) + " vertices (is this .sel for another mesh?)",
                error);
  }
  if (result.moveable.empty()) {
    return Fail(path, "no handle vertex (status 2); nothing would move", error);
  }
  *layout = std::move(result);
  *count = vertex;
  return true;
}

}  // namespace

bool ReadSel(const std::string& path, int num_vertices, HandleLayout* layout, std::string* error) {
  int count = 0;
  return ReadSelStatuses(path, num_vertices, layout, &count, error);
}

bool ReadSel(const std::string& path, HandleLayout* layout, int* num_vertices,
             std::string* error) {
  return ReadSelStatuses(path, -1, layout, num_vertices, error);
}

bool WriteSel(const std::string& path, const HandleLayout& layout, int num_vertices,
              std::string* error) {
  std::string problem;
  if (!ValidateHandles(layout, num_vertices, &problem)) {
    return Fail(path, "refusing to write an invalid layout: " + problem, error);
  }
  if (layout.num_groups() > 1) {
    return Fail(path,
                "a .sel file holds one handle group; this layout has " +
                    std::to_string(layout.num_groups()) + " (save a scenario instead)",
                error);
  }
  std::vector<char> status(num_vertices, '1');
  for (int v : layout.fixed) status[v] = '0';
  for (int v : layout.moveable) status[v] = '2';
  return WriteFileAtomically(
      path,
      [&](std::ostream& out, std::string*) {
        out << "# per vertex status: 0=fixed, 1=deformable-region, 2=handle\n"
            << "# " << num_vertices << " vertices\n";
        for (char s : status) out << s << '\n';
        return static_cast<bool>(out);
      },
      error);
}

bool ReadDef(const std::string& path, Eigen::Affine3d* deformed_from_rest, std::string* error) {
  std::ifstream in;
  if (!OpenForReading(path, &in, error)) return false;
  std::vector<double> values;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (IsComment(line)) continue;
    for (const std::string& token : Tokens(line)) {
      const std::string at = "line " + std::to_string(line_number) + ": ";
      char* end = nullptr;
      const double value = std::strtod(token.c_str(), &end);
      if (end != token.c_str() + token.size()) {
        return Fail(path, at + Quote(token) + " is not a number", error);
      }
      if (!std::isfinite(value)) {
        return Fail(path, at + "matrix entry " + Quote(token) + " is not finite", error);
      }
      if (values.size() == 16) {
        return Fail(path, at + "more than 16 numbers; expected a 4x4 matrix", error);
      }
      values.push_back(value);
    }
  }
  if (in.bad()) return Fail(path, "read error", error);
  if (values.size() != 16) {
    return Fail(
        path,
        "has " + std::to_string(values.size()) + " numbers; expected 16 (a 4x4 matrix, row by row)",
        error);
  }
  // Row-major in the file.
  const Eigen::Matrix4d matrix =
      Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(values.data());
  const Eigen::RowVector4d expected(0.0, 0.0, 0.0, 1.0);
  if ((matrix.row(3) - expected).cwiseAbs().maxCoeff() > 1e-9) {
    std::ostringstream message;
    message << "last row is " << matrix.row(3) << "; expected 0 0 0 1 (an affine transform)";
    return Fail(path, message.str(), error);
  }
  deformed_from_rest->matrix() = matrix;
  deformed_from_rest->matrix().row(3) = expected;
  return true;
}

bool WriteDef(const std::string& path, const Eigen::Affine3d& deformed_from_rest,
              std::string* error) {
  if (!deformed_from_rest.matrix().allFinite()) {
    return Fail(path, "refusing to write a transform with non-finite entries", error);
  }
  return WriteFileAtomically(
      path,
      [&](std::ostream& out, std::string*) {
        out << "# 4x4 handle transformation matrix\n"
            << std::setprecision(std::numeric_limits<double>::max_digits10);
        for (int r = 0; r < 4; ++r) {
          for (int c = 0; c < 4; ++c) out << (c ? " " : "") << deformed_from_rest.matrix()(r, c);
          out << '\n';
        }
        return static_cast<bool>(out);
      },
      error);
}

}  // namespace msdeform
