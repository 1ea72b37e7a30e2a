#include "solvers/conic/cones.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "solvers/error.h"

namespace bivo::solvers::conic {

int ConeSpec::dim() const {
  // Summed in 64 bits: dimensions that add up past 2^31 must not wrap to a valid row count.
  std::int64_t d = nonnegative;
  for (int m : soc) d += m;
  if (d > std::numeric_limits<int>::max()) {
    throw Error("cone: dimensions sum to " + std::to_string(d) + ", more than " +
                std::to_string(std::numeric_limits<int>::max()) + " rows");
  }
  return static_cast<int>(d);
}

double soc_det(const double* u, int m) {
  double n1 = 0.0;
  for (int i = 1; i < m; ++i) n1 += u[i] * u[i];
  n1 = std::sqrt(n1);
  return (u[0] - n1) * (u[0] + n1);
}

ConeProduct::ConeProduct(ConeSpec spec) : spec_(std::move(spec)) {
  if (spec_.nonnegative < 0) throw Error("cone: negative orthant dimension " + std::to_string(spec_.nonnegative));
  for (std::size_t k = 0; k < spec_.soc.size(); ++k) {
    if (spec_.soc[k] < 1) {
      throw Error("cone: second-order cone #" + std::to_string(k) + " has dimension " + std::to_string(spec_.soc[k]) +
                  " (must be >= 1)");
    }
  }
  dim_ = spec_.dim();  // throws when the sum does not fit an int
  int offset = spec_.nonnegative;
  for (int m : spec_.soc) {
    soc_offset_.push_back(offset);
    offset += m;
  }
}

double ConeProduct::min_eigenvalue(const Eigen::VectorXd& u) const {
  double m = std::numeric_limits<double>::infinity();
  for (int i = 0; i < spec_.nonnegative; ++i) m = std::min(m, u[i]);
  for (int k = 0; k < soc_count(); ++k) {
    const int p = soc_offset_[k], d = spec_.soc[k];
    m = std::min(m, u[p] - u.segment(p + 1, d - 1).norm());
  }
  return m;
}

void ConeProduct::add_identity(Eigen::VectorXd& u, double a) const {
  for (int i = 0; i < spec_.nonnegative; ++i) u[i] += a;
  for (int k = 0; k < soc_count(); ++k) u[soc_offset_[k]] += a;
}

Eigen::VectorXd ConeProduct::identity() const {
  Eigen::VectorXd e = Eigen::VectorXd::Zero(dim_);
  add_identity(e, 1.0);
  return e;
}

bool ConeProduct::interior(const Eigen::VectorXd& u) const {
  for (int i = 0; i < spec_.nonnegative; ++i) {
    if (!(u[i] > 0.0)) return false;
  }
  for (int k = 0; k < soc_count(); ++k) {
    const int p = soc_offset_[k];
    if (!(u[p] > 0.0) || !(soc_det(u.data() + p, spec_.soc[k]) > 0.0)) return false;
  }
  return true;
}

NtScaling ConeProduct::identity_scaling() const {
  NtScaling w;
  identity_scaling(w);
  return w;
}

void ConeProduct::identity_scaling(NtScaling& w) const {
  w.orthant_w.setOnes(spec_.nonnegative);
  w.soc.resize(soc_count());
  for (int k = 0; k < soc_count(); ++k) {
    SocScaling& sc = w.soc[k];
    sc.beta = 1.0;
    sc.wb.setZero(spec_.soc[k]);
    sc.wb[0] = 1.0;
    sc.q0 = 1.0;
    sc.q1_norm = 0.0;
    sc.cplus = 0.0;
    sc.cminus = 0.0;
  }
}

bool ConeProduct::compute_scaling(const Eigen::VectorXd& s, const Eigen::VectorXd& z, NtScaling& w,
                                  Eigen::VectorXd& lambda) const {
  const int l = spec_.nonnegative;
  w.orthant_w.resize(l);
  lambda.resize(dim_);
  for (int i = 0; i < l; ++i) {
    if (!(s[i] > 0.0) || !(z[i] > 0.0)) return false;
    w.orthant_w[i] = std::sqrt(s[i] / z[i]);
    lambda[i] = std::sqrt(s[i] * z[i]);
  }
  w.soc.resize(soc_count());
  for (int k = 0; k < soc_count(); ++k) {
    const int p = soc_offset_[k], m = spec_.soc[k];
    const double ds = soc_det(s.data() + p, m), dz = soc_det(z.data() + p, m);
    if (!(s[p] > 0.0) || !(z[p] > 0.0) || !(ds > 0.0) || !(dz > 0.0)) return false;
    const double rs = std::sqrt(ds), rz = std::sqrt(dz);
    // Normalized points sb = s/sqrt(det s), zb = z/sqrt(det z); NT point (sb + J zb)/(2 gamma).
    double dot = 0.0;
    for (int i = 0; i < m; ++i) dot += (s[p + i] / rs) * (z[p + i] / rz);
    const double gamma_nt = std::sqrt(std::max(0.5 * (1.0 + dot), 0.0));
    if (!(gamma_nt > 0.0)) return false;
    SocScaling& sc = w.soc[k];
    sc.beta = std::sqrt(std::sqrt(ds / dz));
    sc.wb.resize(m);
    sc.wb[0] = (s[p] / rs + z[p] / rz) / (2.0 * gamma_nt);
    for (int i = 1; i < m; ++i) sc.wb[i] = (s[p + i] / rs - z[p + i] / rz) / (2.0 * gamma_nt);
    // Restore det = 1 exactly (w0 = sqrt(1 + ||w1||^2)), then take the Jordan square root:
    // W^2 = beta^2 P(w), so W = beta P(w^{1/2}) with w^{1/2} = (w + e) / sqrt(2 (w0 + 1)).
    const double w0 = std::sqrt(1.0 + sc.wb.tail(m - 1).squaredNorm());
    const double root = std::sqrt(2.0 * (w0 + 1.0));
    sc.wb[0] = (w0 + 1.0) / root;
    sc.wb.tail(m - 1) /= root;
    const double n1sq = sc.wb.tail(m - 1).squaredNorm();
    // q = wb o wb = (||wb||^2, 2 wb0 wb1); det q = 1. Expansion coefficients (see header),
    // written without cancellation: q0 - 1 = ||q1||^2 / (q0 + 1), q0 - ||q1|| = 1/(q0 + ||q1||).
    sc.q0 = sc.wb[0] * sc.wb[0] + n1sq;
    sc.q1_norm = 2.0 * sc.wb[0] * std::sqrt(n1sq);
    const double nq = sc.q1_norm;
    const double sum_minus_one = nq * nq / (sc.q0 + 1.0) + nq;  // q0 + ||q1|| - 1
    sc.cplus = 0.5 * sum_minus_one * (sum_minus_one + 2.0);
    const double inv = 1.0 / (sc.q0 + nq);  // q0 - ||q1||
    sc.cminus = 0.5 * (sum_minus_one * inv) * (1.0 + inv);
  }
  // lambda = W z on the cones (in place: no buffer of the cone's size per iteration); the
  // orthant part keeps sqrt(s z), computed above, rather than W z = sqrt(s/z) z.
  apply_w(w, z, lambda);
  for (int i = 0; i < l; ++i) lambda[i] = std::sqrt(s[i] * z[i]);
  return true;
}

void ConeProduct::apply_w(const NtScaling& w, const Eigen::VectorXd& in, Eigen::VectorXd& out) const {
  out.resize(dim_);
  const int l = spec_.nonnegative;
  out.head(l) = w.orthant_w.cwiseProduct(in.head(l));
  for (int k = 0; k < soc_count(); ++k) {
    const int p = soc_offset_[k], m = spec_.soc[k];
    const SocScaling& sc = w.soc[k];
    // W x = beta (2 wb (wb^T x) - J x)
    const double t = 2.0 * sc.wb.dot(in.segment(p, m));
    out[p] = sc.beta * (t * sc.wb[0] - in[p]);
    for (int i = 1; i < m; ++i) out[p + i] = sc.beta * (t * sc.wb[i] + in[p + i]);
  }
}

void ConeProduct::apply_w_inverse(const NtScaling& w, const Eigen::VectorXd& in, Eigen::VectorXd& out) const {
  out.resize(dim_);
  const int l = spec_.nonnegative;
  out.head(l) = in.head(l).cwiseQuotient(w.orthant_w);
  for (int k = 0; k < soc_count(); ++k) {
    const int p = soc_offset_[k], m = spec_.soc[k];
    const SocScaling& sc = w.soc[k];
    // W^{-1} x = (2 J wb (wb^T J x) - J x) / beta
    double t = sc.wb[0] * in[p];
    for (int i = 1; i < m; ++i) t -= sc.wb[i] * in[p + i];
    t *= 2.0;
    out[p] = (t * sc.wb[0] - in[p]) / sc.beta;
    for (int i = 1; i < m; ++i) out[p + i] = (-t * sc.wb[i] + in[p + i]) / sc.beta;
  }
}

void ConeProduct::apply_w_squared(const NtScaling& w, const Eigen::VectorXd& in, Eigen::VectorXd& out) const {
  out.resize(dim_);
  const int l = spec_.nonnegative;
  for (int i = 0; i < l; ++i) out[i] = w.orthant_w[i] * w.orthant_w[i] * in[i];
  for (int k = 0; k < soc_count(); ++k) {
    const int p = soc_offset_[k], m = spec_.soc[k];
    const SocScaling& sc = w.soc[k];
    // W^2 x = beta^2 (2 q (q^T x) - J x), q = (q0, 2 wb0 wb1)
    const double two_wb0 = 2.0 * sc.wb[0];
    double t = sc.q0 * in[p];
    for (int i = 1; i < m; ++i) t += two_wb0 * sc.wb[i] * in[p + i];
    t *= 2.0;
    const double b2 = sc.beta * sc.beta;
    out[p] = b2 * (t * sc.q0 - in[p]);
    for (int i = 1; i < m; ++i) out[p + i] = b2 * (t * two_wb0 * sc.wb[i] + in[p + i]);
  }
}

void ConeProduct::jordan_product(const Eigen::VectorXd& u, const Eigen::VectorXd& v, Eigen::VectorXd& out) const {
  out.resize(dim_);
  const int l = spec_.nonnegative;
  out.head(l) = u.head(l).cwiseProduct(v.head(l));
  for (int k = 0; k < soc_count(); ++k) {
    const int p = soc_offset_[k], m = spec_.soc[k];
    const double u0 = u[p], v0 = v[p];
    out[p] = u.segment(p, m).dot(v.segment(p, m));
    for (int i = 1; i < m; ++i) out[p + i] = u0 * v[p + i] + v0 * u[p + i];
  }
}

void ConeProduct::jordan_divide(const Eigen::VectorXd& lambda, const Eigen::VectorXd& r, Eigen::VectorXd& out) const {
  out.resize(dim_);
  const int l = spec_.nonnegative;
  out.head(l) = r.head(l).cwiseQuotient(lambda.head(l));
  for (int k = 0; k < soc_count(); ++k) {
    const int p = soc_offset_[k], m = spec_.soc[k];
    const double l0 = lambda[p];
    const double det = soc_det(lambda.data() + p, m);
    double cross = 0.0;
    for (int i = 1; i < m; ++i) cross += lambda[p + i] * r[p + i];
    const double x0 = (l0 * r[p] - cross) / det;
    out[p] = x0;
    for (int i = 1; i < m; ++i) out[p + i] = (r[p + i] - x0 * lambda[p + i]) / l0;
  }
}

namespace {

// Smallest positive root of c + b a + q a^2 (c > 0), +infinity if none.
double first_positive_root(double q, double b, double c) {
  const double inf = std::numeric_limits<double>::infinity();
  if (q == 0.0) return b < 0.0 ? -c / b : inf;
  const double disc = b * b - 4.0 * q * c;
  if (disc < 0.0) return inf;  // no real root: det stays positive, u stays in K
  const double sq = std::sqrt(disc);
  // Stable roots: t = -(b + sign(b) sq)/2, roots t/q and c/t.
  const double t = -0.5 * (b + (b >= 0.0 ? sq : -sq));
  double best = inf;
  if (t != 0.0) {
    const double r1 = t / q, r2 = c / t;
    if (r1 > 0.0) best = std::min(best, r1);
    if (r2 > 0.0) best = std::min(best, r2);
  }
  return best;
}

}  // namespace

double ConeProduct::max_step(const Eigen::VectorXd& u, const Eigen::VectorXd& d) const {
  double a = std::numeric_limits<double>::infinity();
  for (int i = 0; i < spec_.nonnegative; ++i) {
    if (d[i] < 0.0) a = std::min(a, -u[i] / d[i]);
  }
  for (int k = 0; k < soc_count(); ++k) {
    const int p = soc_offset_[k], m = spec_.soc[k];
    if (m == 1) {
      if (d[p] < 0.0) a = std::min(a, -u[p] / d[p]);
      continue;
    }
    // det(u + a d) = det(u) + 2 a <u, J d> + a^2 det(d)
    const double c = soc_det(u.data() + p, m);
    const double q = soc_det(d.data() + p, m);
    double cross = u[p] * d[p];
    for (int i = 1; i < m; ++i) cross -= u[p + i] * d[p + i];
    a = std::min(a, first_positive_root(q, 2.0 * cross, c));
    // The head must stay positive too (the ray could cross into -K through the apex).
    if (d[p] < 0.0) a = std::min(a, -u[p] / d[p]);
  }
  return a;
}

}  // namespace bivo::solvers::conic
