// Synthetic chessboard views: poses, noisy corners and rendered pictures from known intrinsics.
#include "tests/core/calibration/chessboard_scene.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "core/geometry/distortion.hpp"

namespace ccdlane::test {

using calibration::BoardGeometry;
using calibration::BoardPose;

ChessboardCamera chessboard_camera() {
  ChessboardCamera c;
  c.chip.U_mm = 2.56;
  c.chip.V_mm = 1.92;
  c.chip.Uc_mm = 0.004;
  c.chip.Vc_mm = 0.004;
  c.chip.Nu = 640;
  c.chip.Nv = 480;
  c.chip.cx = 327.3;
  c.chip.cy = 236.9;
  c.chip.k_px2 = -6.0e-7;
  c.truth = {2.4, c.chip.cx, c.chip.cy, c.chip.k_px2};
  return c;
}

namespace {

// The ideal pixel of a camera-frame point (x right, y down, z ahead), then distorted.
std::optional<Vec2> observed_of_camera_point(const ChessboardCamera& c, const Vec3& p) {
  if (!(p.z() > 0.0)) return std::nullopt;
  const Vec2 ideal(c.truth.cx + c.truth.f_mm / c.chip.pitch_u() * p.x() / p.z(),
                   c.truth.cy + c.truth.f_mm / c.chip.pitch_v() * p.y() / p.z());
  return distort_pixel(ideal, Vec2(c.truth.cx, c.truth.cy), c.truth.k_px2);
}

bool board_in_picture(const ChessboardCamera& c, const BoardGeometry& board, const BoardPose& pose) {
  // The outer edge of the white margin: two squares beyond the outer corners.
  const double s = board.square_mm;
  for (double x : {-2.0 * s, (board.columns + 1) * s})
    for (double y : {-2.0 * s, (board.rows + 1) * s}) {
      const auto px = observed_of_camera_point(c, pose.rotation * Vec3(x, y, 0.0) + pose.translation_mm);
      if (!px || px->x() < 4.0 || px->y() < 4.0 || px->x() > c.chip.Nu - 3.0 || px->y() > c.chip.Nv - 3.0) return false;
    }
  return true;
}

}  // namespace

std::vector<BoardPose> varied_board_poses(const ChessboardCamera& camera, const BoardGeometry& board, int count,
                                          std::mt19937& rng, double min_tilt_deg, double max_tilt_deg) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Vec3 board_centre((board.columns - 1) * board.square_mm / 2.0, (board.rows - 1) * board.square_mm / 2.0, 0.0);
  std::vector<BoardPose> poses;
  while (static_cast<int>(poses.size()) < count) {
    const double axis_angle = 2.0 * kPi * unit(rng);
    const double tilt = deg_to_rad(min_tilt_deg + (max_tilt_deg - min_tilt_deg) * unit(rng));
    const double spin = deg_to_rad(-25.0 + 50.0 * unit(rng));
    const Mat3 rotation = (Eigen::AngleAxisd(tilt, Vec3(std::cos(axis_angle), std::sin(axis_angle), 0.0)) *
                           Eigen::AngleAxisd(spin, Vec3::UnitZ()))
                              .toRotationMatrix();
    const double z = 400.0 + 250.0 * unit(rng);
    const Vec3 centre((unit(rng) - 0.5) * 0.3 * z, (unit(rng) - 0.5) * 0.25 * z, z);
    const BoardPose pose{rotation, centre - rotation * board_centre};
    if (board_in_picture(camera, board, pose)) poses.push_back(pose);
  }
  return poses;
}

std::vector<Vec2> corner_pixels(const ChessboardCamera& camera, const BoardGeometry& board, const BoardPose& pose,
                                double sigma_px, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<Vec2> pixels;
  for (const Vec3& corner : calibration::board_corners(board)) {
    Vec2 px = *observed_of_camera_point(camera, pose.rotation * corner + pose.translation_mm);
    if (sigma_px > 0.0) px += sigma_px * Vec2(noise(rng), noise(rng));
    pixels.push_back(px);
  }
  return pixels;
}

std::vector<std::uint8_t> render_board(const ChessboardCamera& c, const BoardGeometry& board, const BoardPose& pose,
                                       double noise_grey, std::mt19937& rng) {
  constexpr double kBlack = 25.0, kWhite = 230.0, kBackground = 110.0;
  constexpr int kSamples = 4;
  const Mat3 to_board = pose.rotation.transpose();
  const Vec3 lens_in_board = -(to_board * pose.translation_mm);  // the lens, board frame
  const double s = board.square_mm;
  const Vec2 centre(c.truth.cx, c.truth.cy);
  std::normal_distribution<double> noise(0.0, noise_grey);
  std::vector<std::uint8_t> picture(static_cast<std::size_t>(c.chip.Nu) * static_cast<std::size_t>(c.chip.Nv));
  for (int y = 0; y < c.chip.Nv; ++y)
    for (int x = 0; x < c.chip.Nu; ++x) {
      double sum = 0.0;
      for (int sy = 0; sy < kSamples; ++sy)
        for (int sx = 0; sx < kSamples; ++sx) {
          // 0-based pixel x covers 1-based [x + 0.5, x + 1.5).
          const Vec2 observed(x + 0.5 + (sx + 0.5) / kSamples, y + 0.5 + (sy + 0.5) / kSamples);
          const Vec2 ideal = *undistort_pixel(observed, centre, c.truth.k_px2);
          const Vec3 ray_camera((ideal.x() - c.truth.cx) * c.chip.pitch_u() / c.truth.f_mm,
                                (ideal.y() - c.truth.cy) * c.chip.pitch_v() / c.truth.f_mm, 1.0);
          const Vec3 ray = to_board * ray_camera;
          double value = kBackground;
          const double t = -lens_in_board.z() / ray.z();
          if (t > 0.0) {
            const Vec3 hit = lens_in_board + t * ray;
            const double bx = hit.x() / s, by = hit.y() / s;  // in squares from the first corner
            if (bx >= -2.0 && bx < board.columns + 1.0 && by >= -2.0 && by < board.rows + 1.0) {
              const bool squares = bx >= -1.0 && bx < board.columns && by >= -1.0 && by < board.rows;
              const auto parity = static_cast<long>(std::floor(bx)) + static_cast<long>(std::floor(by));
              value = squares && ((parity % 2 + 2) % 2 == 0) ? kBlack : kWhite;
            }
          }
          sum += value;
        }
      const double v = sum / (kSamples * kSamples) + (noise_grey > 0.0 ? noise(rng) : 0.0);
      picture[static_cast<std::size_t>(y) * static_cast<std::size_t>(c.chip.Nu) + static_cast<std::size_t>(x)] =
          static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    }
  return picture;
}

}  // namespace ccdlane::test
