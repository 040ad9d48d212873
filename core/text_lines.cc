// The line walker and token parsing shared by the text mesh readers.

#include "msdeform/core/text_lines.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <system_error>

namespace msdeform {
namespace {

// std::isspace in the "C" locale (space, \t, \n, \v, \f, \r), inline: the
// library call per character was a third of reading a text mesh, and a mesh
// file's separators do not depend on the user's locale.
inline bool IsSpace(unsigned char c) { return c == ' ' || (c >= '\t' && c <= '\r'); }

// Splits `line` into whitespace-separated tokens, dropping a '#' comment;
// sets *had_comment when there was one.
void Tokenize(std::string_view line, TextLines::Tokens* tokens, bool* had_comment) {
  tokens->clear();
  *had_comment = false;
  const size_t hash = line.find('#');
  if (hash != std::string_view::npos) {
    line = line.substr(0, hash);
    *had_comment = true;
  }
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && IsSpace(static_cast<unsigned char>(line[i]))) ++i;
    size_t j = i;
    while (j < line.size() && !IsSpace(static_cast<unsigned char>(line[j]))) ++j;
    if (j > i) tokens->push_back(line.substr(i, j - i));
    i = j;
  }
}

// The whole token as a number, with strtod's (strtof's) syntax and value:
// std::from_chars first (no copy, no locale; correctly rounded, as glibc's
// strtod is), and strtod on a copy for what from_chars does not take (a
// leading '+', hexadecimal, a value out of range, which strtod rounds to
// infinity or zero).
template <typename Real>
bool ParseReal(std::string_view token, Real (*parse)(const char*, char**), Real* value) {
  if (token.empty()) return false;
  const char* end = token.data() + token.size();
  const std::from_chars_result fast = std::from_chars(token.data(), end, *value);
  if (fast.ec == std::errc() && fast.ptr == end) return true;
  const std::string copy(token);
  char* parsed_end = nullptr;
  *value = parse(copy.c_str(), &parsed_end);
  return parsed_end == copy.c_str() + copy.size();
}

}  // namespace

bool TextLines::Next() {
  if (next_ >= text_.size()) return false;
  size_t end = text_.find('\n', next_);
  if (end == std::string_view::npos) end = text_.size();
  line_ = text_.substr(next_, end - next_);
  if (!line_.empty() && line_.back() == '\r') line_.remove_suffix(1);
  next_ = end + 1;
  ++line_number_;
  Tokenize(line_, &tokens_, &had_comment_);
  return true;
}

bool TextLines::NextWithContent() {
  while (Next()) {
    if (!tokens_.empty()) return true;
  }
  return false;
}

std::string_view FirstToken(std::string_view line) {
  size_t i = 0;
  while (i < line.size() && IsSpace(static_cast<unsigned char>(line[i]))) ++i;
  size_t j = i;
  while (j < line.size() && line[j] != '#' && !IsSpace(static_cast<unsigned char>(line[j]))) {
    ++j;
  }
  return line.substr(i, j - i);
}

LineCount CountLines(std::string_view text) {
  LineCount count;
  count.lines = ForEachLine(text, [&count](std::string_view line) {
    count.with_content += !FirstToken(line).empty();
  });
  return count;
}

std::vector<size_t> LineChunks(std::string_view text, size_t begin, size_t end,
                               size_t chunk_bytes) {
  std::vector<size_t> bounds = {begin};
  while (end - bounds.back() > chunk_bytes) {
    const size_t line_end = text.substr(0, end).find('\n', bounds.back() + chunk_bytes - 1);
    if (line_end == std::string_view::npos || line_end + 1 >= end) break;
    bounds.push_back(line_end + 1);
  }
  bounds.push_back(end);
  return bounds;
}

std::string Quote(std::string_view token) {
  constexpr size_t kMax = 24;
  if (token.size() <= kMax) return "'" + std::string(token) + "'";
  return "'" + std::string(token.substr(0, kMax)) + "...'";
}

bool ParseInt(std::string_view token, long long* value) {
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, *value);
  return result.ec == std::errc() && result.ptr == end;
}

bool ParseDouble(std::string_view token, double* value) {
  return ParseReal<double>(token, std::strtod, value);
}

bool ParseFloat(std::string_view token, float* value) {
  return ParseReal<float>(token, std::strtof, value);
}

bool ReadVertexCoordinates(const TextLines& lines, size_t first, long long vertex, double xyz[3],
                           std::string* problem) {
  const TextLines::Tokens& tokens = lines.tokens();
  if (tokens.size() < first + 3) {
    return lines.Fail(problem, "vertex ", vertex, " has fewer than 3 coordinates");
  }
  for (size_t k = first; k < first + 3; ++k) {
    double value = 0.0;
    if (!ParseDouble(tokens[k], &value)) {
      return lines.Fail(problem, "vertex ", vertex, " coordinate ", Quote(tokens[k]),
                        " is not a number");
    }
    if (!std::isfinite(value)) {
      return lines.Fail(problem, "vertex ", vertex, " coordinate ", Quote(tokens[k]),
                        " is not finite");
    }
    xyz[k - first] = value;
  }
  return true;
}

}  // namespace msdeform
