// docs/extending.md against the tree. Every code block of a recipe names the
// file it is taken from on its opening line (```cpp methods/full_arap.cc), and
// every line it shows is in that file, in the order shown; a line "// ..." or
// "..." in a block stands for lines left out. The files are compiled and tested
// by the build (the libraries, examples/ through tests/examples/), so the code
// a recipe shows is code that builds and runs. Each recipe ends with "Files
// touched", whose paths exist. What the recipes say a row or a registration
// gives is checked here too, on the examples they walk through (w_coh,
// energy, full_arap).

#include <algorithm>
#include <cctype>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "msdeform/methods/method_option_table.h"
#include "msdeform/methods/registry.h"
#include "msdeform/scales/deformer_options.h"
#include "msdeform/solvers/local_global_arap.h"
#include "tests/test_util.h"

namespace msdeform {
namespace {

const std::string kDoc = "docs/extending.md";

std::string SourcePath(const std::string& relative) {
  return std::string(MSDEFORM_SOURCE_DIR) + "/" + relative;
}

bool Exists(const std::string& relative) {
  return std::ifstream(SourcePath(relative)).good();
}

std::string Trim(const std::string& line) {
  size_t begin = 0, end = line.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(line[begin]))) ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(line[end - 1]))) --end;
  return line.substr(begin, end - begin);
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

bool StartsWith(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}

// A fenced code block: the "## " section it is in, the file its opening line
// names ("" when none), its first line's number in the doc and its lines.
struct Block {
  std::string section;
  std::string file;
  int doc_line = 0;
  std::vector<std::string> lines;
};

struct Section {
  std::string title;
  std::vector<std::string> lines;  // outside code blocks
};

struct Doc {
  std::vector<Block> blocks;
  std::vector<Section> sections;
};

Doc ReadDoc() {
  Doc doc;
  doc.sections.push_back({"", {}});
  Block* open = nullptr;
  const std::vector<std::string> lines = Lines(ReadText(SourcePath(kDoc)));
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::string line = Trim(lines[i]);
    if (open != nullptr) {
      if (line == "```") {
        open = nullptr;
      } else {
        open->lines.push_back(lines[i]);
      }
      continue;
    }
    if (StartsWith(line, "```")) {
      Block block;
      block.section = doc.sections.back().title;
      block.doc_line = static_cast<int>(i) + 1;
      std::istringstream info(line.substr(3));
      std::string language;
      info >> language >> block.file;
      doc.blocks.push_back(block);
      open = &doc.blocks.back();
      continue;
    }
    if (StartsWith(line, "## ")) doc.sections.push_back({line.substr(3), {}});
    doc.sections.back().lines.push_back(line);
  }
  EXPECT_EQ(open, nullptr) << kDoc << ": a code block is not closed";
  return doc;
}

bool IsRecipe(const std::string& section) { return StartsWith(section, "Adding "); }

bool IsElision(const std::string& trimmed) {
  return trimmed == "..." || StartsWith(trimmed, "// ...");
}

// The non-blank lines of `lines`, trimmed.
std::vector<std::string> Code(const std::vector<std::string>& lines) {
  std::vector<std::string> code;
  for (const std::string& line : lines) {
    const std::string trimmed = Trim(line);
    if (!trimmed.empty()) code.push_back(trimmed);
  }
  return code;
}

// Empty when every run of the block's lines between elisions is a run of
// consecutive lines of `file` (blank lines and indentation aside), the runs
// in order; else the first line of the run that is not there.
std::string FirstMissingRun(const std::vector<std::string>& block,
                            const std::vector<std::string>& file) {
  std::vector<std::vector<std::string>> runs(1);
  for (const std::string& line : Code(block)) {
    if (IsElision(line)) {
      runs.emplace_back();
    } else {
      runs.back().push_back(line);
    }
  }
  size_t from = 0;
  for (const std::vector<std::string>& run : runs) {
    if (run.empty()) continue;
    bool found = false;
    for (size_t start = from; start + run.size() <= file.size() && !found; ++start) {
      found = std::equal(run.begin(), run.end(), file.begin() + start);
      if (found) from = start + run.size();
    }
    if (!found) return run.front();
  }
  return "";
}

// The paths a line names in backticks: `methods/foo.cc`, `methods/x.{h,cc}`;
// not a placeholder (foo, <name>) nor a token with spaces.
std::vector<std::string> BacktickedPaths(const std::string& line) {
  std::vector<std::string> paths;
  size_t open = line.find('`');
  while (open != std::string::npos) {
    const size_t close = line.find('`', open + 1);
    if (close == std::string::npos) break;
    const std::string token = line.substr(open + 1, close - open - 1);
    open = line.find('`', close + 1);
    if (token.find('/') == std::string::npos || token.find(' ') != std::string::npos ||
        token.find("foo") != std::string::npos || token.find('<') != std::string::npos ||
        token.find('*') != std::string::npos || StartsWith(token, "--")) {
      continue;
    }
    const size_t brace = token.find(".{");
    if (brace != std::string::npos && token.back() == '}') {
      std::istringstream extensions(token.substr(brace + 2, token.size() - brace - 3));
      for (std::string extension; std::getline(extensions, extension, ',');) {
        paths.push_back(token.substr(0, brace + 1) + extension);
      }
      continue;
    }
    const std::string name = token.substr(token.rfind('/') + 1);
    if (name.find('.') != std::string::npos || name == "CMakeLists.txt") paths.push_back(token);
  }
  return paths;
}

TEST(ExtendingDocTest, EveryRecipeShowsCodeNamedByItsFile) {
  const Doc doc = ReadDoc();
  int recipes = 0;
  for (const Section& section : doc.sections) {
    if (!IsRecipe(section.title)) continue;
    ++recipes;
    int blocks = 0;
    for (const Block& block : doc.blocks) {
      if (block.section != section.title) continue;
      ++blocks;
      EXPECT_FALSE(block.file.empty())
          << kDoc << ":" << block.doc_line << " (" << section.title
          << "): the block names no file (```cpp <path>)";
    }
    EXPECT_GE(blocks, 1) << kDoc << " (" << section.title << "): shows no code";
  }
  EXPECT_EQ(recipes, 6) << kDoc << ": the six recipes (energy term, method, option, "
                        << "linear solver, Ceres variant, results column)";
}

TEST(ExtendingDocTest, EachBlockIsInTheFileItNames) {
  for (const Block& block : ReadDoc().blocks) {
    if (block.file.empty()) continue;
    SCOPED_TRACE(kDoc + ":" + std::to_string(block.doc_line) + ", from " + block.file);
    ASSERT_TRUE(Exists(block.file)) << block.file << " does not exist";
    const std::vector<std::string> file = Code(Lines(ReadText(SourcePath(block.file))));
    EXPECT_EQ(FirstMissingRun(block.lines, file), "")
        << "the lines from this one on are not in " << block.file << " as shown";
  }
}

// The check itself, on a file it knows: a run must be consecutive lines, the
// runs in order, and an elision may skip lines.
TEST(ExtendingDocTest, ARunMustBeConsecutiveAndInOrder) {
  const std::vector<std::string> file = {"a", "b", "c", "d"};
  EXPECT_EQ(FirstMissingRun({"  a", "", "b"}, file), "");
  EXPECT_EQ(FirstMissingRun({"a", "// ...", "d"}, file), "");
  EXPECT_EQ(FirstMissingRun({"a", "c"}, file), "a");
  EXPECT_EQ(FirstMissingRun({"c", "...", "a"}, file), "a");
  EXPECT_EQ(BacktickedPaths("`methods/x.{h,cc}` and `a/b.h`, `methods/foo.cc`, `--x=a/b`"),
            (std::vector<std::string>{"methods/x.h", "methods/x.cc", "a/b.h"}));
}

TEST(ExtendingDocTest, EveryFileTheDocNamesExists) {
  const Doc doc = ReadDoc();
  for (const Section& section : doc.sections) {
    bool files_touched = false;
    for (const std::string& line : section.lines) {
      files_touched = files_touched || line == "### Files touched";
      for (const std::string& path : BacktickedPaths(line)) {
        EXPECT_TRUE(Exists(path)) << kDoc << " (" << section.title << "): " << path
                                  << " does not exist";
      }
    }
    if (IsRecipe(section.title)) {
      EXPECT_TRUE(files_touched) << kDoc << " (" << section.title << "): no \"Files touched\"";
    }
  }
}

// "Adding an option": the words w_coh's row gives every caller, and the
// enum's from its names table.
TEST(ExtendingRecipesTest, AnOptionsRowGivesTheFlagTheCheckAndTheDescription) {
  const OptionTable<DeformerOptions>& table = DeformerOptionTable();
  DeformerOptions options;
  std::string error;
  EXPECT_FALSE(table.Set("w_coh", "-1", &options, &error, "--w_coh"));
  EXPECT_EQ(error, "--w_coh=-1: expected a finite weight >= 0");
  EXPECT_EQ(table.Find("w_coh")->topic, "weights");
  EXPECT_EQ(table.Find("length_unit")->topic, "");  // no .Flag: not on the command line
  options.w_coh = -1;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_EQ(error, "w_coh=-1: expected a finite weight >= 0");
  bool described = false;
  for (const auto& field : DescribeOptions(DeformerOptions())) {
    described = described || (field.first == "w_coh" && field.second == "10");
  }
  EXPECT_TRUE(described);
  EXPECT_FALSE(table.Set("energy", "x", &options, &error));
  EXPECT_EQ(error, "energy=x: expected ed or arap");
}

// "Adding a method": what full_arap's registration in its own file gives.
TEST(ExtendingRecipesTest, AMethodRegisteredInItsFileHasItsRowsAndItsOptions) {
  const MethodDescriptor* full_arap = FindMethod("full_arap");
  ASSERT_NE(full_arap, nullptr);
  EXPECT_EQ(MinimisedEnergy("full_arap", DeformerOptions()), "arap");
  EXPECT_EQ(MethodsOfRow("full_arap.max_iterations"), std::vector<std::string>{"full_arap"});
  EXPECT_EQ(MethodOptionTable().Find("full_arap_max_iterations")->topic, "method");
  MethodOptions options;
  std::string error;
  ASSERT_TRUE(MethodOptionTable().Set("full_arap.max_iterations", "50", &options, &error));
  EXPECT_EQ(options.own.Get<LocalGlobalArapOptions>("full_arap").max_iterations, 50);
  options.own.Mutable<LocalGlobalArapOptions>("full_arap")->relative_tolerance = 2;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_EQ(error, "full_arap.relative_tolerance=2: expected a number in [0, 1]");
  std::unique_ptr<EditingMethod> method = CreateMethod("full_arap", &error);
  ASSERT_NE(method, nullptr) << error;
  EXPECT_EQ(method->name(), "full_arap");
}

}  // namespace
}  // namespace msdeform
