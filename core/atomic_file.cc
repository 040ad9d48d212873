#include "msdeform/core/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace msdeform {
namespace {

namespace fs = std::filesystem;

// A name for the temporary beside `path`: hidden, and unique within this
// process (pid + counter); O_EXCL below catches clashes with anything else.
std::string TemporaryName(const fs::path& path, int attempt) {
  static std::atomic<unsigned> counter{0};
  std::ostringstream name;
  name << "." << path.filename().string() << ".tmp-" << ::getpid() << "-" << counter++ << "-"
       << attempt;
  return (path.parent_path() / name.str()).string();
}

// Removes the temporary unless Release() was called (after the rename).
class TemporaryFile {
 public:
  explicit TemporaryFile(std::string name) : name_(std::move(name)) {}
  ~TemporaryFile() {
    if (!name_.empty()) std::remove(name_.c_str());
  }
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  const std::string& name() const { return name_; }
  void Release() { name_.clear(); }

 private:
  std::string name_;
};

bool Fail(const std::string& path, const std::string& problem, std::string* error) {
  *error = path + ": " + problem;
  return false;
}

}  // namespace

bool WriteFileAtomically(const std::string& path, const StreamWriter& write, std::string* error) {
  if (path.empty()) return Fail("<empty path>", "no output file name given", error);
  const fs::path target(path);
  if (!target.has_filename()) return Fail(path, "output path names a folder, not a file", error);

  // Create the temporary with O_EXCL so the mode follows the umask like any
  // newly created file, and no other writer's temporary is reused.
  std::string temporary_name;
  int fd = -1;
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    temporary_name = TemporaryName(target, attempt);
    fd = ::open(temporary_name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) {
    return Fail(
        path,
        std::string("cannot create a temporary file beside it (") + std::strerror(errno) + ")",
        error);
  }
  ::close(fd);
  TemporaryFile temporary(temporary_name);

  {
    std::ofstream out(temporary.name(), std::ios::binary | std::ios::trunc);
    if (!out) return Fail(path, "cannot open the temporary file for writing", error);
    std::string write_error;
    if (!write(out, &write_error)) {
      return Fail(path, write_error.empty() ? "writing failed" : write_error, error);
    }
    out.flush();
    if (!out) return Fail(path, "writing failed (disk full or I/O error?)", error);
    out.close();
    if (out.fail()) return Fail(path, "closing the temporary file failed", error);
  }

  // Flush the data to disk before the rename makes it visible, so a crash
  // leaves either the old file or the complete new one.
  fd = ::open(temporary.name().c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0 || ::fsync(fd) != 0) {
    const int saved_errno = errno;
    if (fd >= 0) ::close(fd);
    return Fail(path,
                std::string("cannot sync the temporary file (") + std::strerror(saved_errno) + ")",
                error);
  }
  ::close(fd);

  if (std::rename(temporary.name().c_str(), path.c_str()) != 0) {
    return Fail(
        path,
        std::string("cannot move the finished temporary into place (") + std::strerror(errno) + ")",
        error);
  }
  temporary.Release();
  return true;
}

bool SameFile(const std::string& a, const std::string& b) {
  std::error_code ec;
  const bool same = fs::equivalent(a, b, ec);
  return !ec && same;
}

}  // namespace msdeform
