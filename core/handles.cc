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

void ConstrainedVertices(const HandleLayout& layout, std::vector<int>* constrained,
                         std::vector<char>* follows_handle) {
  constrained->clear();
  follows_handle->clear();
  // Merge the two sorted, disjoint lists.
  size_t f = 0, m = 0;
  while (f < layout.fixed.size() || m < layout.moveable.size()) {
    const bool take_moveable =
        f == layout.fixed.size() ||
        (m < layout.moveable.size() && layout.moveable[m] < layout.fixed[f]);
    constrained->push_back(take_moveable ? layout.moveable[m++] : layout.fixed[f++]);
    follows_handle->push_back(take_moveable ? 1 : 0);
  }
}

Eigen::Matrix3Xd ConstrainedTargets(const Eigen::Matrix3Xd& rest,
                                    const std::vector<int>& constrained,
                                    const std::vector<char>& follows_handle,
                                    const Eigen::Affine3d& deformed_from_rest) {
  Eigen::Matrix3Xd targets(3, constrained.size());
  for (size_t j = 0; j < constrained.size(); ++j) {
    const Eigen::Vector3d at_rest = rest.col(constrained[j]);
    targets.col(j) =
        follows_handle[j] ? Eigen::Vector3d(deformed_from_rest * at_rest) : at_rest;
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
