// ReadMesh and WriteMesh, the dispatcher: the format by extension, then that
// format's check (core/mesh_io_off.cc, mesh_io_obj.cc, mesh_io_ply.cc,
// mesh_io_stl.cc), the OpenMesh pass (core/mesh_io_openmesh.cc), and the
// steps every format shares (core/mesh_io_soup.cc): polygons split into fans,
// STL corners welded (here), triangles that repeat a vertex or duplicate
// another dropped and counted in the MeshReadReport, the result validated.

#include "msdeform/core/mesh_io.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

#include "msdeform/core/atomic_file.h"
#include "msdeform/core/mesh_io_formats.h"
#include "msdeform/core/text_lines.h"

namespace msdeform {
namespace {

namespace fs = std::filesystem;

// Every format, in the order the messages list them.
constexpr MeshFormat kFormats[] = {
    // extension, name, check, weld_equal_positions, writable
    {"off", "OFF", CheckOff, false, true},
    {"obj", "OBJ", CheckObj, false, true},
    {"ply", "PLY", CheckPly, false, true},
    {"stl", "STL", CheckStl, true, false},
};

bool Fail(const std::string& path, const std::string& problem, std::string* error) {
  *error = path + ": " + problem;
  return false;
}

// Lower-case extension without the dot ("" when there is none).
std::string LowerExtension(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  if (!extension.empty()) extension.erase(0, 1);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

// The format for a lower-case extension (among the writable ones when
// `for_writing`); nullptr when there is none.
const MeshFormat* FindFormat(const std::string& extension, bool for_writing) {
  for (const MeshFormat& format : kFormats) {
    if (extension == format.extension && (format.writable || !for_writing)) return &format;
  }
  return nullptr;
}

// "'.xyz'; use .off, .obj, .ply or .stl" for a message about an extension
// no format (or no writable format) has.
std::string OtherFormatsHint(const std::string& extension, bool for_writing) {
  std::vector<std::string> names;
  for (const MeshFormat& format : kFormats) {
    if (format.writable || !for_writing) names.push_back(std::string(".") + format.extension);
  }
  std::string hint = (extension.empty() ? "(no extension)" : "'." + extension + "'") + "; use ";
  for (size_t i = 0; i < names.size(); ++i) {
    if (i > 0) hint += i + 1 == names.size() ? " or " : ", ";
    hint += names[i];
  }
  return hint;
}

// A mesh file's bytes, or a problem: missing, a folder, unreadable or empty.
// A regular file is mapped read-only (the page cache's own pages: no copy and
// no fresh memory to zero, where reading into a string through a stream
// iterator made ReadMesh of the 1.66M binary PLY take 0.45-0.53 s instead of
// 0.28 s; docs/decisions/millions-of-vertices.md); anything else (a pipe, a device) is read into
// memory. The mapping lives as long as the object.
class FileBytes {
 public:
  FileBytes() = default;
  FileBytes(const FileBytes&) = delete;
  FileBytes& operator=(const FileBytes&) = delete;
  ~FileBytes() { Release(); }

  // With `populate` the pages are mapped before Open returns (one thread
  // faulting them in); without, as the parse first reads them (on each of
  // its threads).
  bool Open(const std::string& path, bool populate, std::string* problem) {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (!fs::exists(status)) {
      *problem = "no such file";
      return false;
    }
    if (fs::is_directory(status)) {
      *problem = "is a folder, not a mesh file";
      return false;
    }
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
      *problem = "cannot open for reading (" + std::string(std::strerror(errno)) + ")";
      return false;
    }
    struct stat info;
    if (::fstat(fd, &info) == 0 && S_ISREG(info.st_mode) && info.st_size > 0) {
      void* map = ::mmap(nullptr, static_cast<size_t>(info.st_size), PROT_READ,
                         MAP_PRIVATE | (populate ? MAP_POPULATE : 0), fd, 0);
      if (map != MAP_FAILED) {
        map_ = map;
        size_ = static_cast<size_t>(info.st_size);
        ::close(fd);
        return true;
      }
    }
    // Not mappable (a pipe, a device, a file the kernel reports as empty such
    // as those of /proc): read until the end.
    char buffer[1 << 16];
    for (;;) {
      const ssize_t got = ::read(fd, buffer, sizeof(buffer));
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) {
        ::close(fd);
        *problem = "read error";
        return false;
      }
      if (got == 0) break;
      copy_.append(buffer, static_cast<size_t>(got));
    }
    ::close(fd);
    if (copy_.empty()) {
      *problem = "file is empty";
      return false;
    }
    return true;
  }

  std::string_view view() const {
    return map_ != nullptr ? std::string_view(static_cast<const char*>(map_), size_) : copy_;
  }

  // Unmaps or frees the bytes (view() is empty afterwards).
  void Release() {
    if (map_ != nullptr) ::munmap(map_, size_);
    map_ = nullptr;
    size_ = 0;
    std::string().swap(copy_);
  }

 private:
  void* map_ = nullptr;
  size_t size_ = 0;
  std::string copy_;
};

// Frees what it is given: at once, or with `in_background` on a thread of
// its own (joined when the object goes), alongside the caller's next steps.
class BackgroundRelease {
 public:
  explicit BackgroundRelease(bool in_background) : in_background_(in_background) {}
  BackgroundRelease(const BackgroundRelease&) = delete;
  BackgroundRelease& operator=(const BackgroundRelease&) = delete;
  ~BackgroundRelease() {
    for (std::thread& thread : threads_) thread.join();
  }

  template <typename T>
  void Release(std::unique_ptr<T> object) {
    if (!in_background_) return;  // freed here, as `object` goes
    threads_.emplace_back([owned = std::move(object)]() mutable { owned.reset(); });
  }

 private:
  bool in_background_;
  std::vector<std::thread> threads_;
};

// Merges vertices at exactly equal positions (first appearance wins, order
// kept). Triangles that collapse are left to DropDegenerateAndDuplicateFaces.
void WeldExactDuplicates(Mesh* mesh) {
  std::map<std::array<double, 3>, int> id_of_position;
  std::vector<int> new_id(mesh->num_vertices());
  int count = 0;
  for (int v = 0; v < mesh->num_vertices(); ++v) {
    const std::array<double, 3> key{mesh->vertices(0, v), mesh->vertices(1, v),
                                    mesh->vertices(2, v)};
    const auto [it, inserted] = id_of_position.emplace(key, count);
    if (inserted) mesh->vertices.col(count++) = mesh->vertices.col(v);
    new_id[v] = it->second;
  }
  mesh->vertices.conservativeResize(3, count);
  for (int f = 0; f < mesh->num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) mesh->faces(c, f) = new_id[mesh->faces(c, f)];
  }
}

// "3 faces that repeat a vertex and 1 duplicate face" ("" when none).
std::string DescribeDroppedFaces(const MeshReadReport& report) {
  std::ostringstream text;
  const int degenerate = report.dropped_degenerate_faces;
  const int duplicate = report.dropped_duplicate_faces;
  if (degenerate > 0) {
    text << degenerate << (degenerate == 1 ? " face that repeats" : " faces that repeat")
         << " a vertex";
  }
  if (degenerate > 0 && duplicate > 0) text << " and ";
  if (duplicate > 0) text << duplicate << " duplicate face" << (duplicate == 1 ? "" : "s");
  return text.str();
}

}  // namespace

bool MeshReadOptions::Check(std::string* problem) const {
  if (num_threads < 1) return SetProblem(problem, "num_threads ", num_threads, ": need at least 1");
  if (text_chunk_bytes < 1) {
    return SetProblem(problem, "text_chunk_bytes ", text_chunk_bytes, ": need at least 1");
  }
  if (items_per_chunk < 1) {
    return SetProblem(problem, "items_per_chunk ", items_per_chunk, ": need at least 1");
  }
  return true;
}

bool ReadMesh(const std::string& path, const MeshReadOptions& options, Mesh* mesh,
              MeshReadReport* report, std::string* error) {
  *report = MeshReadReport();
  std::string problem;
  if (!options.Check(&problem)) return Fail(path, "ReadMesh options: " + problem, error);
  const std::string extension = LowerExtension(path);
  const MeshFormat* format = FindFormat(extension, /*for_writing=*/false);
  if (format == nullptr) {
    return Fail(path, "unknown mesh format " + OtherFormatsHint(extension, /*for_writing=*/false),
                error);
  }
  // On more than one thread the file's mapping and the soup are given back
  // on a thread of their own, alongside the steps that follow (unmapping and
  // freeing them took 9 ms of the 1.66M PLY's load, on one core).
  BackgroundRelease release(options.num_threads > 1);
  auto bytes_owner = std::make_unique<FileBytes>();
  FileBytes& bytes = *bytes_owner;
  if (!bytes.Open(path, /*populate=*/options.num_threads == 1, &problem)) {
    return Fail(path, problem, error);
  }
  // The format's check first: OpenMesh's readers trust what they read.
  FormatCheck check;
  check.options = options;
  if (!format->check(bytes.view(), &check, &problem)) return Fail(path, problem, error);
  release.Release(std::move(bytes_owner));
  // Counted with the triangles dropped below.
  report->dropped_degenerate_faces = check.dropped_degenerate_faces;

  PolygonSoup soup;
  if (check.read_data) {
    soup = std::move(check.soup);
  } else if (!ReadWithOpenMesh(path, *format, std::move(check), &soup, &problem)) {
    return Fail(path, problem, error);
  }
  if (!SplitIntoTriangles(soup, options, mesh, &problem)) return Fail(path, problem, error);
  // Its memory back before the steps below take theirs.
  release.Release(std::make_unique<PolygonSoup>(std::move(soup)));
  if (format->weld_equal_positions) WeldExactDuplicates(mesh);

  DropDegenerateAndDuplicateFaces(options, mesh, report);
  const std::string dropped = DescribeDroppedFaces(*report);
  if (mesh->num_faces() == 0 && !dropped.empty()) {
    return Fail(path, "no face left after dropping " + dropped + "; need at least one triangle",
                error);
  }
  // The steps above leave every face id in range and no triangle that
  // repeats a vertex, so ValidateMesh (serial) is needed only for its
  // message when a face or a finite coordinate is missing.
  if ((mesh->num_faces() == 0 || !AllVerticesFinite(*mesh, options)) &&
      !ValidateMesh(*mesh, &problem)) {
    return Fail(path, problem, error);
  }
  if (!dropped.empty()) report->notice = path + ": dropped " + dropped;
  return true;
}

bool ReadMesh(const std::string& path, Mesh* mesh, MeshReadReport* report, std::string* error) {
  return ReadMesh(path, MeshReadOptions(), mesh, report, error);
}

bool ReadMesh(const std::string& path, Mesh* mesh, std::string* error) {
  MeshReadReport report;
  return ReadMesh(path, mesh, &report, error);
}

bool WriteMesh(const std::string& path, const Mesh& mesh, std::string* error) {
  const std::string extension = LowerExtension(path);
  const MeshFormat* format = FindFormat(extension, /*for_writing=*/true);
  if (format == nullptr) {
    return Fail(path, "cannot write format " + OtherFormatsHint(extension, /*for_writing=*/true),
                error);
  }
  std::string problem;
  if (!ValidateMesh(mesh, &problem)) return Fail(path, "refusing to write: " + problem, error);
  return WriteFileAtomically(
      path,
      [&mesh, format](std::ostream& out, std::string* write_error) {
        return WriteMeshFile(mesh, *format, out, write_error);
      },
      error);
}

}  // namespace msdeform
