#include "msdeform/core/text_lines.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

namespace msdeform {
namespace {

// ParseDouble and ParseFloat take a token exactly as strtod and strtof do
// (the fast path is std::from_chars): the same acceptance and the same bits.
TEST(TextLinesTest, NumbersParseAsStrtodParsesThem) {
  for (const std::string token :
       {"1", "-0", "0.1", ".5", "5.", "+1.5", "1e-400", "1e999", "-1e999", "0x1p3", "nan", "inf",
        "-inf", "Infinity", "3.4028235677973366e38", "1.17549435e-38", "123456789.123456789",
        "1.5x", "", "+", "-", "e5", "1e", "--1", "+-1", "0x", "1,5"}) {
    char* end = nullptr;
    const double expected = std::strtod(token.c_str(), &end);
    const bool expected_ok = !token.empty() && end == token.c_str() + token.size();
    double value = 0.0;
    EXPECT_EQ(ParseDouble(token, &value), expected_ok) << token;
    if (expected_ok && !std::isnan(expected)) {
      EXPECT_EQ(value, expected) << token;
    }
    if (expected_ok && std::isnan(expected)) {
      EXPECT_TRUE(std::isnan(value)) << token;
    }

    const float expected_float = std::strtof(token.c_str(), &end);
    float float_value = 0.0f;
    EXPECT_EQ(ParseFloat(token, &float_value), expected_ok) << token;
    if (expected_ok && !std::isnan(expected_float)) {
      EXPECT_EQ(float_value, expected_float) << token;
    }
  }
}

// Texts with blank lines, comment lines, indented lines, CR LF ends, a '#'
// right after a token and no final line end.
std::vector<std::string> MixedTexts() {
  return {"",
          "\n",
          "OFF\n3 1 0\n0 0 0\n",
          "a b\n\n  \n# note\n  # indented note\nv 1 2 3\n\tv 4 5 6 # tail\nlast",
          "x\r\n\r\ny z\r\n#\r\n \r\nend\r\n",
          "v#comment\n#v\n v\nvv 1\n\x0b\x0c\n",
          "\n\n\n1\n\n"};
}

// CountLines, ForEachLine and FirstToken see the lines TextLines walks.
TEST(TextLinesTest, CountsAgreeWithTheWalk) {
  for (const std::string& text : MixedTexts()) {
    TextLines lines(text);
    int walked = 0;
    long long with_content = 0;
    std::vector<std::string_view> first_tokens;
    while (lines.Next()) {
      ++walked;
      with_content += !lines.tokens().empty();
      first_tokens.push_back(lines.tokens().empty() ? std::string_view() : lines.tokens()[0]);
    }
    const LineCount count = CountLines(text);
    EXPECT_EQ(count.lines, walked) << text;
    EXPECT_EQ(count.with_content, with_content) << text;
    std::vector<std::string_view> firsts;
    EXPECT_EQ(ForEachLine(text, [&firsts](std::string_view line) {
                firsts.push_back(FirstToken(line));
              }),
              walked);
    EXPECT_EQ(firsts, first_tokens) << text;
  }
}

// LineChunks: pieces of at least the asked size that end after a line end
// (the last at the end), covering the range; a piece's lines numbered from
// the lines before it are the whole text's.
TEST(TextLinesTest, LineChunksEndAtLineEnds) {
  const std::string text = MixedTexts()[3] + "\n" + MixedTexts()[4] + "\n" + MixedTexts()[5];
  for (size_t chunk : {1, 2, 5, 16, 1000}) {
    const std::vector<size_t> bounds = LineChunks(text, 2, text.size(), chunk);
    ASSERT_GE(bounds.size(), 2u);
    EXPECT_EQ(bounds.front(), 2u);
    EXPECT_EQ(bounds.back(), text.size());
    TextLines whole(std::string_view(text).substr(2));
    int lines_before = 0;
    for (size_t c = 0; c + 1 < bounds.size(); ++c) {
      ASSERT_LT(bounds[c], bounds[c + 1]);
      if (c + 2 < bounds.size()) {
        EXPECT_EQ(text[bounds[c + 1] - 1], '\n');
        EXPECT_GE(bounds[c + 1] - bounds[c], chunk);
      }
      const std::string_view piece =
          std::string_view(text).substr(bounds[c], bounds[c + 1] - bounds[c]);
      TextLines lines(piece, lines_before);
      while (lines.Next()) {
        ASSERT_TRUE(whole.Next());
        EXPECT_EQ(lines.line_number(), whole.line_number());
        EXPECT_EQ(lines.line(), whole.line());
      }
      lines_before += CountLines(piece).lines;
    }
    EXPECT_FALSE(whole.Next());
  }
}

}  // namespace
}  // namespace msdeform
