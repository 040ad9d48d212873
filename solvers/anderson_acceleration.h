// Anderson acceleration of a fixed-point iteration x <- G(x) (Walker & Ni
// 2011), in the form Peng, Deng, Zhang and Liu use for local/global geometry
// solvers ("Anderson Acceleration for Geometry Optimization and Physics
// Simulation", SIGGRAPH 2018). With f = G(x) - x and the differences of the
// last m iterates, dF_j = f_{j+1} - f_j and dG_j = G(x_{j+1}) - G(x_j),
//   theta = argmin |f_k - dF theta|^2,   x_{k+1} = G(x_k) - dG theta.
// With m = 0 (or an empty history) x_{k+1} = G(x_k), the plain iteration.
//
// The accelerator knows nothing of the energy: a caller that minimises one
// keeps the safeguard (Peng et al., Alg. 2): evaluate the energy at the
// accelerated iterate, and where it is not below the previous iterate's take
// the plain step G(x_k) instead and Reset() the history.
//
//   AndersonAcceleration anderson(x.size(), /*window=*/5);
//   for (...) {
//     g = G(x);
//     anderson.Compute(x, g, &x);  // x <- accelerated G(x)
//   }
//
// Deterministic: the same sequence of calls gives the same iterates on any
// number of threads (the dot products are summed in a fixed order).

#ifndef MSDEFORM_SOLVERS_ANDERSON_ACCELERATION_H_
#define MSDEFORM_SOLVERS_ANDERSON_ACCELERATION_H_

#include <Eigen/Core>

namespace msdeform {

class AndersonAcceleration {
 public:
  // `dimension`: the length of x; `window`: m, the number of differences kept
  // (0: the plain iteration). Memory: 2 m + 2 vectors of `dimension` doubles.
  AndersonAcceleration(int dimension, int window);

  // From the iterate x_k and g = G(x_k), writes the next iterate to *next
  // (which may alias x). x and g must have `dimension` entries.
  void Compute(const Eigen::VectorXd& x, const Eigen::VectorXd& g, Eigen::VectorXd* next);

  // Forgets the history: the next Compute returns G(x) itself.
  void Reset() {
    history_ = 0;
    newest_ = -1;
    has_previous_ = false;
  }

  int window() const { return window_; }
  // Differences held now (0 to window).
  int history() const { return history_; }

 private:
  int dimension_;
  int window_;
  int history_ = 0;  // columns of delta_f_ / delta_g_ in use
  int newest_ = -1;  // the column written last (a ring buffer)
  Eigen::MatrixXd delta_f_;  // dimension by window
  Eigen::MatrixXd delta_g_;  // dimension by window
  Eigen::MatrixXd gram_;     // window by window: delta_f_^T delta_f_
  Eigen::VectorXd previous_f_;
  Eigen::VectorXd previous_g_;
  bool has_previous_ = false;
};

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_ANDERSON_ACCELERATION_H_
