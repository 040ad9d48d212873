// The reference as-rigid-as-possible deformation: CGAL's
// Surface_mesh_deformation (cotangent weights) on a CGAL::Surface_mesh copy of
// our mesh, with CGAL's ORIGINAL_ARAP (Sorkine & Alexa 2007; the method
// "cgal_arap") or SRE_ARAP (smoothed rotation enhanced ARAP, Levi & Gotsman
// 2015: the rotations of neighbouring cells are also kept close; "cgal_sr_arap").
//
//   CgalArap arap(ArapVariant::kOriginal);
//   arap.Init(mesh, layout, roi, options, &error);  // factorises the system
//   arap.Drag(deformed_from_rest, &stats);          // one frame, warm-started
//   arap.deformed_vertices();
//
// Fixed vertices (status 0 of a .sel) are left out of the region of interest,
// which CGAL holds at their rest positions; the moveable handle (status 2) is
// the set of control vertices. The ROI is every other vertex unless `roi` names
// it (a .sel's status 1 and 2). CGAL itself is compiled only in cgal_arap.cc.

#ifndef MSDEFORM_METHODS_CGAL_ARAP_H_
#define MSDEFORM_METHODS_CGAL_ARAP_H_

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"
#include "msdeform/methods/method.h"

namespace msdeform {

struct CgalArapOptions {
  // Local/global iterations per deform() call, i.e. per drag frame (issue 6: 20).
  int iterations = 20;
  // CGAL's relative energy tolerance; 0 runs all iterations.
  double tolerance = 0.0;

  // SR-ARAP's rotation smoothing weight (CGAL's set_sre_arap_alpha; its
  // default 0.02, used for meshes scaled to a unit bounding box).
  double sre_alpha = 0.02;

  bool Check(std::string* error) const;
};

enum class ArapVariant { kOriginal, kSmoothRotationEnhanced };

struct CgalArapStats {
  double solve_ms = 0.0;  // set targets + deform()
  double copy_ms = 0.0;   // positions back into deformed_vertices()
};

class CgalArap {
 public:
  explicit CgalArap(ArapVariant variant = ArapVariant::kOriginal);
  ~CgalArap();

  // `roi`: the free vertices plus the handle (sorted, unique); empty means
  // every vertex that is not fixed. Fails on an invalid layout, a handle
  // vertex outside the ROI, or a system CGAL cannot factorise.
  bool Init(const Mesh& mesh, const HandleLayout& layout, const std::vector<int>& roi,
            const CgalArapOptions& options, std::string* error);

  // Moves every handle vertex to deformed_from_rest[its group] * (its rest position)
  // and runs the iterations, starting from the previous frame.
  bool Drag(const HandleTransforms& deformed_from_rest, CgalArapStats* stats, std::string* error);
  // The same with every handle vertex's target given (3 by #moveable, in the
  // layout's moveable order).
  bool DragTo(const Eigen::Matrix3Xd& targets, CgalArapStats* stats, std::string* error);

  const Eigen::Matrix3Xd& deformed_vertices() const { return deformed_vertices_; }
  int roi_size() const { return roi_size_; }
  // Milliseconds of Init: mesh conversion, and CGAL's preprocess()
  // (Laplacian assembly and its factorisation).
  double convert_ms() const { return convert_ms_; }
  double preprocess_ms() const { return preprocess_ms_; }

 private:
  struct Impl;
  ArapVariant variant_;
  std::unique_ptr<Impl> impl_;
  Eigen::Matrix3Xd deformed_vertices_;
  int roi_size_ = 0;
  double convert_ms_ = 0.0;
  double preprocess_ms_ = 0.0;
};

// CgalArap through the one interface (methods/method.h): Precompute keeps the
// mesh, SetHandles converts it and factorises (ROI = every non-fixed vertex),
// each Drag runs options.cgal.iterations iterations. nodes_optimized = ROI
// vertices, variables = 3 per ROI vertex, setup_ms = conversion +
// factorisation; no energy (final_cost NaN).
class CgalArapMethod : public EditingMethod {
 public:
  CgalArapMethod(const std::string& name, ArapVariant variant)
      : EditingMethod(name), arap_(variant) {}

  const Eigen::Matrix3Xd& deformed_vertices() const override;
  int nodes_optimized() const override { return arap_.roi_size(); }
  int variables() const override { return 3 * arap_.roi_size(); }
  double precompute_ms() const override { return 0.0; }
  double setup_ms() const override { return arap_.convert_ms() + arap_.preprocess_ms(); }
  bool takes_vertex_targets() const override { return true; }

 protected:
  bool DoPrecompute(const Mesh& mesh, const MethodOptions& options, std::string* error) override;
  bool DoSetHandles(const HandleLayout& layout, std::string* error) override;
  bool DoDrag(const HandleTransforms& deformed_from_rest, MethodStats* stats,
              std::string* error) override;
  bool DoDragTo(const Eigen::Matrix3Xd& targets, MethodStats* stats, std::string* error) override;

 private:
  void FillStats(const CgalArapStats& frame, std::chrono::steady_clock::time_point frame_start,
                 MethodStats* stats) const;

  CgalArap arap_;
  Mesh mesh_;
  CgalArapOptions options_;
};

}  // namespace msdeform

#endif  // MSDEFORM_METHODS_CGAL_ARAP_H_
