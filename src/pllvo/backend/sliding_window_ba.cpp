#include "pllvo/backend/sliding_window_ba.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include <ceres/problem.h>
#include <ceres/solver.h>

#include "pllvo/backend/ba_costs.h"
#include "pllvo/common/error.h"
#include "pllvo/geometry/config_choice.h"

namespace pllvo::backend {

namespace {
const geometry::Choices<BaJacobians> kJacobianChoices = {{"analytic", BaJacobians::kAnalytic},
                                                         {"autodiff", BaJacobians::kAutodiff}};
const geometry::Choices<BaLinearSolver> kSolverChoices = {{"dense_schur", BaLinearSolver::kDenseSchur},
                                                          {"sparse_schur", BaLinearSolver::kSparseSchur}};

void check_index(int index, size_t size, const char* what) {
  if (index < 0 || static_cast<size_t>(index) >= size)
    throw InternalError(std::string("SlidingWindowBA: observation names ") + what + " " + std::to_string(index) +
                        " of " + std::to_string(size));
}

void validate(const BaProblem& p) {
  const size_t cameras = p.T_cam_cam0.empty() ? 1 : p.T_cam_cam0.size();
  for (const auto& o : p.point_observations) {
    check_index(o.keyframe, p.keyframes.size(), "keyframe");
    check_index(o.point, p.points.size(), "point");
    check_index(o.camera, cameras, "camera");
  }
  for (const auto& o : p.line_observations) {
    check_index(o.keyframe, p.keyframes.size(), "keyframe");
    check_index(o.line, p.lines.size(), "line");
    check_index(o.camera, cameras, "camera");
  }
  for (const auto& o : p.direction_observations) check_index(o.keyframe, p.keyframes.size(), "keyframe");
}

/// Parameter blocks of a BaProblem and the residual norms (pixels) of its observations.
/// All blocks live in one buffer, poses then points then lines. Ceres orders the blocks of an
/// elimination group by address: in separate vectors, points and lines would come in the order
/// the heap happened to place them, which follows earlier allocations (a progress line printed
/// on a timer is one), and the Schur sums would change in the last bits from run to run. The
/// monocular runs are chaotic enough that those bits move the ATE by a factor of 2
/// (docs/vo.md).
class BlockState {
 public:
  explicit BlockState(const BaProblem& p, double line_weight)
      : problem_(p),
        line_scale_(p.focal_px * line_weight),
        points_at_(kPoseBlockSize * p.keyframes.size()),
        lines_at_(points_at_ + kPointBlockSize * p.points.size()),
        offset_at_(lines_at_ + kLineBlockSize * p.lines.size()),
        storage_(offset_at_ + 1) {
    storage_[offset_at_] = p.stereo_offset_px;
    for (size_t i = 0; i < p.keyframes.size(); ++i) pose_to_block(p.keyframes[i].T_world_cam.inverse(), pose(i));
    for (size_t i = 0; i < p.points.size(); ++i) Eigen::Map<Eigen::Vector3d>(point(i)) = p.points[i].p_world;
    for (size_t i = 0; i < p.lines.size(); ++i) {
      Eigen::Map<Eigen::Vector3d>(line(i)) = p.lines[i].segment_world.start;
      Eigen::Map<Eigen::Vector3d>(line(i) + 3) = p.lines[i].segment_world.end;
    }
  }

  double* pose(size_t i) { return storage_.data() + kPoseBlockSize * i; }
  double* point(size_t i) { return storage_.data() + points_at_ + kPointBlockSize * i; }
  double* line(size_t i) { return storage_.data() + lines_at_ + kLineBlockSize * i; }
  const double* pose(size_t i) const { return storage_.data() + kPoseBlockSize * i; }
  const double* point(size_t i) const { return storage_.data() + points_at_ + kPointBlockSize * i; }
  const double* line(size_t i) const { return storage_.data() + lines_at_ + kLineBlockSize * i; }
  /// The rectified pair's horizontal offset (pixels), added to camera > 0 residuals.
  double* offset() { return storage_.data() + offset_at_; }
  double offset_value() const { return storage_[offset_at_]; }

  const Pose& extrinsic(int camera) const {
    return problem_.T_cam_cam0.empty() ? identity_ : problem_.T_cam_cam0[camera];
  }

  /// Residual norm (pixels) of a point observation; NaN when it cannot be evaluated.
  double point_error(const BaPointObservation& o) const {
    const double* params[2] = {pose(o.keyframe), point(o.point)};
    double r[2];
    if (!PointReprojectionCost(o.xy, extrinsic(o.camera), problem_.focal_px).Evaluate(params, r, nullptr)) return NAN;
    if (o.camera > 0) r[0] += offset_value();
    return std::hypot(r[0], r[1]);
  }

  double line_error(const BaLineObservation& o) const {
    const double* params[2] = {pose(o.keyframe), line(o.line)};
    double r[2];
    if (!LineReprojectionCost(o.line_coeffs, extrinsic(o.camera), line_scale_).Evaluate(params, r, nullptr)) return NAN;
    return std::hypot(r[0], r[1]);
  }

 private:
  const BaProblem& problem_;
  double line_scale_;
  size_t points_at_, lines_at_, offset_at_;
  std::vector<double> storage_;
  const Pose identity_ = Pose::Identity();
};

/// RMS of the finite errors of the inliers of both observation kinds.
double inlier_rms(const std::vector<double>& point_errors, const std::vector<uint8_t>& point_outliers,
                  const std::vector<double>& line_errors, const std::vector<uint8_t>& line_outliers) {
  double sum = 0;
  int n = 0;
  auto add = [&](const std::vector<double>& errors, const std::vector<uint8_t>& outliers) {
    for (size_t i = 0; i < errors.size(); ++i) {
      if (outliers[i] || !std::isfinite(errors[i])) continue;
      sum += errors[i] * errors[i];
      ++n;
    }
  };
  add(point_errors, point_outliers);
  add(line_errors, line_outliers);
  return n ? std::sqrt(sum / n) : 0.0;
}
}  // namespace

void BundleAdjustmentConfig::load(const ConfigNode& node) {
  node.get("window_size", window_size);
  node.get("num_fixed_oldest", num_fixed_oldest);
  node.get("distance_gauge", distance_gauge);
  node.get("min_point_observations", min_point_observations);
  node.get("min_line_observations", min_line_observations);
  point_loss.load(node, "point_");
  line_loss.load(node, "line_");
  node.get("line_weight", line_weight);
  node.get("max_iterations", max_iterations);
  node.get("second_pass", second_pass);
  node.get("second_pass_iterations", second_pass_iterations);
  node.get("point_outlier_threshold_px", point_outlier_threshold_px);
  node.get("line_outlier_threshold_px", line_outlier_threshold_px);
  node.get("function_tolerance", function_tolerance);
  node.get("max_solver_time_s", max_solver_time_s);
  node.get("num_threads", num_threads);
  node.get("stereo_offset_sigma_px", stereo_offset_sigma_px);
  geometry::get_choice(node, "jacobians", jacobians, kJacobianChoices);
  geometry::get_choice(node, "linear_solver", linear_solver, kSolverChoices);
  if (window_size < 1) throw InputError(node.file(), node.path("window_size"), "must be at least 1");
  if (num_threads < 1) throw InputError(node.file(), node.path("num_threads"), "must be at least 1");
  if (!(stereo_offset_sigma_px >= 0))
    throw InputError(node.file(), node.path("stereo_offset_sigma_px"), "must be 0 or more");
  node.reject_unknown_keys();
}

bool SlidingWindowBA::keyframe_fixed(int i, int n, bool fixed) const {
  return fixed || i < config_.num_fixed_oldest || i < n - config_.window_size;
}

std::pair<int, int> SlidingWindowBA::distance_gauge_pair(const BaProblem& problem) const {
  if (!config_.distance_gauge) return {-1, -1};
  const int n = static_cast<int>(problem.keyframes.size());
  // A keyframe without observations has no block in the problem: the gauge goes to the next.
  std::vector<char> observed(problem.keyframes.size(), 0);
  for (const auto& o : problem.point_observations) observed[o.keyframe] = 1;
  for (const auto& o : problem.line_observations) observed[o.keyframe] = 1;
  int reference = -1, moving = -1, fixed = 0;
  for (int i = 0; i < n; ++i) {
    if (keyframe_fixed(i, n, problem.keyframes[i].fixed)) {
      ++fixed;
      if (reference < 0) reference = i;
    } else if (moving < 0 && observed[i]) {
      moving = i;
    }
  }
  if (fixed >= 2 || reference < 0 || moving < 0) return {-1, -1};
  return {reference, moving};
}

BaSummary SlidingWindowBA::optimize(BaProblem& P) const {
  validate(P);
  const auto t0 = std::chrono::steady_clock::now();
  BaSummary S;
  BlockState state(P, config_.line_weight);
  const bool autodiff = config_.jacobians == BaJacobians::kAutodiff;
  const int nk = static_cast<int>(P.keyframes.size());

  std::vector<int> point_count(P.points.size(), 0), line_count(P.lines.size(), 0);
  for (const auto& o : P.point_observations) ++point_count[o.point];
  for (const auto& o : P.line_observations) ++line_count[o.line];

  // Without fast removal: its per-block hash sets cost more at construction than the few
  // outlier removals of the second pass save.
  ceres::Problem problem;
  ceres::LossFunction* point_loss = config_.point_loss.make_ceres();  // shared; the problem deletes it once
  ceres::LossFunction* line_loss = config_.line_loss.make_ceres();

  // Residuals, skipping observations that cannot be evaluated at the start (behind a camera).
  std::vector<double> initial_point_error(P.point_observations.size()), initial_line_error(P.line_observations.size());
  std::vector<ceres::ResidualBlockId> point_ids(P.point_observations.size(), nullptr);
  std::vector<ceres::ResidualBlockId> line_ids(P.line_observations.size(), nullptr);
  // The offset enters only when it is estimated or not zero: otherwise the problem is the plain one.
  const bool with_offset = config_.stereo_offset_sigma_px > 0 || P.stereo_offset_px != 0;
  for (size_t j = 0; j < P.point_observations.size(); ++j) {
    const auto& o = P.point_observations[j];
    initial_point_error[j] = state.point_error(o);
    if (!std::isfinite(initial_point_error[j])) continue;
    ceres::CostFunction* cost = new_point_cost(o.xy, state.extrinsic(o.camera), P.focal_px, autodiff);
    if (o.camera > 0 && with_offset)
      point_ids[j] = problem.AddResidualBlock(new StereoOffsetPointCost(cost), point_loss, state.pose(o.keyframe),
                                              state.point(o.point), state.offset());
    else
      point_ids[j] = problem.AddResidualBlock(cost, point_loss, state.pose(o.keyframe), state.point(o.point));
  }
  const bool offset_free = with_offset && config_.stereo_offset_sigma_px > 0 && problem.HasParameterBlock(state.offset());
  if (offset_free)
    problem.AddResidualBlock(new_offset_prior_cost(config_.stereo_offset_sigma_px), nullptr, state.offset());
  for (size_t j = 0; j < P.line_observations.size(); ++j) {
    const auto& o = P.line_observations[j];
    initial_line_error[j] = state.line_error(o);
    if (!std::isfinite(initial_line_error[j])) continue;
    line_ids[j] = problem.AddResidualBlock(
        new_line_cost(o.line_coeffs, state.extrinsic(o.camera), P.focal_px * config_.line_weight, autodiff),
        line_loss, state.pose(o.keyframe), state.line(o.line));
  }
  if (P.direction_weight > 0 && !P.direction_observations.empty()) {
    ceres::LossFunction* direction_loss = config_.line_loss.make_ceres();
    for (const auto& o : P.direction_observations)
      problem.AddResidualBlock(
          new_vanishing_cost(o.direction_world, o.start, o.end, P.focal_px * P.direction_weight), direction_loss,
          state.pose(o.keyframe));
  }
  // Unused losses (no residual took them) are not owned by the problem.
  std::unique_ptr<ceres::LossFunction> point_loss_guard, line_loss_guard;
  if (std::all_of(point_ids.begin(), point_ids.end(), [](auto id) { return id == nullptr; })) point_loss_guard.reset(point_loss);
  if (std::all_of(line_ids.begin(), line_ids.end(), [](auto id) { return id == nullptr; })) line_loss_guard.reset(line_loss);

  // Manifolds, fixed blocks and the Schur elimination order (landmarks first).
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  ceres::Manifold* pose_manifold = new_pose_manifold();
  bool pose_manifold_used = false;
  for (int i = 0; i < nk; ++i) {
    double* block = state.pose(i);
    if (!problem.HasParameterBlock(block)) continue;
    problem.SetManifold(block, pose_manifold);
    pose_manifold_used = true;
    ordering->AddElementToGroup(block, 1);
    if (keyframe_fixed(i, nk, P.keyframes[i].fixed)) problem.SetParameterBlockConstant(block);
    else ++S.num_free_keyframes;
  }
  if (!pose_manifold_used) delete pose_manifold;
  if (problem.HasParameterBlock(state.offset())) {
    ordering->AddElementToGroup(state.offset(), 1);
    if (!offset_free) problem.SetParameterBlockConstant(state.offset());
  }
  const auto [reference, moving] = distance_gauge_pair(P);
  if (moving >= 0 && problem.HasParameterBlock(state.pose(moving))) {
    const Eigen::Vector3d c_ref = P.keyframes[reference].T_world_cam.translation();
    const double distance = (P.keyframes[moving].T_world_cam.translation() - c_ref).norm();
    if (distance > 0) problem.AddResidualBlock(new_distance_cost(c_ref, distance), nullptr, state.pose(moving));
  }
  for (size_t i = 0; i < P.points.size(); ++i) {
    double* block = state.point(i);
    if (!problem.HasParameterBlock(block)) continue;
    ordering->AddElementToGroup(block, 0);
    if (P.points[i].fixed || point_count[i] < config_.min_point_observations) problem.SetParameterBlockConstant(block);
    else ++S.num_free_points;
  }
  for (size_t i = 0; i < P.lines.size(); ++i) {
    double* block = state.line(i);
    if (!problem.HasParameterBlock(block)) continue;
    problem.SetManifold(block, new LineEndpointManifold(P.lines[i].segment_world.end - P.lines[i].segment_world.start));
    ordering->AddElementToGroup(block, 0);
    if (P.lines[i].fixed || line_count[i] < config_.min_line_observations) problem.SetParameterBlockConstant(block);
    else ++S.num_free_lines;
  }

  ceres::Solver::Options options;
  options.linear_solver_type =
      config_.linear_solver == BaLinearSolver::kDenseSchur ? ceres::DENSE_SCHUR : ceres::SPARSE_SCHUR;
  options.linear_solver_ordering = ordering;
  options.max_num_iterations = config_.max_iterations;
  options.function_tolerance = config_.function_tolerance;
  options.num_threads = config_.num_threads;
  if (config_.max_solver_time_s > 0) options.max_solver_time_in_seconds = config_.max_solver_time_s;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;

  const bool anything_free = S.num_free_keyframes + S.num_free_points + S.num_free_lines > 0;
  ceres::Solver::Summary summary;
  if (anything_free && problem.NumResidualBlocks() > 0) {
    ceres::Solve(options, &problem, &summary);
    S.initial_cost = summary.initial_cost;
    S.iterations = static_cast<int>(summary.iterations.size());
    if (config_.second_pass && summary.IsSolutionUsable()) {
      int removed = 0;
      for (size_t j = 0; j < point_ids.size(); ++j) {
        if (!point_ids[j] || !(state.point_error(P.point_observations[j]) > config_.point_outlier_threshold_px)) continue;
        problem.RemoveResidualBlock(point_ids[j]);
        point_ids[j] = nullptr, ++removed;
      }
      for (size_t j = 0; j < line_ids.size(); ++j) {
        if (!line_ids[j] || !(state.line_error(P.line_observations[j]) > config_.line_outlier_threshold_px)) continue;
        problem.RemoveResidualBlock(line_ids[j]);
        line_ids[j] = nullptr, ++removed;
      }
      if (removed > 0 && problem.NumResidualBlocks() > 0) {
        options.max_num_iterations = config_.second_pass_iterations;
        ceres::Solve(options, &problem, &summary);
        S.iterations += static_cast<int>(summary.iterations.size());
      }
    }
    S.final_cost = summary.final_cost;
    S.ok = summary.IsSolutionUsable();
    S.report = summary.BriefReport();
  } else {
    S.ok = true;
    S.report = "nothing to optimise";
  }

  // Write back the free values only: fixed ones stay bit-identical.
  if (S.ok) {
    for (int i = 0; i < nk; ++i)
      if (problem.HasParameterBlock(state.pose(i)) && !problem.IsParameterBlockConstant(state.pose(i)))
        P.keyframes[i].T_world_cam = block_to_pose(state.pose(i)).inverse();
    for (size_t i = 0; i < P.points.size(); ++i)
      if (problem.HasParameterBlock(state.point(i)) && !problem.IsParameterBlockConstant(state.point(i)))
        P.points[i].p_world = Eigen::Map<const Eigen::Vector3d>(state.point(i));
    for (size_t i = 0; i < P.lines.size(); ++i)
      if (problem.HasParameterBlock(state.line(i)) && !problem.IsParameterBlockConstant(state.line(i))) {
        P.lines[i].segment_world.start = Eigen::Map<const Eigen::Vector3d>(state.line(i));
        P.lines[i].segment_world.end = Eigen::Map<const Eigen::Vector3d>(state.line(i) + 3);
      }
    if (offset_free) P.stereo_offset_px = *state.offset();
  }

  // Outliers from the values now in `P` (the initial ones when the solve failed).
  const BlockState final_state(P, config_.line_weight);
  std::vector<double> final_point_error(P.point_observations.size()), final_line_error(P.line_observations.size());
  S.point_outliers.assign(P.point_observations.size(), 0);
  S.line_outliers.assign(P.line_observations.size(), 0);
  for (size_t j = 0; j < P.point_observations.size(); ++j) {
    final_point_error[j] = final_state.point_error(P.point_observations[j]);
    S.point_outliers[j] = !(final_point_error[j] <= config_.point_outlier_threshold_px);
  }
  for (size_t j = 0; j < P.line_observations.size(); ++j) {
    final_line_error[j] = final_state.line_error(P.line_observations[j]);
    S.line_outliers[j] = !(final_line_error[j] <= config_.line_outlier_threshold_px);
  }
  S.num_point_outliers = static_cast<int>(std::count(S.point_outliers.begin(), S.point_outliers.end(), 1));
  S.num_line_outliers = static_cast<int>(std::count(S.line_outliers.begin(), S.line_outliers.end(), 1));
  S.initial_rms_px = inlier_rms(initial_point_error, S.point_outliers, initial_line_error, S.line_outliers);
  S.final_rms_px = inlier_rms(final_point_error, S.point_outliers, final_line_error, S.line_outliers);
  S.solve_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return S;
}

}  // namespace pllvo::backend
