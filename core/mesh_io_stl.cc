// The STL check. OpenMesh's STL reader merges corners at equal positions and
// skips, without a word, a facet two of whose corners merge; so the facets are
// walked here as it walks them, to count those for the notice and to predict
// what it hands over. (On the way this refuses what it would misread: it
// takes the three lines after any line holding "outer" as the corners,
// whatever they say, and keeps going with stale values.)

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

#include "msdeform/core/mesh_io_formats.h"
#include "msdeform/core/text_lines.h"

namespace msdeform {
namespace {

using StlCorner = std::array<float, 3>;
using StlFacet = std::array<StlCorner, 3>;

// OpenMesh's STL reader takes two corners for one vertex when every
// coordinate differs by at most FLT_MIN (its CmpVec).
bool SameStlCorner(const StlCorner& p, const StlCorner& q) {
  for (int k = 0; k < 3; ++k) {
    if (!(std::fabs(p[k] - q[k]) <= std::numeric_limits<float>::min())) return false;
  }
  return true;
}

bool IsCollapsedFacet(const StlFacet& corners) {
  return SameStlCorner(corners[0], corners[1]) || SameStlCorner(corners[1], corners[2]) ||
         SameStlCorner(corners[0], corners[2]);
}

// "vertex" in any case (OpenMesh does not look at the word at all).
bool IsStlVertexKeyword(std::string_view token) {
  constexpr std::string_view kVertex = "vertex";
  return token.size() == kVertex.size() &&
         std::equal(token.begin(), token.end(), kVertex.begin(), [](char a, char b) {
           return std::tolower(static_cast<unsigned char>(a)) == b;
         });
}

// Binary STL with `num_facets` facets: every corner coordinate finite.
bool CheckBinaryStl(std::string_view text, uint32_t num_facets, long long* num_collapsed,
                    std::string* problem) {
  for (uint32_t facet = 0; facet < num_facets; ++facet) {
    StlFacet corners;
    // After the facet's normal: three corners of three little-endian floats.
    std::memcpy(corners.data(), text.data() + 84 + 50ull * facet + 12, sizeof(corners));
    for (int c = 0; c < 3; ++c) {
      for (float coordinate : corners[c]) {
        if (!std::isfinite(coordinate)) {
          return SetProblem(problem, "binary facet ", facet, ": corner ", c,
                            " has a non-finite coordinate");
        }
      }
    }
    *num_collapsed += IsCollapsedFacet(corners);
  }
  return true;
}

// ASCII STL: the three lines after each line holding "outer" are "vertex x y
// z" with finite numbers (single precision, as OpenMesh reads them, so that
// equal positions here are equal there).
bool CheckAsciiStl(std::string_view text, long long* num_facets, long long* num_collapsed,
                   std::string* problem) {
  TextLines lines(text);
  while (lines.Next()) {
    if (lines.line().find("outer") == std::string_view::npos &&
        lines.line().find("OUTER") == std::string_view::npos) {
      continue;
    }
    const int outer_line = lines.line_number();
    StlFacet corners;
    for (int c = 0; c < 3; ++c) {
      if (!lines.Next()) {
        return SetProblem(problem, "truncated: the file ends in facet ", *num_facets, " (line ",
                          lines.line_number(), ")");
      }
      const TextLines::Tokens& tokens = lines.tokens();
      if (tokens.size() != 4 || !IsStlVertexKeyword(tokens[0])) {
        return lines.Fail(problem, "facet ", *num_facets, ": expected 'vertex x y z' (corner ", c,
                          " after 'outer' on line ", outer_line, ")");
      }
      for (int k = 0; k < 3; ++k) {
        if (!ParseFloat(tokens[1 + k], &corners[c][k]) || !std::isfinite(corners[c][k])) {
          return lines.Fail(problem, "facet ", *num_facets, ": ", Quote(tokens[1 + k]),
                            " is not a finite number");
        }
      }
    }
    ++*num_facets;
    *num_collapsed += IsCollapsedFacet(corners);
  }
  return true;
}

}  // namespace

bool CheckStl(std::string_view text, FormatCheck* check, std::string* problem) {
  long long num_facets = 0;
  long long num_collapsed = 0;
  // OpenMesh reads binary STL exactly when the file is as long as the facet
  // count after the 80-byte header says: 84 bytes and 50 per facet.
  uint32_t binary_count = 0;
  if (text.size() >= 84) std::memcpy(&binary_count, text.data() + 80, sizeof(binary_count));
  if (text.size() >= 84 && text.size() == 84 + 50ull * binary_count) {
    if (!CheckBinaryStl(text, binary_count, &num_collapsed, problem)) return false;
    num_facets = binary_count;
  } else if (!CheckAsciiStl(text, &num_facets, &num_collapsed, problem)) {
    return false;
  }
  if (num_facets > std::numeric_limits<int>::max()) return SetProblem(problem, "too many facets");
  check->num_faces = static_cast<int>(num_facets - num_collapsed);
  check->dropped_degenerate_faces = static_cast<int>(num_collapsed);
  return true;
}

}  // namespace msdeform
