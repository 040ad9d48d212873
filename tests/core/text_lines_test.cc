#include "msdeform/core/text_lines.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string>

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
    if (expected_ok && !std::isnan(expected)) EXPECT_EQ(value, expected) << token;
    if (expected_ok && std::isnan(expected)) EXPECT_TRUE(std::isnan(value)) << token;

    const float expected_float = std::strtof(token.c_str(), &end);
    float float_value = 0.0f;
    EXPECT_EQ(ParseFloat(token, &float_value), expected_ok) << token;
    if (expected_ok && !std::isnan(expected_float)) EXPECT_EQ(float_value, expected_float) << token;
  }
}

}  // namespace
}  // namespace msdeform
