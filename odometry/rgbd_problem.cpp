#include "odometry/rgbd_problem.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "odometry/affine_brightness.h"
#include "odometry/kernels/kernels.h"
#include "odometry/residual_definition.h"
#include "solvers/error.h"
#include "solvers/geometry/se3.h"

namespace bivo::odometry {
namespace {

// Where a Jacobian kind takes its image gradients from (kMethodDefault is resolved earlier).
GradientSource gradient_source(JacobianKind kind) {
  return kind == JacobianKind::kForward   ? GradientSource::kCurrent
         : kind == JacobianKind::kInverse ? GradientSource::kReference
                                          : GradientSource::kAverage;
}

namespace se3 = solvers::se3;

ObjectiveMask both() { return {true, true}; }
bool covers(ObjectiveMask have, ObjectiveMask want) {
  return (have.intensity || !want.intensity) && (have.depth || !want.depth);
}
ObjectiveMask unite(ObjectiveMask a, ObjectiveMask b) { return {a.intensity || b.intensity, a.depth || b.depth}; }

PoseF pose_of(const Eigen::VectorXd& x) {
  const Eigen::Isometry3d T = se3::from_ambient(x);
  PoseF p;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) p.R[3 * r + c] = static_cast<float>(T.linear()(r, c));
    p.t[r] = static_cast<float>(T.translation()(r));
  }
  return p;
}

solvers::QuadraticModel model_of(const GramSums& g) {
  solvers::QuadraticModel m;
  m.H.resize(6, 6);
  m.b.resize(6);
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j <= i; ++j) m.H(i, j) = m.H(j, i) = g.g[i * (i + 1) / 2 + j];
    m.b(i) = g.g[21 + i];
  }
  m.a = g.g[27];
  return m;
}

solvers::QuadraticModel zero_model() {
  solvers::QuadraticModel m;
  m.b = Eigen::VectorXd::Zero(6);
  m.H = Eigen::MatrixXd::Zero(6, 6);
  return m;
}

}  // namespace

RgbdOdometryProblem::RgbdOdometryProblem(const RgbdLevel& reference, const RgbdLevel& current,
                                         RgbdProblemOptions options)
    : reference_(&reference), current_(&current), options_(options), kernels_(&default_kernels()) {
  const auto& ri = reference.intensity;
  const auto& rd = reference.depth;
  const auto& ci = current.intensity;
  const auto& cd = current.depth;
  const auto size = [](const auto& im) { return std::to_string(im.width) + "x" + std::to_string(im.height); };
  const std::string level = "RGB-D problem: level " + std::to_string(reference.level);
  if (ri.width != rd.width || ri.height != rd.height || ci.width != cd.width || ci.height != cd.height ||
      ri.width != ci.width || ri.height != ci.height) {
    throw Error(level + " sizes differ (reference " + size(ri) + " / depth " + size(rd) + ", current " + size(ci) +
                " / depth " + size(cd) + ")");
  }
  if (ri.width < 2 || ri.height < 2) throw Error(level + " is too small (" + size(ri) + ")");
  check_problem_options(options_);
  gradients_ = gradient_source(options_.jacobian);
  // Everything that does not depend on the pose, once per (pair, level): the iterations then
  // only transform, project, interpolate and accumulate.
  reference_terms_ = make_reference_terms(reference, options_.min_depth, options_.max_depth,
                                          gradients_ != GradientSource::kCurrent, options_.threads);
  if (current.intensity_depth.size() == 2 * ci.data.size()) {
    cells_ = current.intensity_depth.data();
  } else {
    own_cells_ = interleave_intensity_depth(current);
    cells_ = own_cells_.data();
  }
  const std::size_t n = padded_terms(reference_terms_.count);
  for (auto* v : {&r_i_, &r_d_, &gi_u_, &gi_v_, &gd_u_, &gd_v_, &w_i_, &w_d_}) {
    v->reset(n);
    v->fill_from(reference_terms_.count, 0.0f);
  }
  if (options_.affine_brightness == 2) {
    q_.reset(n);
    q_.fill_from(0, 0.0f);
    rho2_ = squared_radii(*kernels_, reference_terms_.view(), n);
  }
  flag_storage_.reset((n + sizeof(float) - 1) / sizeof(float));
  stats_.terms = num_terms();
}

std::string RgbdOdometryProblem::name() const {
  const auto& im = reference_->intensity;
  return "rgbd-odometry(level " + std::to_string(reference_->level) + ", " + std::to_string(im.width) + "x" +
         std::to_string(im.height) + (options_.depth_first ? ", F_1 = F_D" : "") + ")";
}

void RgbdOdometryProblem::set_kernel_isa(KernelIsa isa) {
  kernels_ = &kernels(isa);
  if (options_.affine_brightness == 2) rho2_ = squared_radii(*kernels_, reference_terms_.view(), rho2_.size());
  warp_x_.resize(0);  // nothing cached was computed by these kernels
  f_at_warp_.reset();
  last_linearization_.reset();
}

void RgbdOdometryProblem::set_jacobian(JacobianKind kind) {
  if (kind == JacobianKind::kMethodDefault) {
    throw Error("RGB-D problem: Jacobian kind 'auto' names a method's default; resolve it first (method_jacobian())");
  }
  if (kind != JacobianKind::kForward && reference_terms_.gi_u.size() == 0 && reference_terms_.count > 0) {
    throw Error(std::string("RGB-D problem: Jacobian kind '") + to_string(kind) +
                "' needs the reference-side gradients, which a problem built with forward Jacobians does not have");
  }
  options_.jacobian = kind;
  gradients_ = gradient_source(kind);
  warp_x_.resize(0);  // the cached warp holds gradients of the previous kind
  f_at_warp_.reset();
  last_linearization_.reset();
}

void RgbdOdometryProblem::set_objectives(bool joint_weights, bool model_f2) {
  options_.joint_weights = joint_weights;
  options_.model_f2 = model_f2;
  weights_mask_ = ObjectiveMask{false, false};  // weights of the other weighting are not reused
  if (!joint_weights) stats_.joint_scale = JointScale{};
  warp_x_.resize(0);
  f_at_warp_.reset();
  last_linearization_.reset();
}

void RgbdOdometryProblem::check_x(const Eigen::VectorXd& x) const {
  if (x.size() != 7) throw Error("RGB-D problem: x must be the 7-vector [t; q], got size " + std::to_string(x.size()));
  if (!x.allFinite()) throw Error("RGB-D problem: x contains NaN or Inf");
  if (x.tail<4>().norm() < 1e-12) throw Error("RGB-D problem: quaternion of x has zero norm");
}

ObjectiveMask RgbdOdometryProblem::modelled() const {
  if (options_.model_f2) return both();
  return options_.depth_first ? ObjectiveMask{false, true} : ObjectiveMask{true, false};
}

TermBuffers RgbdOdometryProblem::buffers() {
  TermBuffers b;
  b.r_i = r_i_.data();
  b.r_d = r_d_.data();
  b.gi_u = gi_u_.data();
  b.gi_v = gi_v_.data();
  b.gd_u = gd_u_.data();
  b.gd_v = gd_v_.data();
  b.flags = flags();
  b.w_i = w_i_.data();
  b.w_d = w_d_.data();
  if (options_.affine_brightness == 2) b.q = q_.data();
  return b;
}

WarpParams RgbdOdometryProblem::warp_params(const Eigen::VectorXd& x, ObjectiveMask mask) const {
  WarpParams p;
  p.pose = pose_of(x);
  p.fx = static_cast<float>(current_->K.fx);
  p.fy = static_cast<float>(current_->K.fy);
  p.cx = static_cast<float>(current_->K.cx);
  p.cy = static_cast<float>(current_->K.cy);
  p.width = current_->intensity.width;
  p.height = current_->intensity.height;
  p.cells = cells_;
  p.occlusion_margin = static_cast<float>(options_.occlusion_margin);
  p.depth_noise_exponent = options_.depth_noise_exponent;
  p.objectives = mask;
  p.gradients = gradients_;
  p.gain = static_cast<float>(stats_.brightness_gain);
  p.offset = static_cast<float>(stats_.brightness_offset);
  p.radial = static_cast<float>(stats_.brightness_radial);
  if (options_.affine_brightness == 2) p.rho2 = rho2_.data();
  return p;
}

void RgbdOdometryProblem::warp_all(const Eigen::VectorXd& x, ObjectiveMask mask, bool weighted_sums) {
  check_x(x);
  if (warp_x_.size() == x.size() && warp_x_ == x && covers(warp_mask_, mask)) return;
  warp_x_.resize(0);
  f_at_warp_.reset();
  last_linearization_.reset();
  WarpParams p = warp_params(x, mask);
  p.weighted_sums = weighted_sums;
  const ReferenceArrays ref = reference_terms_.view();
  const TermBuffers buf = buffers();
  warp_sums_ = sum_over_chunks<WarpSums>(r_i_.size(), kChunkTerms, options_.threads, [&](std::size_t b, std::size_t e) {
    return kernels_->warp(p, ref, buf, b, e);
  });
  warp_sums_weighted_ = weighted_sums;
  warp_mask_ = mask;
  warp_x_ = x;
}

void RgbdOdometryProblem::refit_brightness(WarpSums& at) {
  BrightnessFit fit;
  fit.intensity = reference_terms_.intensity.data();
  fit.weighted = weights_mask_.intensity;
  fit.radial = options_.affine_brightness == 2;
  const RadialPrior prior{options_.radial_prior, stats_.brightness_radial};
  const BrightnessCorrection c = refit_stored_brightness(*kernels_, fit, prior, stats_.brightness_gain, buffers(),
                                                         r_i_.size(), options_.threads, at.ss_i);
  if (!c.valid) return;
  stats_.brightness_gain += c.gain;
  stats_.brightness_offset += c.offset;
  stats_.brightness_radial += c.radial;
  f_at_warp_.reset();
}

void RgbdOdometryProblem::estimate_weights(ObjectiveMask mask, WarpSums& at) {
  last_linearization_.reset();
  if (options_.affine_brightness != 0 && mask.intensity && mask.depth) refit_brightness(at);
  const std::size_t n = reference_terms_.count;
  if (options_.joint_weights && mask.intensity && mask.depth) {
    // Method joint: ONE weight per pixel from (r_I, r_D) and the 2x2 scale S (joint_weights.h),
    // computed by the kernels' weight stage (WeightModel::kJoint) in the pass that uses them.
    stats_.joint_scale =
        estimate_joint_scale(buffers(), n, options_.weights, stats_.joint_scale, *kernels_, options_.threads);
    stats_.sigma_intensity = std::sqrt(stats_.joint_scale.s_ii);
    stats_.sigma_depth = std::sqrt(stats_.joint_scale.s_dd);
    model_ = joint_weight_model(stats_.joint_scale, options_.weights);
    return;
  }
  // Warm start: the scale changes little between the iterations of one problem.
  const ResidualSet intensity{r_i_.data(), flags(), 1, at.valid_i, at.ss_i};
  const ResidualSet depth{r_d_.data(), flags(), 2, at.valid_d, at.ss_d};
  if (mask.intensity && mask.depth) {
    const std::array<double, 2> sigma =
        estimate_scales(intensity, depth, n, options_.weights, {stats_.sigma_intensity, stats_.sigma_depth}, *kernels_,
                        options_.threads);
    stats_.sigma_intensity = sigma[0];
    stats_.sigma_depth = sigma[1];
  } else if (mask.intensity) {
    stats_.sigma_intensity =
        estimate_scale(intensity, n, options_.weights, stats_.sigma_intensity, *kernels_, options_.threads);
  } else if (mask.depth) {
    stats_.sigma_depth = estimate_scale(depth, n, options_.weights, stats_.sigma_depth, *kernels_, options_.threads);
  }
  const WeightModel fresh = weight_model(options_.weights, stats_.sigma_intensity, stats_.sigma_depth);
  model_.kind = fresh.kind;
  if (mask.intensity) model_.intensity = fresh.intensity;
  if (mask.depth) model_.depth = fresh.depth;
}

void RgbdOdometryProblem::ensure_weights(const Eigen::VectorXd& x, ObjectiveMask mask) {
  if (options_.joint_weights) mask = both();  // one weight from both residuals
  const ObjectiveMask missing{mask.intensity && !weights_mask_.intensity, mask.depth && !weights_mask_.depth};
  if (!missing.intensity && !missing.depth) return;
  warp_all(x, unite(mask, warp_x_.size() == x.size() && warp_x_ == x ? warp_mask_ : mask), false);
  estimate_weights(missing, warp_sums_);
  const TermBuffers buf = buffers();
  const WeightModel m = model_;
  sum_over_chunks<WeighSums>(r_i_.size(), kChunkTerms, options_.threads,
                             [&](std::size_t b, std::size_t e) { return kernels_->weigh(m, missing, buf, b, e); });
  weights_mask_ = unite(weights_mask_, missing);
  f_at_warp_.reset();
  warp_sums_weighted_ = false;
}

solvers::Linearization RgbdOdometryProblem::linearize(const Eigen::VectorXd& x,
                                                      const solvers::LinearizeOptions& options) {
  const ObjectiveMask mask = modelled();
  check_x(x);
  if (last_linearization_ && !options.want_full && warp_x_.size() == x.size() && warp_x_ == x &&
      covers(warp_mask_, mask)) {
    return *last_linearization_;
  }
  {
    solvers::ScopedPhase phase(options.profile, "residuals");
    warp_all(x, mask, false);
  }
  WeightModel model;
  {
    solvers::ScopedPhase phase(options.profile, "weights");
    if (options.update_weights || !covers(weights_mask_, mask)) {
      estimate_weights(mask, warp_sums_);
      model = model_;
    } else {
      model.kind = WeightModel::kStored;
    }
  }
  NormalSums sums;
  {
    // Weights applied, Jacobians built and H, b, a accumulated in one pass.
    solvers::ScopedPhase phase(options.profile, "normal_equations");
    NormalParams p;
    p.pose = pose_of(x);
    p.objectives = mask;
    p.depth_noise_exponent = options_.depth_noise_exponent;
    p.radial = static_cast<float>(stats_.brightness_radial);
    const bool reference_g = gradients_ == GradientSource::kReference;
    p.gi_u = reference_g ? reference_terms_.gi_u.data() : gi_u_.data();
    p.gi_v = reference_g ? reference_terms_.gi_v.data() : gi_v_.data();
    p.gd_u = reference_g ? reference_terms_.gd_u.data() : gd_u_.data();
    p.gd_v = reference_g ? reference_terms_.gd_v.data() : gd_v_.data();
    const ReferenceArrays ref = reference_terms_.view();
    const TermBuffers buf = buffers();
    sums = sum_over_chunks<NormalSums>(r_i_.size(), kChunkTerms, options_.threads, [&](std::size_t b, std::size_t e) {
      return kernels_->normal_equations(p, model, ref, buf, b, e);
    });
  }
  weights_mask_ = unite(weights_mask_, mask);
  solvers::QuadraticModel mi = mask.intensity ? model_of(sums.intensity) : zero_model();
  solvers::QuadraticModel md = mask.depth ? model_of(sums.depth) : zero_model();
  stats_.valid_intensity = static_cast<int>(warp_sums_.valid_i);
  stats_.valid_depth = static_cast<int>(warp_sums_.valid_d);
  stats_.weight_sum_intensity = sums.intensity.weight_sum;
  stats_.weight_sum_depth = sums.depth.weight_sum;
  stats_.f_intensity = mi.a;
  stats_.f_depth = md.a;
  f_at_warp_ = std::array<double, 2>{mi.a, md.a};

  solvers::Linearization lin;
  if (options.want_full) {
    solvers::ScopedPhase phase(options.profile, "normal_equations");
    const Eigen::Isometry3d T = se3::from_ambient(x);
    const DoublePathOptions dp = double_path_options();
    const auto full = [&](bool depth, bool modelled) {
      if (modelled)
        return double_residuals(reference_terms_, *current_, T, depth, true, (depth ? w_d_ : w_i_).data(), dp);
      const Eigen::Index n = num_terms();
      return solvers::ResidualData{Eigen::VectorXd::Zero(n), Eigen::MatrixXd::Zero(n, 6), Eigen::VectorXd::Zero(n)};
    };
    solvers::ResidualData fi = full(false, mask.intensity), fd = full(true, mask.depth);
    if (options_.depth_first) std::swap(fi, fd);
    lin.full1 = std::move(fi);
    lin.full2 = std::move(fd);
  }
  if (options_.depth_first) {
    lin.f1 = std::move(md);
    lin.f2 = std::move(mi);
  } else {
    lin.f1 = std::move(mi);
    lin.f2 = std::move(md);
  }
  if (!options.want_full) last_linearization_ = lin;
  return lin;
}

std::array<double, 2> RgbdOdometryProblem::evaluate_intensity_depth(const Eigen::VectorXd& x) {
  const ObjectiveMask mask = modelled();
  check_x(x);
  ensure_weights(x, mask);
  const bool cached = warp_x_.size() == x.size() && warp_x_ == x && covers(warp_mask_, mask);
  if (cached && f_at_warp_) return *f_at_warp_;
  if (cached && warp_sums_weighted_) return {warp_sums_.f_i, warp_sums_.f_d};
  if (!cached) {
    // The warp at a new x sums F under the stored weights in the same pass.
    warp_all(x, mask, true);
    return {warp_sums_.f_i, warp_sums_.f_d};
  }
  WeightModel stored;
  stored.kind = WeightModel::kStored;
  const TermBuffers buf = buffers();
  const WeighSums s = sum_over_chunks<WeighSums>(
      r_i_.size(), kChunkTerms, options_.threads,
      [&](std::size_t b, std::size_t e) { return kernels_->weigh(stored, mask, buf, b, e); });
  f_at_warp_ = std::array<double, 2>{s.f_i, s.f_d};
  return *f_at_warp_;
}

std::array<double, 2> RgbdOdometryProblem::evaluate(const Eigen::VectorXd& x) {
  const auto f = evaluate_intensity_depth(x);
  if (options_.depth_first) return {f[1], f[0]};
  return f;
}

std::array<double, 2> RgbdOdometryProblem::evaluate_only(const Eigen::VectorXd& x) {
  const ObjectiveMask mask = modelled();
  check_x(x);
  const ObjectiveMask weighted = options_.joint_weights ? both() : mask;
  const bool cached = warp_x_.size() == x.size() && warp_x_ == x && covers(warp_mask_, mask);
  if (cached || !covers(weights_mask_, weighted)) return evaluate(x);
  // The sums of evaluate_intensity_depth()'s warp at a new x, in the same order.
  WarpParams p = warp_params(x, mask);
  p.weighted_sums = true;
  p.store = false;
  const ReferenceArrays ref = reference_terms_.view();
  const TermBuffers buf = buffers();
  const WarpSums s =
      sum_over_chunks<WarpSums>(r_i_.size(), kChunkTerms, options_.threads,
                                [&](std::size_t b, std::size_t e) { return kernels_->warp(p, ref, buf, b, e); });
  counted_x_ = x;
  counted_sums_ = s;
  if (options_.depth_first) return {s.f_d, s.f_i};
  return {s.f_i, s.f_d};
}

std::array<double, 2> RgbdOdometryProblem::objectives_at(const Eigen::VectorXd& x, solvers::PhaseProfile* profile) {
  {
    solvers::ScopedPhase phase(profile, "residuals");
    warp_all(x, both(), false);
  }
  solvers::ScopedPhase phase(profile, "weights");
  estimate_weights(both(), warp_sums_);
  const TermBuffers buf = buffers();
  const WeightModel m = model_;
  const WeighSums s =
      sum_over_chunks<WeighSums>(r_i_.size(), kChunkTerms, options_.threads,
                                 [&](std::size_t b, std::size_t e) { return kernels_->weigh(m, both(), buf, b, e); });
  weights_mask_ = both();
  stats_.valid_intensity = static_cast<int>(warp_sums_.valid_i);
  stats_.valid_depth = static_cast<int>(warp_sums_.valid_d);
  stats_.weight_sum_intensity = s.weight_sum_i;
  stats_.weight_sum_depth = s.weight_sum_d;
  stats_.f_intensity = s.f_i;
  stats_.f_depth = s.f_d;
  // The model's F_2 = 0 convention for a one-objective problem stays with evaluate().
  f_at_warp_.reset();
  warp_sums_weighted_ = false;
  return {s.f_i, s.f_d};
}

double RgbdOdometryProblem::pixel_motion(const Eigen::VectorXd& x, const Eigen::VectorXd& delta) {
  check_x(x);
  if (delta.size() != 6) throw Error("RGB-D problem: a step has 6 entries, got " + std::to_string(delta.size()));
  if (!motion_metric_) {
    const Eigen::Isometry3d T = se3::from_ambient(x);
    const double fx = current_->K.fx, fy = current_->K.fy;
    const ReferenceTerms& ref = reference_terms_;
    const std::size_t stride = std::max<std::size_t>(1, ref.count / 4096);
    Eigen::Matrix<double, 6, 6> M = Eigen::Matrix<double, 6, 6>::Zero();
    int samples = 0;
    for (std::size_t k = 0; k < ref.count; k += stride) {
      const Eigen::Vector3d q = T * Eigen::Vector3d(ref.x[k], ref.y[k], ref.z[k]);
      if (!(q.z() > 1e-6)) continue;
      const double iz = 1.0 / q.z();
      // d y / d delta = (d y / d q) [I, -q^]; each row is [c, q x c] with c = d y_row / d q.
      for (const Eigen::Vector3d& c : {Eigen::Vector3d(fx * iz, 0.0, -fx * q.x() * iz * iz),
                                       Eigen::Vector3d(0.0, fy * iz, -fy * q.y() * iz * iz)}) {
        Eigen::Matrix<double, 6, 1> row;
        row << c, q.cross(c);
        M.noalias() += row * row.transpose();
      }
      ++samples;
    }
    motion_metric_ = samples > 0 ? M / samples : M;
  }
  return std::sqrt(std::max(0.0, delta.dot(*motion_metric_ * delta)));
}

std::optional<std::string> RgbdOdometryProblem::degenerate(const Eigen::VectorXd& x) {
  check_x(x);
  const ObjectiveMask mask = modelled();
  WarpSums s;
  if (warp_x_.size() == x.size() && warp_x_ == x && covers(warp_mask_, mask)) {
    s = warp_sums_;
  } else if (counted_x_.size() == x.size() && counted_x_ == x) {
    s = counted_sums_;  // evaluate_only() at x, same objectives (modelled())
  } else if (covers(weights_mask_, options_.joint_weights ? both() : mask)) {
    // A counting pass that writes nothing (the buffers keep the latest warp).
    WarpParams p = warp_params(x, mask);
    p.weighted_sums = true;
    p.store = false;
    const ReferenceArrays ref = reference_terms_.view();
    const TermBuffers buf = buffers();
    s = sum_over_chunks<WarpSums>(r_i_.size(), kChunkTerms, options_.threads,
                                  [&](std::size_t b, std::size_t e) { return kernels_->warp(p, ref, buf, b, e); });
  } else {
    warp_all(x, mask, false);
    s = warp_sums_;
  }
  const long long valid = options_.depth_first ? s.valid_d : s.valid_i;
  const long long terms = num_terms();
  const double needed =
      std::max<double>(options_.min_valid_terms, options_.min_valid_fraction * static_cast<double>(terms));
  if (static_cast<double>(valid) >= needed) return std::nullopt;
  return std::to_string(valid) + " of " + std::to_string(terms) + " terms valid, fewer than " +
         std::to_string(static_cast<long long>(std::ceil(needed))) + " (min_valid_terms " +
         std::to_string(options_.min_valid_terms) + ", min_valid_fraction " +
         std::to_string(options_.min_valid_fraction) + ")";
}

solvers::ResidualData RgbdOdometryProblem::residuals(int j, const Eigen::VectorXd& x, bool with_jacobian) {
  if (j != 1 && j != 2) throw Error("RGB-D problem: objective index must be 1 or 2, got " + std::to_string(j));
  check_x(x);
  const bool depth = (j == 2) != options_.depth_first;
  ensure_weights(x, depth ? ObjectiveMask{false, true} : ObjectiveMask{true, false});
  const DoublePathOptions dp = double_path_options();
  return double_residuals(reference_terms_, *current_, se3::from_ambient(x), depth, with_jacobian,
                          (depth ? w_d_ : w_i_).data(), dp);
}

}  // namespace bivo::odometry
