#include "msdeform/core/atomic_file.h"

#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "tests/test_util.h"

namespace msdeform {
namespace {

namespace fs = std::filesystem;

int CountEntries(const std::string& folder) {
  int count = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder)) ++count;
  return count;
}

StreamWriter WriteString(const std::string& text) {
  return [text](std::ostream& out, std::string*) {
    out << text;
    return true;
  };
}

TEST(AtomicFileTest, WritesTheContentAndLeavesNoTemporary) {
  const std::string folder = FreshFolder();
  const std::string path = folder + "/out.txt";
  std::string error;
  ASSERT_TRUE(WriteFileAtomically(path, WriteString("hello\n"), &error)) << error;
  EXPECT_EQ(ReadText(path), "hello\n");
  EXPECT_EQ(CountEntries(folder), 1);
}

TEST(AtomicFileTest, ReplacesAnExistingFile) {
  const std::string path = FreshFolder() + "/out.txt";
  std::string error;
  ASSERT_TRUE(WriteFileAtomically(path, WriteString("old, longer content\n"), &error)) << error;
  ASSERT_TRUE(WriteFileAtomically(path, WriteString("new\n"), &error)) << error;
  EXPECT_EQ(ReadText(path), "new\n");
}

TEST(AtomicFileTest, FailedWriterLeavesNothingAndSaysWhy) {
  const std::string folder = FreshFolder();
  const std::string path = folder + "/out.csv";
  std::string error;
  const bool ok = WriteFileAtomically(
      path,
      [](std::ostream& out, std::string* why) {
        out << "half a table,";
        *why = "row 3 has no value";
        return false;
      },
      &error);
  EXPECT_FALSE(ok);
  EXPECT_EQ(error, path + ": row 3 has no value");
  EXPECT_EQ(CountEntries(folder), 0) << "neither output nor temporary";
}

TEST(AtomicFileTest, FailedWriteKeepsThePreviousFile) {
  const std::string folder = FreshFolder();
  const std::string path = folder + "/report.json";
  std::string error;
  ASSERT_TRUE(WriteFileAtomically(path, WriteString("{\"good\": 1}"), &error)) << error;
  EXPECT_FALSE(WriteFileAtomically(
      path,
      [](std::ostream& out, std::string*) {
        out << "{\"bro";
        return false;
      },
      &error));
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_EQ(ReadText(path), "{\"good\": 1}");
  EXPECT_EQ(CountEntries(folder), 1);
}

TEST(AtomicFileTest, StreamErrorCountsAsFailure) {
  const std::string folder = FreshFolder();
  const std::string path = folder + "/out.txt";
  std::string error;
  EXPECT_FALSE(WriteFileAtomically(
      path,
      [](std::ostream& out, std::string*) {
        out.setstate(std::ios::badbit);
        return true;
      },
      &error));
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_EQ(CountEntries(folder), 0);
}

TEST(AtomicFileTest, MissingFolderIsAnErrorNamingThePath) {
  const std::string path = FreshFolder() + "/not/there/out.txt";
  std::string error;
  EXPECT_FALSE(WriteFileAtomically(path, WriteString("x"), &error));
  EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << error;
  EXPECT_FALSE(fs::exists(path));
}

TEST(AtomicFileTest, OutputPathThatIsAFolderFails) {
  const std::string folder = FreshFolder();
  fs::create_directory(folder + "/taken");
  std::string error;
  EXPECT_FALSE(WriteFileAtomically(folder + "/taken", WriteString("x"), &error));
  EXPECT_NE(error.find("taken"), std::string::npos) << error;
  EXPECT_TRUE(fs::is_directory(folder + "/taken"));
  EXPECT_EQ(CountEntries(folder), 1) << "temporary removed";
}

TEST(AtomicFileTest, SameFileSeesThroughSpellingAndLinks) {
  const std::string folder = FreshFolder();
  const std::string a = folder + "/a.off";
  const std::string b = folder + "/b.off";
  std::string error;
  ASSERT_TRUE(WriteFileAtomically(a, WriteString("a"), &error)) << error;
  ASSERT_TRUE(WriteFileAtomically(b, WriteString("a"), &error)) << error;
  fs::create_symlink(a, folder + "/link.off");
  EXPECT_TRUE(SameFile(a, a));
  EXPECT_TRUE(SameFile(a, folder + "/./a.off"));
  EXPECT_TRUE(SameFile(a, folder + "/link.off"));
  EXPECT_FALSE(SameFile(a, b)) << "equal content, different files";
  EXPECT_FALSE(SameFile(a, folder + "/missing.off"));
  EXPECT_FALSE(SameFile(folder + "/missing.off", folder + "/missing.off"));
}

}  // namespace
}  // namespace msdeform
