#include "msdeform/core/build_info.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace msdeform {
namespace {

namespace fs = std::filesystem;

// FIPS 180-4 / NIST example vectors, with the x86 SHA extensions (where the
// CPU has them) and with the portable code.
TEST(BuildInfoTest, Sha256MatchesTheStandardVectors) {
  SCOPED_TRACE(Sha256ExtensionsAvailable() ? "SHA extensions available" : "portable code only");
  for (bool extensions : {true, false}) {
    SCOPED_TRACE(extensions ? "use_cpu_extensions" : "portable");
    EXPECT_EQ(Sha256("", extensions),
              "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    EXPECT_EQ(Sha256("abc", extensions),
              "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    // 56 bytes: the padding needs a second block.
    EXPECT_EQ(Sha256("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq", extensions),
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    // 112 bytes: two whole blocks of message.
    EXPECT_EQ(Sha256("abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmnoijklmnopjklmnopq"
                     "klmnopqrlmnopqrsmnopqrstnopqrstu",
                     extensions),
              "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1");
    // One million 'a' (many blocks).
    EXPECT_EQ(Sha256(std::string(1000000, 'a'), extensions),
              "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  }
}

// Every length around the block and padding boundaries: both codes agree.
TEST(BuildInfoTest, Sha256ExtensionsAndPortableCodeAgreeOnEveryLength) {
  std::string bytes;
  for (int i = 0; i < 300; ++i) bytes.push_back(static_cast<char>(i * 131 % 251));
  for (size_t length = 0; length <= bytes.size(); ++length) {
    const std::string prefix = bytes.substr(0, length);
    EXPECT_EQ(Sha256(prefix, true), Sha256(prefix, false)) << length;
  }
}

TEST(BuildInfoTest, Sha256FileHashesTheFileBytes) {
  const fs::path path = fs::temp_directory_path() / "msdeform_build_info_test.bin";
  std::string bytes;
  // Over two of Sha256File's 1 MiB reads, ending inside a block.
  for (unsigned i = 0; i < (5u << 19) + 37; ++i) bytes.push_back(static_cast<char>(i * 7919 % 256));
  {
    std::ofstream out(path, std::ios::binary);
    out << bytes;
  }
  std::string digest, error;
  ASSERT_TRUE(Sha256File(path.string(), &digest, &error)) << error;
  EXPECT_EQ(digest, Sha256(bytes));
  EXPECT_EQ(digest, Sha256(bytes, /*use_cpu_extensions=*/false));
  fs::remove(path);
  EXPECT_FALSE(Sha256File(path.string(), &digest, &error));
  EXPECT_NE(error.find("cannot read"), std::string::npos) << error;
}

TEST(BuildInfoTest, VersionsAndCommitAreFilledIn) {
  EXPECT_FALSE(std::string(MsdeformVersion()).empty());
  EXPECT_FALSE(std::string(MsdeformCommit()).empty());
  EXPECT_EQ(EigenVersion().find('.') != std::string::npos, true) << EigenVersion();
  EXPECT_EQ(OpenMeshVersion().find('.') != std::string::npos, true) << OpenMeshVersion();
  EXPECT_GE(NumCores(), 1);
  EXPECT_EQ(UtcNow().size(), 20u) << UtcNow();  // 2026-11-23T04:05:06Z
}

TEST(BuildInfoTest, SourceTreePathFindsTheTreeOrTheOverride) {
  // The test binary lives in <tree>/build/tests/: walking up finds the tree.
  EXPECT_TRUE(fs::exists(fs::path(SourceTreePath("experiments/scenarios")) / "cactus.json"));
  EXPECT_TRUE(fs::exists(fs::path(DataDir()) / "scenarios" / "armadillo_claw.json"));
  setenv("MSDEFORM_SOURCE_DIR", "/elsewhere", 1);
  EXPECT_EQ(SourceTreePath("experiments/scenarios"), "/elsewhere/experiments/scenarios");
  unsetenv("MSDEFORM_SOURCE_DIR");
  setenv("MSDEFORM_DATA_DIR", "/my/data", 1);
  EXPECT_EQ(DataDir(), "/my/data");
  unsetenv("MSDEFORM_DATA_DIR");
  // Nothing of that name above the executable: the relative path itself.
  EXPECT_EQ(SourceTreePath("no/such/folder/anywhere"), "no/such/folder/anywhere");
}

}  // namespace
}  // namespace msdeform
