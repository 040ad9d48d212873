// An experiment's edit: a mesh, its handle layout, an optional watch region
// and the drag path, from a scenario file under experiments/scenarios/ in the
// one format msdeform reads too (core/scenario.h, docs/formats.md): regions
// and a transform, or a .sel/.def pair.

#ifndef MSDEFORM_EXPERIMENTS_EXPERIMENT_SCENARIO_H_
#define MSDEFORM_EXPERIMENTS_EXPERIMENT_SCENARIO_H_

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"

namespace msdeform {

struct ExperimentScenario {
  std::string file;       // the entry itself
  std::string name;
  std::string mesh_path;  // resolved
  Mesh mesh;
  HandleLayout layout;
  bool has_watch = false;
  std::vector<int> watch;  // sorted, unique
  std::vector<HandleTransforms> path;  // one transform per frame; back() is the target
};

// Reads the entry at `path` and its mesh; `frames` > 0 overrides the entry's
// frame count, a non-empty `mesh_path` the entry's mesh (the same edit on a
// subdivided mesh, whose first vertices are the original's). False with one
// line naming the file on any error.
bool LoadExperimentScenario(const std::string& path, int frames, ExperimentScenario* scenario,
                            std::string* error, const std::string& mesh_path = "");

// The scenario files (*.json) of `folder`, in name order; false with
// "<folder>: <why>" when it cannot be listed.
bool ListScenarioFiles(const std::string& folder, std::vector<std::string>* files,
                       std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_EXPERIMENTS_EXPERIMENT_SCENARIO_H_
