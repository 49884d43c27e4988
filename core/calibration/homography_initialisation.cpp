// Zhang's homography initialisation, reduced to one focal length with a known principal point.
#include "core/calibration/homography_initialisation.hpp"

#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/SVD>

namespace ccdlane::calibration {
namespace {

// Hartley's normalisation: centroid to the origin, mean distance sqrt(2).
Mat3 normalising_transform(std::span<const Vec2> points) {
  Vec2 mean = Vec2::Zero();
  for (const Vec2& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  double spread = 0.0;
  for (const Vec2& p : points) spread += (p - mean).norm();
  spread /= static_cast<double>(points.size());
  const double s = spread > 0.0 ? std::sqrt(2.0) / spread : 1.0;
  Mat3 t;
  t << s, 0.0, -s * mean.x(), 0.0, s, -s * mean.y(), 0.0, 0.0, 1.0;
  return t;
}

Vec2 apply(const Mat3& t, const Vec2& p) { return (t * p.homogeneous()).hnormalized(); }

}  // namespace

std::optional<Mat3> board_to_chip_homography(const CameraSpec& chip, double cx, double cy, std::span<const Vec3> board,
                                             std::span<const Vec2> corners_px) {
  const std::size_t n = board.size();
  if (n < 4 || corners_px.size() != n) return std::nullopt;
  std::vector<Vec2> from(n), to(n);
  for (std::size_t i = 0; i < n; ++i) {
    from[i] = board[i].head<2>();
    to[i] = Vec2((corners_px[i].x() - cx) * chip.pitch_u(), (corners_px[i].y() - cy) * chip.pitch_v());
  }
  const Mat3 t_from = normalising_transform(from), t_to = normalising_transform(to);
  Eigen::MatrixXd a(2 * n, 9);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 x = apply(t_from, from[i]).homogeneous();
    const Vec2 y = apply(t_to, to[i]);
    const auto r = static_cast<Eigen::Index>(2 * i);
    a.row(r) << x.transpose(), Eigen::RowVector3d::Zero(), -y.x() * x.transpose();
    a.row(r + 1) << Eigen::RowVector3d::Zero(), x.transpose(), -y.y() * x.transpose();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullV);
  const Eigen::VectorXd& sv = svd.singularValues();
  // A second vanishing singular value: the corners do not fix a plane-to-plane map.
  if (!(sv(7) > 1e-9 * sv(0))) return std::nullopt;
  const Eigen::Matrix<double, 9, 1> h = svd.matrixV().col(8);
  Mat3 normalised;
  normalised << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8);
  Mat3 homography = t_to.inverse() * normalised * t_from;
  if (!homography.allFinite() || homography.norm() == 0.0) return std::nullopt;
  return Mat3(homography / homography.norm());
}

std::optional<double> focal_length_from_homographies(std::span<const Mat3> homographies) {
  // omega = K^-T K^-1 = diag(w, w, 1) with w = 1/f^2, K = diag(f, f, 1): h1' omega h2 = 0
  // and h1' omega h1 = h2' omega h2, each a w + b = 0.
  double aa = 0.0, ab = 0.0;
  for (const Mat3& h : homographies) {
    const Vec3 h1 = h.col(0), h2 = h.col(1);
    // Each view's pair scaled to unit size, so no view outweighs the others by its scale.
    const double scale = 1.0 / (h1.squaredNorm() + h2.squaredNorm());
    const double a1 = (h1.x() * h2.x() + h1.y() * h2.y()) * scale, b1 = h1.z() * h2.z() * scale;
    const double a2 = (h1.head<2>().squaredNorm() - h2.head<2>().squaredNorm()) * scale;
    const double b2 = (h1.z() * h1.z() - h2.z() * h2.z()) * scale;
    aa += a1 * a1 + a2 * a2;
    ab += a1 * b1 + a2 * b2;
  }
  if (!(aa > 0.0)) return std::nullopt;
  const double w = -ab / aa;
  if (!(w > 0.0) || !std::isfinite(1.0 / std::sqrt(w))) return std::nullopt;
  return 1.0 / std::sqrt(w);
}

BoardPose pose_from_homography(const Mat3& homography, double f_mm) {
  const Mat3 b = Eigen::Vector3d(1.0 / f_mm, 1.0 / f_mm, 1.0).asDiagonal() * homography;
  double lambda = 2.0 / (b.col(0).norm() + b.col(1).norm());
  if (b(2, 2) * lambda < 0.0) lambda = -lambda;  // the board's origin in front of the lens
  Mat3 r;
  r.col(0) = lambda * b.col(0);
  r.col(1) = lambda * b.col(1);
  r.col(2) = r.col(0).cross(r.col(1));
  const Eigen::JacobiSVD<Mat3> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 rotation = svd.matrixU() * svd.matrixV().transpose();
  if (rotation.determinant() < 0.0) {
    Mat3 flip = Mat3::Identity();
    flip(2, 2) = -1.0;
    rotation = svd.matrixU() * flip * svd.matrixV().transpose();
  }
  return {rotation, lambda * b.col(2)};
}

}  // namespace ccdlane::calibration
