// Inputs shared by the benchmarks: the real meshes of data/meshes/ and the
// default claw drag (data/scenarios/armadillo_claw.json) applied to any of
// the armadillo sizes. Each is loaded once per process; a missing file stops
// the benchmark with a message saying how to make it (never a silent skip).

#ifndef MSDEFORM_BENCH_BENCH_DATA_H_
#define MSDEFORM_BENCH_BENCH_DATA_H_

#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <glog/logging.h>

#include "msdeform/core/build_info.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/core/scenario.h"

namespace msdeform {

// data/meshes/<name>.off, or data/meshes/<name> when the name has an
// extension (armadillo_1664k.ply).
inline Mesh ReadBenchMeshOrDie(const std::string& name) {
  const std::string path =
      DataDir() + "/meshes/" + name + (name.find('.') == std::string::npos ? ".off" : "");
  Mesh mesh;
  std::string error;
  CHECK(ReadMesh(path, &mesh, &error))
      << error << " (run data/fetch_meshes.sh, then msdeform_make_large for the large meshes)";
  return mesh;
}

// The default claw drag on data/meshes/<name>.off (armadillo, armadillo_104k,
// armadillo_416k share vertex ids, so the same scenario applies).
struct ClawEdit {
  Mesh mesh;
  HandleLayout layout;
  std::vector<HandleTransforms> path;  // one transform per frame
};

inline const ClawEdit& LoadClawEdit(const std::string& name) {
  static auto* edits = new std::map<std::string, ClawEdit>;
  auto found = edits->find(name);
  if (found != edits->end()) return found->second;
  ClawEdit& edit = (*edits)[name];
  std::string error;
  Scenario scenario;
  CHECK(ReadScenario(DataDir() + "/scenarios/armadillo_claw.json", &scenario,
                     &error))
      << error;
  edit.mesh = ReadBenchMeshOrDie(name);
  std::vector<int> watch;
  HandleTransforms deformed_from_rest;
  CHECK(ResolveScenario(scenario, edit.mesh, &edit.layout, &watch, &deformed_from_rest, &error))
      << error;
  edit.path = DragPath(scenario, edit.mesh, edit.layout);
  return edit;
}

}  // namespace msdeform

#endif  // MSDEFORM_BENCH_BENCH_DATA_H_
