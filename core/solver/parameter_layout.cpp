// The reduced parameter vector's layout: packing steps into poses and lines.
#include "core/solver/parameter_layout.hpp"

namespace ccdlane::solver {
namespace {
constexpr FreeParam kGlobalFree[kPoseParams] = {FreeParam::psi, FreeParam::theta, FreeParam::phi, FreeParam::H,
                                                FreeParam::f};
constexpr FreeParam kLineFree[kLineParams] = {FreeParam::y0, FreeParam::m, FreeParam::c};
}  // namespace

double& pose_param(CameraPose& pose, PoseParam p) {
  switch (p) {
    case kPsi: return pose.attitude.psi;
    case kTheta: return pose.attitude.theta;
    case kPhi: return pose.attitude.phi;
    case kHeight: return pose.H_mm;
    default: return pose.f_mm;
  }
}

double& line_param(RoadLine& line, LineParam k) {
  switch (k) {
    case kY0: return line.y0_mm;
    case kSlope: return line.m;
    default: return line.c_per_mm;
  }
}

ParameterLayout::ParameterLayout(const FreeSet& free, int num_lines, LineModel model) : num_lines_(num_lines) {
  for (int p = 0; p < kPoseParams; ++p)
    if (free.has(kGlobalFree[p])) global_[num_pose_++] = static_cast<PoseParam>(p);
  const bool shared = model == LineModel::shared_curvature;
  num_global_ = num_pose_ + (shared ? 1 : 0);
  for (int k = 0; k < kLineParams; ++k)
    if (free.has(kLineFree[k]) && !(shared && k == kCurvature))
      line_kind_[num_line_kinds_++] = static_cast<LineParam>(k);
}

int ParameterLayout::line_index(int line, LineParam kind) const {
  for (int k = 0; k < num_line_kinds_; ++k)
    if (line_kind_[k] == kind) return line_offset(line) + k;
  return -1;
}

int ParameterLayout::global_index(PoseParam p) const {
  for (int k = 0; k < num_pose_; ++k)
    if (global_[k] == p) return k;
  return -1;
}

ReducedParam ParameterLayout::describe(int index) const {
  if (index < num_pose_) return {kGlobalFree[global_[index]], -1};
  if (index < num_global_) return {FreeParam::c, -1};  // the shared curvature
  const int rel = index - num_global_;
  return {kLineFree[line_kind_[rel % num_line_kinds_]], rel / num_line_kinds_};
}

void ParameterLayout::apply_step(const ReducedVector& step, CameraPose& pose, RoadLine* lines) const {
  for (int k = 0; k < num_pose_; ++k) pose_param(pose, global_[k]) += step[k];
  if (const int c = shared_curvature_index(); c >= 0)
    for (int j = 0; j < num_lines_; ++j) lines[j].c_per_mm += step[c];
  for (int j = 0; j < num_lines_; ++j)
    for (int k = 0; k < num_line_kinds_; ++k) line_param(lines[j], line_kind_[k]) += step[line_offset(j) + k];
}

double ParameterLayout::squared_norm(const CameraPose& pose, const RoadLine* lines) const {
  CameraPose p = pose;
  double sum = 0.0;
  for (int k = 0; k < num_pose_; ++k) sum += pose_param(p, global_[k]) * pose_param(p, global_[k]);
  if (shared_curvature_index() >= 0 && num_lines_ > 0) sum += lines[0].c_per_mm * lines[0].c_per_mm;
  for (int j = 0; j < num_lines_; ++j) {
    RoadLine l = lines[j];
    for (int k = 0; k < num_line_kinds_; ++k) sum += line_param(l, line_kind_[k]) * line_param(l, line_kind_[k]);
  }
  return sum;
}

}  // namespace ccdlane::solver
