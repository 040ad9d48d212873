// The generic options table (core/option_table.h): enum names, rows bound to
// fields, embedding under a prefix, describe, set and range errors.

#include "msdeform/core/option_table.h"

#include <cstdint>
#include <string>

#include <gtest/gtest.h>

namespace msdeform {
namespace {

enum class Colour { kRed, kGreen, kBlue };

const EnumNames<Colour>& ColourNames() {
  static const EnumNames<Colour> names = {
      {Colour::kRed, "red"}, {Colour::kGreen, "green"}, {Colour::kBlue, "blue"}};
  return names;
}

struct Inner {
  double weight = 0.1;
  std::uint64_t seed = 7;
};

struct Outer {
  bool on = true;
  int count = 3;
  Colour colour = Colour::kGreen;
  Inner inner;
};

// A struct of a higher library that holds Outer and keeps its vocabulary.
struct Wider {
  Outer outer;
  int steps = 5;
};

const OptionTable<Inner>& InnerTable() {
  static const OptionTable<Inner> table = [] {
    OptionTable<Inner> t;
    t.Double("weight", &Inner::weight, "A weight.").AtLeast(0, "a finite weight >= 0");
    t.Int("seed", &Inner::seed, "A seed.");
    return t;
  }();
  return table;
}

const OptionTable<Outer>& OuterTable() {
  static const OptionTable<Outer> table = [] {
    OptionTable<Outer> t;
    t.Bool("on", &Outer::on, "A switch.");
    t.Int("count", &Outer::count, "A count.").Range(1, 10, "an integer in 1..10").Alias("n");
    t.Enum("colour", &Outer::colour, ColourNames(), "A colour.");
    t.Embed("inner", &Outer::inner, InnerTable());
    return t;
  }();
  return table;
}

TEST(EnumNamesTest, NamesParsesAndListsTheValues) {
  EXPECT_STREQ(ColourNames().Name(Colour::kBlue), "blue");
  Colour colour = Colour::kRed;
  EXPECT_TRUE(ColourNames().Parse("green", &colour));
  EXPECT_EQ(colour, Colour::kGreen);
  EXPECT_FALSE(ColourNames().Parse("purple", &colour));
  EXPECT_EQ(colour, Colour::kGreen);
  EXPECT_EQ(ColourNames().Expected(), "red, green or blue");
}

TEST(EnumNamesTest, FromAnExistingNameFunction) {
  const auto names = EnumNames<Colour>::FromFunction(
      {Colour::kRed, Colour::kBlue}, [](Colour c) { return ColourNames().Name(c); });
  EXPECT_EQ(names.Expected(), "red or blue");
  Colour colour = Colour::kRed;
  EXPECT_FALSE(names.Parse("green", &colour));
}

TEST(OptionTableTest, DescribesInDeclarationOrderWithExactNumbers) {
  const auto fields = OuterTable().Describe(Outer());
  ASSERT_EQ(fields.size(), 5u);
  EXPECT_EQ(fields[0], std::make_pair(std::string("on"), std::string("true")));
  EXPECT_EQ(fields[1], std::make_pair(std::string("count"), std::string("3")));
  EXPECT_EQ(fields[2], std::make_pair(std::string("colour"), std::string("green")));
  EXPECT_EQ(fields[3], std::make_pair(std::string("inner.weight"),
                                      std::string("0.10000000000000001")));
  EXPECT_EQ(fields[4], std::make_pair(std::string("inner.seed"), std::string("7")));
}

TEST(OptionTableTest, SetsEmbeddedFieldsAndAliases) {
  Outer outer;
  std::string error;
  ASSERT_TRUE(OuterTable().Set("inner.weight", "2.5", &outer, &error)) << error;
  ASSERT_TRUE(OuterTable().Set("n", "9", &outer, &error)) << error;
  ASSERT_TRUE(OuterTable().Set("colour", "blue", &outer, &error)) << error;
  ASSERT_TRUE(OuterTable().Set("on", "false", &outer, &error)) << error;
  EXPECT_EQ(outer.inner.weight, 2.5);
  EXPECT_EQ(outer.count, 9);
  EXPECT_EQ(outer.colour, Colour::kBlue);
  EXPECT_FALSE(outer.on);
}

TEST(OptionTableTest, ErrorsAreOneLineNamingTheOption) {
  Outer outer;
  std::string error;
  EXPECT_FALSE(OuterTable().Set("count", "11", &outer, &error));
  EXPECT_EQ(error, "count=11: expected an integer in 1..10");
  EXPECT_FALSE(OuterTable().Set("n", "0", &outer, &error, "--n"));
  EXPECT_EQ(error, "--n=0: expected an integer in 1..10");
  EXPECT_FALSE(OuterTable().Set("colour", "purple", &outer, &error));
  EXPECT_EQ(error, "colour=purple: expected red, green or blue");
  EXPECT_FALSE(OuterTable().Set("inner.weight", "-1", &outer, &error));
  EXPECT_EQ(error, "inner.weight=-1: expected a finite weight >= 0");
  EXPECT_FALSE(OuterTable().Set("inner.weight", "inf", &outer, &error));
  EXPECT_FALSE(OuterTable().Set("inner.weight", "1x", &outer, &error));
  EXPECT_EQ(error, "inner.weight=1x: expected a number");
  EXPECT_FALSE(OuterTable().Set("count", "99999999999", &outer, &error));
  EXPECT_EQ(error, "count=99999999999: expected an integer in -2147483648..2147483647");
  EXPECT_FALSE(OuterTable().Set("inner.seed", "-1", &outer, &error));
  EXPECT_FALSE(OuterTable().Set("on", "yes", &outer, &error));
  EXPECT_EQ(error, "on=yes: expected true or false");
  EXPECT_FALSE(OuterTable().Set("colur", "red", &outer, &error));
  EXPECT_EQ(error, "colur: not an option (the options are on, count, colour, inner.weight, "
                   "inner.seed)");
  // A refused value leaves the struct as it was.
  EXPECT_EQ(OuterTable().Describe(outer), OuterTable().Describe(Outer()));
}

TEST(OptionTableTest, ChecksRanges) {
  Outer outer;
  std::string error;
  EXPECT_TRUE(OuterTable().CheckRanges(outer, &error));
  outer.count = 0;
  EXPECT_FALSE(OuterTable().CheckRanges(outer, &error));
  EXPECT_EQ(error, "count=0: expected an integer in 1..10");
}

TEST(OptionTableTest, AWiderStructEmbedsATableKeepingItsNames) {
  OptionTable<Wider> wider;
  wider.Embed("", &Wider::outer, OuterTable());
  wider.Int("steps", &Wider::steps, "Steps per frame.").AtLeast(1, "an integer >= 1");
  Wider options;
  std::string error;
  ASSERT_TRUE(wider.Set("inner.seed", "11", &options, &error)) << error;
  ASSERT_TRUE(wider.Set("n", "4", &options, &error)) << error;
  EXPECT_EQ(options.outer.inner.seed, 11u);
  EXPECT_EQ(options.outer.count, 4);
  const auto fields = wider.Describe(options);
  ASSERT_EQ(fields.size(), 6u);
  EXPECT_EQ(fields[4].first, "inner.seed");
  EXPECT_EQ(fields[5], std::make_pair(std::string("steps"), std::string("5")));
}

}  // namespace
}  // namespace msdeform
