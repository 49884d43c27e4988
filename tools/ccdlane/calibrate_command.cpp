// `ccdlane calibrate camera`: the camera's f, principal point and distortion from chessboard
// pictures, written as the configuration's [camera] table.
//
// OpenCV is used here for finding and refining the chessboard corners only; the pictures
// are read by grey_picture.cpp, the model and its fit are the project's own (core/calibration).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <regex>
#include <sstream>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "app/config_loader.hpp"
#include "core/calibration/camera_calibration.hpp"
#include "core/solver/lane_solver.hpp"
#include "tools/ccdlane/calibration_output.hpp"
#include "tools/ccdlane/checked_output.hpp"
#include "tools/ccdlane/command.hpp"
#include "tools/ccdlane/grey_picture.hpp"
#include "tools/ccdlane/overlay_png.hpp"

namespace ccdlane::cli {
namespace {

using calibration::BoardGeometry;
using calibration::BoardView;
using calibration::CalibrationStatus;
using calibration::CameraCalibration;

struct CameraArgs {
  std::string config;
  std::string board = "9x6";
  double square_mm = 25.0;
  std::string out;
  std::string overlay;
  std::vector<std::string> images;
};

BoardGeometry parse_board(const std::string& text, double square_mm) {
  static const std::regex pattern(R"((\d{1,3})x(\d{1,3}))");
  std::smatch m;
  if (!std::regex_match(text, m, pattern))
    throw UsageError("--board: expected COLUMNSxROWS of inner corners, e.g. 9x6, got \"" + text + "\"");
  const BoardGeometry board{std::stoi(m[1]), std::stoi(m[2]), square_mm};
  if (board.columns < 3 || board.rows < 3)
    throw UsageError("--board: a board needs at least 3x3 inner corners, got " + text);
  if (!(square_mm > 0.0) || !std::isfinite(square_mm))
    throw UsageError("--square-mm: must be > 0, got " + std::to_string(square_mm));
  return board;
}

struct Picture {
  std::string path;
  GreyPicture picture;
  std::vector<Vec2> corners_px;  // 1-based; empty when the board was not found
};

// The sub-pixel search window: large for accuracy, but within half the smallest square
// seen, so that the search never reaches a neighbouring corner.
int refinement_half_window(const std::vector<cv::Point2f>& corners, const BoardGeometry& board) {
  double smallest = 1e9;
  for (int r = 0; r < board.rows; ++r)
    for (int c = 0; c + 1 < board.columns; ++c) {
      const cv::Point2f d = corners[static_cast<std::size_t>(r * board.columns + c + 1)] -
                            corners[static_cast<std::size_t>(r * board.columns + c)];
      smallest = std::min(smallest, std::hypot(static_cast<double>(d.x), static_cast<double>(d.y)));
    }
  for (int r = 0; r + 1 < board.rows; ++r)
    for (int c = 0; c < board.columns; ++c) {
      const cv::Point2f d = corners[static_cast<std::size_t>((r + 1) * board.columns + c)] -
                            corners[static_cast<std::size_t>(r * board.columns + c)];
      smallest = std::min(smallest, std::hypot(static_cast<double>(d.x), static_cast<double>(d.y)));
    }
  return std::clamp(static_cast<int>(0.4 * smallest), 2, 11);
}

// A picture too small to hold the board (4 px per square at least) is refused before
// OpenCV sees it: it asserts on tiny images (Nu = 2) instead of reporting no board.
void require_room_for_board(const Picture& p, const BoardGeometry& board) {
  const int min_width = 4 * (board.columns + 1), min_height = 4 * (board.rows + 1);
  if (p.picture.width < min_width || p.picture.height < min_height)
    throw UsageError(p.path + ": " + std::to_string(p.picture.width) + "x" + std::to_string(p.picture.height) +
                     " pixels cannot show a " + std::to_string(board.columns) + "x" + std::to_string(board.rows) +
                     " board (at least " + std::to_string(min_width) + "x" + std::to_string(min_height) + ")");
}

std::vector<Vec2> find_corners(GreyPicture& picture, const BoardGeometry& board) {
  const cv::Mat grey(picture.height, picture.width, CV_8UC1, picture.pixels.data());  // no copy
  std::vector<cv::Point2f> corners;
  const cv::Size size(board.columns, board.rows);
  if (!cv::findChessboardCorners(grey, size, corners, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE))
    return {};
  const int half = refinement_half_window(corners, board);
  cv::cornerSubPix(grey, corners, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4));
  std::vector<Vec2> pixels;
  // OpenCV's pixel centres are 0-based; the camera model's are 1-based.
  for (const cv::Point2f& p : corners)
    pixels.emplace_back(static_cast<double>(p.x) + 1.0, static_cast<double>(p.y) + 1.0);
  return pixels;
}

std::vector<Picture> read_pictures(const CameraArgs& args, const CameraSpec& chip) {
  std::vector<Picture> pictures;
  for (const std::string& path : args.images) {
    Picture p{path, {}, {}};
    try {
      p.picture = read_grey_picture(path);
    } catch (const std::runtime_error& e) {
      throw UsageError(e.what());
    }
    const GreyPicture& q = p.picture;
    if (!pictures.empty() && (q.width != pictures.front().picture.width || q.height != pictures.front().picture.height))
      throw UsageError(path + ": pictures of different sizes: " + std::to_string(q.width) + "x" +
                       std::to_string(q.height) + ", but " + pictures.front().path + " is " +
                       std::to_string(pictures.front().picture.width) + "x" +
                       std::to_string(pictures.front().picture.height));
    pictures.push_back(std::move(p));
  }
  const GreyPicture& first = pictures.front().picture;
  if (first.width != chip.Nu || first.height != chip.Nv)
    throw UsageError(pictures.front().path + ": the pictures are " + std::to_string(first.width) + "x" +
                     std::to_string(first.height) + ", but " + args.config +
                     "'s [camera] chip has Nu x Nv = " + std::to_string(chip.Nu) + "x" + std::to_string(chip.Nv));
  return pictures;
}

void print_report(std::ostream& out, const std::vector<Picture>& pictures, const std::vector<int>& used,
                  const CameraCalibration& c, const BoardGeometry& board, const CameraSpec& chip) {
  const Vec3 board_centre((board.columns - 1) * board.square_mm / 2.0, (board.rows - 1) * board.square_mm / 2.0, 0.0);
  for (std::size_t v = 0; v < c.views.size(); ++v) {
    const calibration::ViewResidual& view = c.views[v];
    const double distance = (view.pose.rotation * board_centre + view.pose.translation_mm).norm();
    out << pictures[static_cast<std::size_t>(used[v])].path << ": rms " << fixed(view.rms_px, 3) << " px, board tilted "
        << fixed(view.tilt_deg, 1) << " deg, " << fixed(distance, 0) << " mm away\n";
  }
  if (c.status != CalibrationStatus::ok) return;
  const std::size_t corners = used.size() * static_cast<std::size_t>(board.corner_count());
  const double f_px = c.intrinsics.f_mm / chip.pitch_u();
  out << used.size() << " of " << pictures.size() << " pictures, " << corners << " corners: reprojection RMS "
      << fixed(c.rms_px, 3) << " px (sigma per coordinate " << fixed(c.residual_sigma_px, 3) << " px), " << c.iterations
      << " iterations\n"
      << "f_mm  = " << fixed(c.intrinsics.f_mm, 5) << " +/- " << fixed(c.sigma.f_mm, 5) << "  (" << fixed(f_px, 1)
      << " +/- " << fixed(c.sigma.f_mm / chip.pitch_u(), 1) << " px along a row)\n"
      << "cx    = " << fixed(c.intrinsics.cx, 2) << " +/- " << fixed(c.sigma.cx, 2) << " px\n"
      << "cy    = " << fixed(c.intrinsics.cy, 2) << " +/- " << fixed(c.sigma.cy, 2) << " px\n"
      << "k_px2 = " << scientific(c.intrinsics.k_px2, 4) << " +/- " << scientific(c.sigma.k_px2, 2)
      << "  (k f^2 = " << fixed(c.intrinsics.k_px2 * f_px * f_px, 4) << " on normalised coordinates)\n";
}

std::string camera_table(const CameraCalibration& c, const CameraSpec& chip, std::size_t used, std::size_t total) {
  std::ostringstream t;
  t << "# ccdlane calibrate camera: " << used << " of " << total << " pictures, reprojection RMS " << fixed(c.rms_px, 3)
    << " px; sigmas in the comments\n"
    << "[camera]\n"
    << "U_mm = " << toml_float(chip.U_mm) << "\n"
    << "V_mm = " << toml_float(chip.V_mm) << "\n"
    << "Uc_mm = " << toml_float(chip.Uc_mm) << "\n"
    << "Vc_mm = " << toml_float(chip.Vc_mm) << "\n"
    << "Nu = " << chip.Nu << "\n"
    << "Nv = " << chip.Nv << "\n"
    << "f_mm = " << toml_float(c.intrinsics.f_mm) << "  # sigma " << toml_float(c.sigma.f_mm) << "\n"
    << "cx = " << toml_float(c.intrinsics.cx) << "  # sigma " << toml_float(c.sigma.cx) << "\n"
    << "cy = " << toml_float(c.intrinsics.cy) << "  # sigma " << toml_float(c.sigma.cy) << "\n"
    << "k_px2 = " << toml_float(c.intrinsics.k_px2) << "  # sigma " << toml_float(c.sigma.k_px2) << "\n";
  return t.str();
}

// Found corners as green crosses, the model's corners as red ones.
void write_overlays(const std::string& dir, const std::vector<Picture>& pictures, const std::vector<int>& used,
                    const CameraCalibration& c) {
  std::filesystem::create_directories(dir);
  for (std::size_t v = 0; v < c.views.size(); ++v) {
    const Picture& p = pictures[static_cast<std::size_t>(used[v])];
    Overlay overlay(p.picture.view());
    constexpr int kFound = 1, kModel = 0;  // the overlay's line colours: green, red
    std::vector<Pick> found, model;
    for (const Vec2& px : p.corners_px) found.push_back({kFound, px.x(), px.y()});
    for (const Vec2& px : c.views[v].reprojected_px) model.push_back({kModel, px.x(), px.y()});
    overlay.draw_picks(found);
    overlay.draw_picks(model);
    overlay.write_png((std::filesystem::path(dir) / std::filesystem::path(p.path).stem()).string() + ".png");
  }
}

int run_camera(const CameraArgs& args) {
  const Config config = load_config_file(args.config);
  const BoardGeometry board = parse_board(args.board, args.square_mm);
  std::vector<Picture> pictures = read_pictures(args, config.camera);

  std::vector<BoardView> views;
  std::vector<int> used;  // picture index of each view
  for (std::size_t i = 0; i < pictures.size(); ++i) {
    Picture& p = pictures[i];
    require_room_for_board(p, board);
    p.corners_px = find_corners(p.picture, board);
    if (p.corners_px.empty()) {
      std::cerr << p.path << ": no " << args.board
                << " board found (all inner corners must be in the picture), skipped\n";
      continue;
    }
    views.push_back({p.picture.width, p.picture.height, p.corners_px});
    used.push_back(static_cast<int>(i));
  }

  const CameraCalibration c = calibration::calibrate_camera(config.camera, config.f_mm, board, views);
  print_report(std::cerr, pictures, used, c, board, config.camera);
  if (!args.overlay.empty() && !c.views.empty()) write_overlays(args.overlay, pictures, used, c);
  const auto picture_of = [&](int view) {
    return view >= 0 ? pictures[static_cast<std::size_t>(used[static_cast<std::size_t>(view)])].path + ": " : "";
  };
  switch (c.status) {
    case CalibrationStatus::ok: break;
    case CalibrationStatus::too_few_views:
    case CalibrationStatus::not_determined:
    case CalibrationStatus::mixed_sizes:
    case CalibrationStatus::wrong_size: throw UsageError(picture_of(c.failed_view) + c.message);
    case CalibrationStatus::wrong_corner_count:
    case CalibrationStatus::no_convergence: throw std::runtime_error(picture_of(c.failed_view) + c.message);
  }

  const std::string table = camera_table(c, config.camera, views.size(), pictures.size());
  if (args.out.empty()) {
    std::cout << table;
  } else {
    write_file_checked(args.out, table);
    std::cerr << "wrote [camera] to " << args.out << "\n";
  }
  return 0;
}

}  // namespace

CommandAction setup_calibrate_mount(CLI::App& sub);

CommandAction setup_calibrate(CLI::App& sub) {
  sub.require_subcommand(1);
  CommandAction mount = setup_calibrate_mount(*sub.add_subcommand(
      "mount", "the camera's yaw, pitch, roll and height on the vehicle from a drive on a marked road"));
  auto args = std::make_shared<CameraArgs>();
  CLI::App* camera = sub.add_subcommand("camera", "f, principal point and distortion from chessboard pictures");
  camera->add_option("--config", args->config, "configuration (TOML) whose [camera] gives the chip geometry")
      ->required();
  camera->add_option("--board", args->board, "inner corners of the chessboard, COLUMNSxROWS")->capture_default_str();
  camera->add_option("--square-mm", args->square_mm, "side of one square, mm (sets only the reported distances)")
      ->capture_default_str();
  camera->add_option("--out", args->out, "write the [camera] table here (atomically) instead of standard output");
  camera->add_option("--overlay", args->overlay, "draw found (green) and fitted (red) corners, one PNG per picture");
  camera->add_option("images", args->images, "chessboard pictures, all of the chip's size")->required();
  camera->footer(
      "Prints per picture its residual, tilt and distance, then the reprojection RMS and f, cx, cy, k_px2 with "
      "their sigmas (standard error); writes the [camera] table with the chip geometry of --config. Pictures "
      "without the whole board are named and skipped. At least 3 usable pictures, some with the board tilted.");
  CLI::App* mount_app = sub.get_subcommand("mount");
  return [args, mount_app, mount] { return mount_app->parsed() ? mount() : run_camera(*args); };
}

}  // namespace ccdlane::cli
