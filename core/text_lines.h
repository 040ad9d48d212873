// The one line walker of the text mesh readers (core/mesh_io_off.cc,
// mesh_io_obj.cc, mesh_io_ply.cc, mesh_io_stl.cc): lines numbered from 1,
// split into tokens, with the number parsing and the "line N: ..." messages
// the readers share. Internal to core; not part of the public API.

#ifndef MSDEFORM_CORE_TEXT_LINES_H_
#define MSDEFORM_CORE_TEXT_LINES_H_

#include <cstddef>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace msdeform {

// Puts the parts, streamed one after another, in *problem and returns false,
// so that a check can end with `return SetProblem(problem, ...)`.
template <typename... Parts>
bool SetProblem(std::string* problem, const Parts&... parts) {
  std::ostringstream message;
  (message << ... << parts);
  *problem = message.str();
  return false;
}

// Walks the lines of a text that must outlive it. A line ends at '\n' (a '\r'
// before it is dropped); the text's last line needs none. Each line is split
// into whitespace-separated tokens after dropping a '#' comment.
class TextLines {
 public:
  using Tokens = std::vector<std::string_view>;

  explicit TextLines(std::string_view text) : text_(text) {}

  // Moves to the next line; false (and nothing changed) at the end.
  bool Next();
  // Moves to the next line with a token, skipping blank and comment-only
  // lines; false at the end.
  bool NextWithContent();

  // The current line, without its '\n' or '\r'.
  std::string_view line() const { return line_; }
  // 1 for the first line; 0 before Next.
  int line_number() const { return line_number_; }
  // The current line's tokens, without the comment.
  const Tokens& tokens() const { return tokens_; }
  // True when the current line holds a '#'.
  bool had_comment() const { return had_comment_; }
  // Where the text after the current line starts (the text's size when the
  // line has no '\n'): the start of the binary data after a text header.
  size_t next_offset() const { return next_ < text_.size() ? next_ : text_.size(); }

  // SetProblem with "line <current line number>: " in front.
  template <typename... Parts>
  bool Fail(std::string* problem, const Parts&... parts) const {
    return SetProblem(problem, "line ", line_number_, ": ", parts...);
  }

 private:
  std::string_view text_;
  size_t next_ = 0;  // start of the next line
  int line_number_ = 0;
  std::string_view line_;
  Tokens tokens_;
  bool had_comment_ = false;
};

// The token in single quotes for a message, cut after 24 characters.
std::string Quote(std::string_view token);

// Each true when the whole token is one number. ParseDouble and ParseFloat
// take strtod's and strtof's syntax and value (correctly rounded to the
// nearest double or float; beyond the range infinite, below it zero or
// subnormal), so "nan" and "inf" parse (and can then be refused as
// non-finite rather than as junk).
bool ParseInt(std::string_view token, long long* value);
bool ParseDouble(std::string_view token, double* value);
bool ParseFloat(std::string_view token, float* value);

// Checks that tokens first, first + 1 and first + 2 of the current line are
// finite doubles, the coordinates of vertex `vertex` of an OFF or OBJ text,
// and appends them to *xyz. A decimal beyond the double range is refused as
// not finite.
bool ReadVertexCoordinates(const TextLines& lines, size_t first, long long vertex,
                           std::vector<double>* xyz, std::string* problem);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_TEXT_LINES_H_
