// The mesh's own as-rigid-as-possible energy (Sorkine & Alexa 2007) minimised
// by local/global iterations, with Anderson acceleration (solvers/
// anderson_acceleration.h) and its energy safeguard: the reference every
// method's quality is measured against, and the method "full_arap".
//
// The energy is the one core/metrics.h measures (ArapEnergyPerVertex and
// NormalisedArapEnergy): one rotation per vertex, cotangent weights
// (core/cotangent_weights.h), every spoke of every vertex,
//   E(x) = min_R sum_i sum_{k in N(i)} w_ik |(x_i - x_k) - R_i (r_i - r_k)|^2
//          / sum_i sum_{k in N(i)} w_ik |r_i - r_k|^2,
// r the rest positions. The constrained vertices (handles and fixed) are held
// exactly at their targets; every other vertex that reaches a constrained one
// through edges of positive weight is free; the rest (a part of the mesh no
// constraint reaches) stays where it is, since nothing pins its position.
//
//   LocalGlobalArap arap;
//   arap.Setup(mesh, constrained, options, &error);  // factorises, once per layout
//   arap.Solve(targets, &deformed);                  // per frame, warm-started
//
// Local step: R_i = the rotation maximising tr(R^T S_i), S_i = sum_k w_ik
// (x_i - x_k)(r_i - r_k)^T, exact to rounding (a scaled Newton polar
// iteration, the SVD for a flat one-ring). Global step: L x_free = b with L
// the cotangent Laplacian of the free vertices (factorised once) and
//   b_i = sum_k w_ik / 2 (R_i + R_k)(r_i - r_k) + sum_{k constrained} w_ik x_k.
// Each iteration costs one local step, one right-hand side and three
// triangular solve pairs, on `num_threads` (the local step and the right-hand
// side in fixed chunks, the solves one coordinate a thread), so the result is
// the same on any number of threads. A frame stops when a plain (not
// accelerated) step lowers the energy by at most the relative tolerance.

#ifndef MSDEFORM_SOLVERS_LOCAL_GLOBAL_ARAP_H_
#define MSDEFORM_SOLVERS_LOCAL_GLOBAL_ARAP_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msdeform/core/mesh.h"
#include "msdeform/core/option_table.h"

namespace msdeform {

struct LocalGlobalArapOptions {
  // Stop when an iteration lowers the energy by at most this fraction of it,
  // (E_prev - E) <= relative_tolerance E_prev. The default is tight enough
  // for a reference (the energy is then within about 1e-6 of its minimum on
  // the tables' edits).
  double relative_tolerance = 1e-9;
  // Iterations per Solve at most (each one local and one global step).
  int max_iterations = 10000;
  // Anderson window m: the number of past iterates combined; 0 runs the plain
  // local/global iteration.
  int anderson_window = 5;
  // Threads of the local step, the right-hand side and the three solves (at
  // least 1; passes over fewer than 16,384 items run on one).
  int num_threads = 1;
  // The sparse Cholesky factor of the free vertices' Laplacian. kSimplicial
  // is Eigen's SimplicialLLT with AMD ordering, the three coordinates solved
  // one a thread; kCholmod is CHOLMOD's supernodal LLT with its own choice of
  // ordering (METIS nested dissection where AMD fills too much), the three
  // coordinates solved in one pass. kAuto takes kCholmod from
  // kCholmodFromFreeVertices free vertices: at 371K both factorise in about
  // 4 s, at 1.66M CHOLMOD takes 28.5 s and SimplicialLLT had not finished
  // after 23 minutes (docs/decisions/full-arap.md). Without CHOLMOD in the
  // build kAuto is kSimplicial and Check refuses kCholmod.
  enum class Factorization { kAuto, kSimplicial, kCholmod };
  static constexpr int kCholmodFromFreeVertices = 500000;
  Factorization factorization = Factorization::kAuto;

  // Messages name the field ("relative_tolerance must be >= 0").
  bool Check(std::string* error) const;
};

// "auto", "simplicial", "cholmod".
const EnumNames<LocalGlobalArapOptions::Factorization>& LocalGlobalArapFactorizationNames();

struct LocalGlobalArapSummary {
  int iterations = 0;        // global steps taken
  int rejected = 0;          // accelerated steps the safeguard replaced by the plain one
  double initial_energy = 0.0;  // E at the warm start (targets applied)
  double final_energy = 0.0;
  bool converged = false;       // a plain step's decrease met the tolerance (not max_iterations,
                                // not a non-finite start)
  bool stopped = false;         // Solve's `stop` ended it before convergence
  // The energy after each iteration (entry 0: the initial energy) and the
  // milliseconds since Solve began.
  std::vector<double> energy_trace;
  std::vector<double> ms_trace;
};

class LocalGlobalArap {
 public:
  LocalGlobalArap();
  ~LocalGlobalArap();
  LocalGlobalArap(const LocalGlobalArap&) = delete;
  LocalGlobalArap& operator=(const LocalGlobalArap&) = delete;

  // `constrained`: the vertices held at targets (sorted, unique, in range).
  // Builds the Laplacian of the free vertices and factorises it. False with a
  // message on bad options or indices; the solver is then empty.
  bool Setup(const Mesh& rest, const std::vector<int>& constrained,
             const LocalGlobalArapOptions& options, std::string* error);

  // Holds constrained[j] at targets.col(j) (3 by #constrained) and minimises
  // the energy over the free vertices from *deformed (3 by #V; the warm
  // start, the result on return; columns of vertices no constraint reaches
  // are left as they are). `stop`, when given, is asked before each
  // iteration with the iterations taken and the milliseconds since Solve
  // began; true ends the solve there with the last accepted iterate (a budget
  // or a cancellation: methods/polish.h). Without it the result is the same.
  LocalGlobalArapSummary Solve(
      const Eigen::Matrix3Xd& targets, Eigen::Matrix3Xd* deformed,
      const std::function<bool(int iterations, double ms)>& stop = nullptr);

  // E(deformed) as above (per-vertex best rotations by the same local step,
  // without changing the solver's warm-start rotations).
  double Energy(const Eigen::Matrix3Xd& deformed) const;

  int num_free() const;
  int num_vertices() const;
  const LocalGlobalArapOptions& options() const;
  // Milliseconds of Setup: the Laplacian and its factorisation.
  double setup_ms() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_LOCAL_GLOBAL_ARAP_H_
