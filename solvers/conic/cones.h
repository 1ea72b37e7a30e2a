#pragma once
// The cone K = R^l_+ x Q^{m_1} x ... x Q^{m_k} of the conic IPM, behind one small
// interface: membership, Nesterov-Todd scaling, Jordan algebra, step to the boundary.
// Second-order cone Q^m = {(u0, u1) : u0 >= ||u1||}. Determinants are always formed as
// (u0 - ||u1||)(u0 + ||u1||), never as u0^2 - ||u1||^2, because the latter loses all
// significant digits near the boundary once ||u1||^2 sums ~1e5 terms.
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace bivo::solvers::conic {

struct ConeSpec {
  int nonnegative = 0;   // dimension l of the orthant (rows first in G, h)
  std::vector<int> soc;  // second-order cone dimensions, each >= 1, in row order
  int dim() const;       // sum of all dimensions; bivo::Error when it exceeds INT_MAX
  int degree() const { return nonnegative + static_cast<int>(soc.size()); }
};

// Nesterov-Todd scaling W (symmetric, W z = W^{-1} s = lambda). Orthant: W = diag(sqrt(s/z)).
// SOC: W = beta (2 wb wb^T - J), J = diag(1, -I), det(wb) = 1, wb the Jordan square root
// of the normalized NT point q; then
//   W^2 = beta^2 (2 q q^T - J), q = wb o wb,
// which the KKT system expands sparsely on the eigenvectors f = (1, qh), g = (1, -qh) of its
// 2-d active block (qh = q1/||q1||):
//   W^2 = beta^2 (I + c+ f f^T - c- g g^T),
//   c+ = ((q0 + ||q1||)^2 - 1)/2,  c- = (1 - (q0 - ||q1||)^2)/2 in [0, 1/2).
// D = I keeps every z pivot at -beta^2 (no tiny pivots that would blow up the fill) and
// I - c- g g^T > 0, so the expanded matrix stays quasi-definite.
struct SocScaling {
  double beta = 1.0;
  Eigen::VectorXd wb;  // normalized NT point, det = 1
  double q0 = 1.0;     // q = wb o wb = (q0, q1), q1 = 2 wb0 wb1
  double q1_norm = 0.0;
  double cplus = 0.0, cminus = 0.0;
};

struct NtScaling {
  Eigen::VectorXd orthant_w;  // sqrt(s/z)
  std::vector<SocScaling> soc;
};

class ConeProduct {
 public:
  explicit ConeProduct(ConeSpec spec);

  const ConeSpec& spec() const { return spec_; }
  int dim() const { return dim_; }
  int degree() const { return spec_.degree(); }
  int soc_count() const { return static_cast<int>(spec_.soc.size()); }
  int soc_offset(int k) const { return soc_offset_[k]; }

  // Smallest "eigenvalue" over all cones: u_i (orthant), u0 - ||u1|| (SOC).
  double min_eigenvalue(const Eigen::VectorXd& u) const;
  // u += a e, e the identity (ones on the orthant, (1, 0) on each SOC).
  void add_identity(Eigen::VectorXd& u, double a) const;
  Eigen::VectorXd identity() const;
  // Strictly inside K (every determinant positive).
  bool interior(const Eigen::VectorXd& u) const;

  NtScaling identity_scaling() const;
  void identity_scaling(NtScaling& w) const;  // into w's buffers
  // Computes the NT scaling of the pair (s, z) and lambda = W z; false if either leaves int K.
  bool compute_scaling(const Eigen::VectorXd& s, const Eigen::VectorXd& z, NtScaling& w, Eigen::VectorXd& lambda) const;
  void apply_w(const NtScaling& w, const Eigen::VectorXd& in, Eigen::VectorXd& out) const;
  void apply_w_inverse(const NtScaling& w, const Eigen::VectorXd& in, Eigen::VectorXd& out) const;
  void apply_w_squared(const NtScaling& w, const Eigen::VectorXd& in, Eigen::VectorXd& out) const;

  // Jordan product u o v and its inverse: x such that lambda o x = r.
  void jordan_product(const Eigen::VectorXd& u, const Eigen::VectorXd& v, Eigen::VectorXd& out) const;
  void jordan_divide(const Eigen::VectorXd& lambda, const Eigen::VectorXd& r, Eigen::VectorXd& out) const;

  // Largest a with u + a d in K (u interior); +infinity when the ray never leaves K.
  double max_step(const Eigen::VectorXd& u, const Eigen::VectorXd& d) const;

 private:
  ConeSpec spec_;
  int dim_ = 0;
  std::vector<int> soc_offset_;
};

// (u0 - ||u1||)(u0 + ||u1||) for a SOC block of size m starting at p.
double soc_det(const double* u, int m);

}  // namespace bivo::solvers::conic
