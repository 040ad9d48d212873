// msdeform_make_large: makes the generated meshes of data/meshes/: the large
// armadillo variants used for scaling work, by Loop subdivision of
// data/meshes/armadillo.off (26K vertices),
//   armadillo_104k.off  1 step,  #V + #E          = 104,002 vertices
//   armadillo_416k.off  2 steps, 104,002 + 312,000 = 416,002 vertices
// and with --huge, for bench/scaling_table.sh, from armadillo_416k.off as read
// (binary PLY, exact doubles),
//   armadillo_1664k.ply 3 steps, 1,664,002 vertices
//   armadillo_6656k.ply 4 steps, 6,656,002 vertices
// (input vertex ids are kept first, so selections on the original still
// apply; run data/fetch_meshes.sh first), and the capped cylinder of the
// Botsch-Sorkine bending test (experiments/scenarios/cylinder_bend.json),
//   cylinder.off        radius 1, height 10, 64 segments, 118 rings = 8,322 vertices
// (core/procedural_meshes.h, MakeCylinder). Each output is written
// atomically, and only when missing (--force remakes them).

#include <chrono>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include <gflags/gflags.h>
#include <glog/logging.h>

#include "msdeform/core/build_info.h"
#include "msdeform/core/main_guard.h"
#include "msdeform/core/mesh.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/core/procedural_meshes.h"
#include "msdeform/core/subdivide.h"

DEFINE_string(mesh_dir, "",
              "Folder holding armadillo.off (from data/fetch_meshes.sh); the large "
              "variants and cylinder.off are written next to it. Default: data/meshes of the "
              "source tree (core/build_info.h, DataDir).");
DEFINE_bool(force, false,
            "Remake the meshes even when their files already exist.");
DEFINE_bool(huge, false,
            "Also the scaling meshes of bench/scaling_table.sh: armadillo_416k.off Loop-subdivided "
            "once (armadillo_1664k.ply, 1,664,002 vertices) and twice (armadillo_6656k.ply, "
            "6,656,002 vertices), as binary PLY (about 83 MB and 333 MB).");

namespace msdeform {
namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool FileExists(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) return false;
  std::fclose(file);
  return true;
}

// The cylinder: a bar of aspect 10 (as Botsch & Sorkine's), its side edge
// 2 pi / 64 = 0.098 well below the lattice cell diagonal / 48 = 0.22 (the
// bounding-box diagonal is sqrt(2^2 + 2^2 + 10^2) = 10.4), and its rows
// 10 / 118 = 0.085 apart, sqrt(3) / 2 of the edge: near-equilateral triangles.
constexpr double kCylinderRadius = 1.0;
constexpr double kCylinderHeight = 10.0;
constexpr int kCylinderSegments = 64;
constexpr int kCylinderRings = 118;

int MakeCylinderFile() {
  const std::string output = FLAGS_mesh_dir + "/cylinder.off";
  if (!FLAGS_force && FileExists(output)) {
    std::printf("msdeform_make_large: %s exists; nothing to do (--force remakes it)\n",
                output.c_str());
    return 0;
  }
  const auto start = std::chrono::steady_clock::now();
  const Mesh cylinder =
      MakeCylinder(kCylinderRadius, kCylinderHeight, kCylinderSegments, kCylinderRings);
  std::string error;
  if (!WriteMesh(output, cylinder, &error)) {
    std::fprintf(stderr, "msdeform_make_large: %s\n", error.c_str());
    return 1;
  }
  std::printf("msdeform_make_large: wrote %s: %d vertices, %d faces (%.2f s)\n", output.c_str(),
              cylinder.num_vertices(), cylinder.num_faces(), SecondsSince(start));
  return 0;
}

// Loop-subdivides `mesh` one step per output (in double precision, each step
// on the last) and writes each result; 0 or 1 as the program's exit code.
int SubdivideAndWrite(Mesh mesh, const std::vector<std::string>& outputs) {
  std::string error;
  for (const std::string& output : outputs) {
    auto start = std::chrono::steady_clock::now();
    Mesh finer;
    if (!LoopSubdivide(mesh, 1, &finer, &error)) {
      std::fprintf(stderr, "msdeform_make_large: cannot subdivide: %s\n", error.c_str());
      return 1;
    }
    const double subdivide_seconds = SecondsSince(start);
    start = std::chrono::steady_clock::now();
    if (!WriteMesh(output, finer, &error)) {
      std::fprintf(stderr, "msdeform_make_large: %s\n", error.c_str());
      return 1;
    }
    std::printf(
        "msdeform_make_large: wrote %s: %d vertices, %d faces (subdivide %.2f s, write %.2f s)\n",
        output.c_str(), finer.num_vertices(), finer.num_faces(), subdivide_seconds,
        SecondsSince(start));
    mesh = std::move(finer);
  }
  return 0;
}

// Reads data/meshes/`input` and writes `outputs` (one Loop step each, each
// on the last), unless they all exist.
int MakeSubdivided(const std::string& input, const std::vector<std::string>& outputs) {
  bool all_exist = !FLAGS_force;
  for (const std::string& output : outputs) all_exist &= FileExists(FLAGS_mesh_dir + "/" + output);
  if (all_exist) {
    std::printf("msdeform_make_large: %s exist in %s; nothing to do (--force remakes them)\n",
                (outputs[0] + " and " + outputs[1]).c_str(), FLAGS_mesh_dir.c_str());
    return 0;
  }
  const auto start = std::chrono::steady_clock::now();
  Mesh mesh;
  std::string error;
  if (!ReadMesh(FLAGS_mesh_dir + "/" + input, &mesh, &error)) {
    std::fprintf(stderr, "msdeform_make_large: %s (run data/fetch_meshes.sh first)\n",
                 error.c_str());
    return 1;
  }
  std::printf("msdeform_make_large: read %s: %d vertices, %d faces (%.2f s)\n", input.c_str(),
              mesh.num_vertices(), mesh.num_faces(), SecondsSince(start));
  std::vector<std::string> paths;
  for (const std::string& output : outputs) paths.push_back(FLAGS_mesh_dir + "/" + output);
  return SubdivideAndWrite(std::move(mesh), paths);
}

int Run() {
  const int armadillo = MakeSubdivided("armadillo.off", {"armadillo_104k.off", "armadillo_416k.off"});
  const int cylinder = MakeCylinderFile();
  // The scaling meshes: one and two more steps on the 416K armadillo as read
  // from its file (the recipe of the scaling benchmark), binary PLY.
  const int huge = armadillo == 0 && FLAGS_huge
                       ? MakeSubdivided("armadillo_416k.off",
                                        {"armadillo_1664k.ply", "armadillo_6656k.ply"})
                       : 0;
  return armadillo != 0 ? armadillo : cylinder != 0 ? cylinder : huge;
}

}  // namespace
}  // namespace msdeform

// The program; main() below adds the out-of-memory report.
static int Main(int argc, char** argv) {
  gflags::SetUsageMessage(
      "Writes armadillo_104k.off and armadillo_416k.off (Loop subdivision of "
      "armadillo.off) and cylinder.off (a capped cylinder) into --mesh_dir; with --huge also "
      "armadillo_1664k.ply and armadillo_6656k.ply.");
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  if (FLAGS_mesh_dir.empty()) FLAGS_mesh_dir = msdeform::DataDir() + "/meshes";
  google::InitGoogleLogging(argv[0]);
  FLAGS_logtostderr = true;
  return msdeform::Run();
}

// Out of memory ends the run with one line and exit 1 (core/main_guard.h).
int main(int argc, char** argv) {
  return msdeform::RunReportingOutOfMemory("msdeform_make_large", Main, argc, argv);
}
