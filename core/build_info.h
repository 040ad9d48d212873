// What a run was made with, for reports and --version: msdeform's version and
// the commit it was built from (embedded at build time), the versions of the
// libraries core is built against, the machine, the date, and SHA-256 digests
// of input files.

#ifndef MSDEFORM_CORE_BUILD_INFO_H_
#define MSDEFORM_CORE_BUILD_INFO_H_

#include <string>

namespace msdeform {

// "0.3.0" (CMake's project version).
const char* MsdeformVersion();
// The short commit hash the binary was built from, "+uncommitted" when the
// working tree had changes to tracked files, or "unknown" outside a git
// checkout.
const char* MsdeformCommit();
// "3.4.0", "9.0".
std::string EigenVersion();
std::string OpenMeshVersion();
// The CPU model name from /proc/cpuinfo ("unknown" when not there).
std::string CpuModel();
int NumCores();
// Current UTC time, ISO 8601: "2026-11-23T04:05:06Z".
std::string UtcNow();

// Where msdeform's own files are, without a path baked in at build time:
// `relative` (e.g. "experiments/scenarios") under $MSDEFORM_SOURCE_DIR when
// set, else under the nearest folder above the running executable that has
// it (the source tree of a build in <tree>/build/...), else `relative`
// itself (from the working folder).
std::string SourceTreePath(const std::string& relative);
// The data folder: $MSDEFORM_DATA_DIR when set, else SourceTreePath("data").
std::string DataDir();

// SHA-256 of a file's bytes as 64 lowercase hex digits; false with
// "<path>: cannot read" when it cannot be read. On a CPU with the x86 SHA
// extensions (checked at run time) the blocks are hashed with them, about 6x
// faster than the portable code (the 1.66M armadillo's 83 MB in 0.06 s;
// docs/decisions/millions-of-vertices.md).
bool Sha256File(const std::string& path, std::string* digest, std::string* error);
// SHA-256 of a byte string (the same digest as the file holding those bytes).
// use_cpu_extensions = false forces the portable code (tests compare the two).
std::string Sha256(const std::string& bytes, bool use_cpu_extensions = true);
// Whether Sha256File and Sha256 use the x86 SHA extensions on this CPU.
bool Sha256ExtensionsAvailable();

}  // namespace msdeform

#endif  // MSDEFORM_CORE_BUILD_INFO_H_
