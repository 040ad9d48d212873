// The bodies of the libFuzzer targets (tests/fuzz/*_fuzzer.cc), shared with
// fuzz_regression_test.cc, which replays every saved input through them in
// the normal test suite. Each takes arbitrary bytes, hands them to one parser
// through a file (the parsers read files), and checks that a parser that
// accepts the input returns something consistent.

#ifndef MSDEFORM_TESTS_FUZZ_FUZZ_TARGETS_H_
#define MSDEFORM_TESTS_FUZZ_FUZZ_TARGETS_H_

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <Eigen/Geometry>

#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/core/procedural_meshes.h"
#include "msdeform/core/scenario.h"

namespace msdeform {
namespace fuzz {

// Writes the bytes to a per-process file with the given extension and
// returns its path. The file is reused by every call.
inline std::string WriteInput(const uint8_t* data, size_t size, const std::string& extension) {
  const char* folder = std::getenv("TMPDIR");
  const std::string path = std::string(folder != nullptr ? folder : "/tmp") + "/msdeform_fuzz_" +
                           std::to_string(::getpid()) + extension;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

// Aborts (so that libFuzzer reports it) when a claimed success is broken.
inline void Require(bool condition, const char* what) {
  if (!condition) {
    std::fprintf(stderr, "fuzz target invariant broken: %s\n", what);
    std::abort();
  }
}

inline bool OneLine(const std::string& error) {
  return !error.empty() && error.find('\n') == std::string::npos;
}

inline void FuzzSel(const uint8_t* data, size_t size) {
  const std::string path = WriteInput(data, size, ".sel");
  for (int num_vertices : {0, 1, 7, 100}) {
    HandleLayout layout;
    std::string error;
    if (ReadSel(path, num_vertices, &layout, &error)) {
      Require(ValidateHandles(layout, num_vertices, &error), "ReadSel returned an invalid layout");
    } else {
      Require(OneLine(error), "ReadSel error not one line");
    }
  }
  std::remove(path.c_str());
}

inline void FuzzDef(const uint8_t* data, size_t size) {
  const std::string path = WriteInput(data, size, ".def");
  Eigen::Affine3d transform;
  std::string error;
  if (ReadDef(path, &transform, &error)) {
    Require(transform.matrix().allFinite(), "ReadDef returned a non-finite matrix");
  } else {
    Require(OneLine(error), "ReadDef error not one line");
  }
  std::remove(path.c_str());
}

inline void FuzzScenario(const uint8_t* data, size_t size) {
  const std::string path = WriteInput(data, size, ".json");
  Scenario scenario;
  std::string error;
  if (ReadScenario(path, &scenario, &error)) {
    // Resolve against a small mesh instead of the file the scenario names.
    static const Mesh* const mesh = new Mesh(MakeBar(4, 1.0, 1));
    HandleLayout layout;
    std::vector<int> watch;
    HandleTransforms transform;
    if (ResolveScenario(scenario, *mesh, &layout, &watch, &transform, &error)) {
      Require(ValidateHandles(layout, mesh->num_vertices(), &error), "invalid resolved layout");
      Require(transform.CheckFinite(&error), "non-finite scenario transform");
      if (scenario.frames <= 1000) {
        for (const HandleTransforms& frame : DragPath(scenario, *mesh, layout)) {
          Require(frame.CheckFinite(&error), "non-finite drag path");
        }
      }
    } else {
      Require(OneLine(error), "ResolveScenario error not one line");
    }
  } else {
    Require(OneLine(error), "ReadScenario error not one line");
  }
  std::remove(path.c_str());
}

// `extension` is ".off" or ".obj" (or any format ReadMesh takes).
inline void FuzzMesh(const uint8_t* data, size_t size, const std::string& extension) {
  const std::string path = WriteInput(data, size, extension);
  Mesh mesh;
  MeshReadReport report;
  std::string error;
  if (ReadMesh(path, &mesh, &report, &error)) {
    Require(ValidateMesh(mesh, &error), "ReadMesh returned an invalid mesh");
    const bool dropped = report.dropped_degenerate_faces > 0 || report.dropped_duplicate_faces > 0;
    Require(report.dropped_degenerate_faces >= 0 && report.dropped_duplicate_faces >= 0,
            "negative dropped-face count");
    Require(dropped ? OneLine(report.notice) : report.notice.empty(),
            "dropped-face notice not one line, or given when nothing was dropped");
  } else {
    Require(OneLine(error), "ReadMesh error not one line");
  }
  std::remove(path.c_str());
}

}  // namespace fuzz
}  // namespace msdeform

#endif  // MSDEFORM_TESTS_FUZZ_FUZZ_TARGETS_H_
