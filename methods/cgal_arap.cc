#include "msdeform/methods/cgal_arap.h"

#include <chrono>
#include <cmath>
#include <limits>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_deformation.h>
#include <glog/logging.h>

#include "msdeform/core/timing.h"
#include "msdeform/methods/method_option_table.h"
#include "msdeform/methods/method_options.h"
#include "msdeform/methods/registry.h"

namespace msdeform {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using VertexIndex = SurfaceMesh::Vertex_index;
template <CGAL::Deformation_algorithm_tag kTag>
using Deformation =
    CGAL::Surface_mesh_deformation<SurfaceMesh, CGAL::Default, CGAL::Default, kTag>;

}  // namespace

struct CgalArap::Impl {
  SurfaceMesh mesh;
  // One of the two, by the variant.
  std::unique_ptr<Deformation<CGAL::ORIGINAL_ARAP>> original;
  std::unique_ptr<Deformation<CGAL::SRE_ARAP>> sre;
  std::vector<VertexIndex> handle;
  std::vector<Eigen::Vector3d> handle_rest;
  std::vector<int> handle_group;  // per entry of handle

  // Calls f with the deformation object, whichever variant it is.
  template <class F>
  void Visit(F&& f) {
    if (original != nullptr) {
      f(*original);
    } else {
      f(*sre);
    }
  }
};

bool CgalArapOptions::Check(std::string* error) const {
  // The table's ranges, named as MethodOptionTable() names the row.
  if (CgalArapOptionTable().CheckRanges(*this, error)) return true;
  *error = "cgal." + *error;
  return false;
}

CgalArap::CgalArap(ArapVariant variant) : variant_(variant) {}
CgalArap::~CgalArap() = default;

bool CgalArap::Init(const Mesh& mesh, const HandleLayout& layout, const std::vector<int>& roi,
                    const CgalArapOptions& options, std::string* error) {
  if (!options.Check(error)) return false;
  if (!ValidateHandles(layout, mesh.num_vertices(), error)) return false;
  const auto convert_start = std::chrono::steady_clock::now();
  impl_ = std::make_unique<Impl>();
  SurfaceMesh& sm = impl_->mesh;
  std::vector<VertexIndex> vertex(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    vertex[v] = sm.add_vertex(Point(mesh.vertices(0, v), mesh.vertices(1, v), mesh.vertices(2, v)));
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    if (sm.add_face(vertex[mesh.faces(0, f)], vertex[mesh.faces(1, f)],
                    vertex[mesh.faces(2, f)]) == SurfaceMesh::null_face()) {
      *error = "CGAL Surface_mesh rejects face " + std::to_string(f) +
               " (non-manifold or inconsistently oriented)";
      return false;
    }
  }
  convert_ms_ = MillisecondsSince(convert_start);

  const auto preprocess_start = std::chrono::steady_clock::now();
  if (variant_ == ArapVariant::kOriginal) {
    impl_->original = std::make_unique<Deformation<CGAL::ORIGINAL_ARAP>>(sm);
  } else {
    impl_->sre = std::make_unique<Deformation<CGAL::SRE_ARAP>>(sm);
    impl_->sre->set_sre_arap_alpha(options.sre_alpha);
  }
  bool ok = true;
  impl_->Visit([&](auto& deformation) {
    std::vector<char> in_roi(mesh.num_vertices(), roi.empty() ? 1 : 0);
    if (roi.empty()) {
      for (int v : layout.fixed) in_roi[v] = 0;
    } else {
      for (int v : roi) {
        if (v < 0 || v >= mesh.num_vertices()) {
          *error = "ROI vertex " + std::to_string(v) + " is out of range";
          ok = false;
        return;
        }
        in_roi[v] = 1;
      }
    }
    std::vector<VertexIndex> roi_vertices;
    for (int v = 0; v < mesh.num_vertices(); ++v)
      if (in_roi[v]) roi_vertices.push_back(vertex[v]);
    roi_size_ = static_cast<int>(roi_vertices.size());
    deformation.insert_roi_vertices(roi_vertices.begin(), roi_vertices.end());
    impl_->handle.clear();
    impl_->handle_rest.clear();
    impl_->handle_group.clear();
    for (int i = 0; i < static_cast<int>(layout.moveable.size()); ++i) {
      const int v = layout.moveable[i];
      if (!in_roi[v]) {
        *error = "handle vertex " + std::to_string(v) + " is not in the region of interest";
        ok = false;
        return;
      }
      deformation.insert_control_vertex(vertex[v]);
      impl_->handle.push_back(vertex[v]);
      impl_->handle_rest.push_back(mesh.vertices.col(v));
      impl_->handle_group.push_back(layout.group_of(i));
    }
    deformation.set_iterations(options.iterations);
    deformation.set_tolerance(options.tolerance);
    if (!deformation.preprocess()) {
      *error = "CGAL could not factorise the ARAP system (a ROI component without a fixed or "
               "control vertex?)";
      ok = false;
        return;
    }
  });
  if (!ok) return false;
  preprocess_ms_ = MillisecondsSince(preprocess_start);
  deformed_vertices_ = mesh.vertices;
  return true;
}

bool CgalArap::Drag(const HandleTransforms& deformed_from_rest, CgalArapStats* stats,
                    std::string* error) {
  if (impl_ == nullptr || (impl_->original == nullptr && impl_->sre == nullptr)) {
    *error = "CgalArap::Drag before a successful Init";
    return false;
  }
  Eigen::Matrix3Xd targets(3, impl_->handle.size());
  for (size_t h = 0; h < impl_->handle.size(); ++h) {
    targets.col(h) = deformed_from_rest[impl_->handle_group[h]] * impl_->handle_rest[h];
  }
  return DragTo(targets, stats, error);
}

bool CgalArap::DragTo(const Eigen::Matrix3Xd& targets, CgalArapStats* stats, std::string* error) {
  if (impl_ == nullptr || (impl_->original == nullptr && impl_->sre == nullptr)) {
    *error = "CgalArap::Drag before a successful Init";
    return false;
  }
  CHECK_EQ(targets.cols(), static_cast<Eigen::Index>(impl_->handle.size()));
  CgalArapStats local;
  CgalArapStats& frame = stats != nullptr ? *stats : local;
  const auto solve_start = std::chrono::steady_clock::now();
  for (size_t h = 0; h < impl_->handle.size(); ++h) {
    const Eigen::Vector3d target = targets.col(h);
    impl_->Visit([&](auto& deformation) {
      deformation.set_target_position(impl_->handle[h], Point(target.x(), target.y(), target.z()));
    });
  }
  impl_->Visit([](auto& deformation) { deformation.deform(); });
  frame.solve_ms = MillisecondsSince(solve_start);
  const auto copy_start = std::chrono::steady_clock::now();
  const SurfaceMesh& sm = impl_->mesh;
  for (VertexIndex v : sm.vertices()) {
    const Point& p = sm.point(v);
    deformed_vertices_.col(static_cast<int>(v)) << p.x(), p.y(), p.z();
  }
  frame.copy_ms = MillisecondsSince(copy_start);
  if (!deformed_vertices_.allFinite()) {
    *error = "CGAL ARAP produced non-finite positions";
    return false;
  }
  return true;
}

const Eigen::Matrix3Xd& CgalArapMethod::deformed_vertices() const {
  // Before SetHandles the CGAL copy does not exist yet: the rest pose.
  return arap_.deformed_vertices().cols() == mesh_.num_vertices() ? arap_.deformed_vertices()
                                                                 : mesh_.vertices;
}

bool CgalArapMethod::DoPrecompute(const Mesh& mesh, const MethodOptions& options,
                                  std::string* error) {
  if (!options.cgal.Check(error) || !ValidateMesh(mesh, error)) return false;
  mesh_ = mesh;
  options_ = options.cgal;
  return true;
}

bool CgalArapMethod::DoSetHandles(const HandleLayout& layout, std::string* error) {
  return arap_.Init(mesh_, layout, {}, options_, error);
}

bool CgalArapMethod::DoDrag(const HandleTransforms& deformed_from_rest, MethodStats* stats,
                            std::string* error) {
  const auto frame_start = std::chrono::steady_clock::now();
  CgalArapStats frame;
  if (!arap_.Drag(deformed_from_rest, &frame, error)) return false;
  FillStats(frame, frame_start, stats);
  return true;
}

bool CgalArapMethod::DoDragTo(const Eigen::Matrix3Xd& targets, MethodStats* stats,
                              std::string* error) {
  const auto frame_start = std::chrono::steady_clock::now();
  CgalArapStats frame;
  if (!arap_.DragTo(targets, &frame, error)) return false;
  FillStats(frame, frame_start, stats);
  return true;
}

void CgalArapMethod::FillStats(const CgalArapStats& frame,
                               std::chrono::steady_clock::time_point frame_start,
                               MethodStats* stats) const {
  *stats = MethodStats();
  stats->solve_ms = frame.solve_ms;
  stats->iterations = options_.iterations;
  stats->initial_cost = stats->final_cost = std::numeric_limits<double>::quiet_NaN();
  stats->converged = true;
  stats->frame_ms = MillisecondsSince(frame_start);
}

namespace {

MethodDescriptor CgalDescriptor(const std::string& name, ArapVariant variant,
                                const std::string& energy) {
  MethodDescriptor d;
  d.name = name;
  d.energy = energy;
  d.options = "cgal";
  d.add_option_rows = [](OptionTable<MethodOptions>* t) {
    t->Embed("cgal", &MethodOptions::cgal, CgalArapOptionTable());
  };
  d.create = [name, variant] { return std::make_unique<CgalArapMethod>(name, variant); };
  return d;
}

}  // namespace

MSDEFORM_REGISTER_METHODS(cgal_arap, registry) {
  registry->push_back(CgalDescriptor("cgal_arap", ArapVariant::kOriginal, "arap"));
  registry->push_back(
      CgalDescriptor("cgal_sr_arap", ArapVariant::kSmoothRotationEnhanced, "sr_arap"));
}

}  // namespace msdeform
