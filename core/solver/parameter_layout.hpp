// Which unknowns are free, and where each sits in the reduced vector of the LM solve:
// free globals (psi theta phi H f order, then a shared curvature) first, then each line's
// free kinds (y0 m c).
#pragma once

#include <array>

#include "core/solver/solver_types.hpp"

namespace ccdlane::solver {

enum LineParam : int { kY0 = 0, kSlope = 1, kCurvature = 2, kLineParams = 3 };

class ParameterLayout {
 public:
  ParameterLayout() = default;
  // With LineModel::shared_curvature the curvature is one global, after the pose's (and
  // never a line kind, whatever `free` says: LaneSolver refuses c in `free` then).
  ParameterLayout(const FreeSet& free, int num_lines, LineModel model = LineModel::per_line);

  int size() const { return num_global_ + num_line_kinds_ * num_lines_; }
  // Globals: the free pose parameters, then the shared curvature if any.
  int num_global() const { return num_global_; }
  int num_pose() const { return num_pose_; }
  int num_line_kinds() const { return num_line_kinds_; }
  int num_lines() const { return num_lines_; }
  // Columns a pick's residuals can touch: the globals, then its line's kinds.
  int local_size() const { return num_global_ + num_line_kinds_; }
  PoseParam global(int k) const { return global_[k]; }  // k < num_pose()
  LineParam line_kind(int k) const { return line_kind_[k]; }
  int line_offset(int line) const { return num_global_ + line * num_line_kinds_; }
  // Reduced (and local) index of the shared curvature, or -1 without one.
  int shared_curvature_index() const { return num_global_ > num_pose_ ? num_pose_ : -1; }
  // Reduced index of kind `kind` of line `line`, or -1 when that kind is fixed.
  int line_index(int line, LineParam kind) const;
  int global_index(PoseParam p) const;  // -1 when fixed
  ReducedParam describe(int index) const;

  // Adds a reduced step to the parameters it stands for (a shared curvature's to every
  // line's c).
  void apply_step(const ReducedVector& step, CameraPose& pose, RoadLine* lines) const;
  // Squared norm of the free parameters' values (radians, mm): the scale of a step.
  double squared_norm(const CameraPose& pose, const RoadLine* lines) const;
  // Where local parameter `local` of line `line` (globals, then the line's kinds) sits in
  // the reduced vector: the globals are shared by every line, its own kinds sit at the
  // line's offset.
  int reduced_index(int line, int local) const { return local < num_global_ ? local : local + line * num_line_kinds_; }

 private:
  int num_pose_ = 0;
  int num_global_ = 0;
  int num_line_kinds_ = 0;
  int num_lines_ = 0;
  std::array<PoseParam, kPoseParams> global_{};
  std::array<LineParam, kLineParams> line_kind_{};
};

// Pose parameter p of a pose, by reference (psi theta phi H f order).
double& pose_param(CameraPose& pose, PoseParam p);
double& line_param(RoadLine& line, LineParam k);

}  // namespace ccdlane::solver
