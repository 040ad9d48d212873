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
  // A piece of a longer text that starts after its line `lines_before`: the
  // line numbers (and so the messages) are the longer text's.
  TextLines(std::string_view text, int lines_before)
      : text_(text), line_number_(lines_before) {}

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

// The first token of `line` as TextLines splits it ("" for a blank or
// comment-only line): what NextWithContent and the readers' line kinds look
// at, without splitting the whole line.
std::string_view FirstToken(std::string_view line);

// Splits text[begin, end) into pieces for parsing apart: each piece ends
// right after the first '\n' at or beyond `chunk_bytes` bytes from its start
// (the last one at `end`), so every line lies in one piece. Returns the
// pieces' boundaries, `begin` first and `end` last. Depends only on the text
// and `chunk_bytes`.
std::vector<size_t> LineChunks(std::string_view text, size_t begin, size_t end,
                               size_t chunk_bytes);

// The lines of a text as TextLines walks them, and those with a token (as
// NextWithContent finds them), counted without splitting the lines into
// tokens (ForEachLine and FirstToken): about a tenth of the time of parsing
// the lines (10 ms of 83 for a 42 MB OFF).
struct LineCount {
  int lines = 0;
  long long with_content = 0;
};
LineCount CountLines(std::string_view text);

// Calls visit(line) for each line of `text`, a line as TextLines::line()
// would give it but for a '\r' kept at its end; returns the number of lines.
template <typename Visit>
int ForEachLine(std::string_view text, Visit visit) {
  int count = 0;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    visit(text.substr(start, end - start));
    ++count;
    start = end + 1;
  }
  return count;
}

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
// and puts them in xyz[0..2]. A decimal beyond the double range is refused
// as not finite.
bool ReadVertexCoordinates(const TextLines& lines, size_t first, long long vertex, double xyz[3],
                           std::string* problem);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_TEXT_LINES_H_
