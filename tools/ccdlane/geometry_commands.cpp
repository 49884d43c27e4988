// `ccdlane project` and `ccdlane ground`: the camera geometry for one point, as JSON.
#include <iostream>
#include <memory>

#include "app/config_loader.hpp"
#include "core/geometry/camera_model.hpp"
#include "tools/ccdlane/command.hpp"
#include "tools/ccdlane/json_output.hpp"

namespace ccdlane::cli {
namespace {

struct GeometryArgs {
  std::string config;
  std::vector<std::string> coords;
};

CameraModel camera_from(const std::string& config_path) {
  const Config c = load_config_file(config_path);
  return CameraModel(c.camera, c.nominal_pose());
}

}  // namespace

CommandAction setup_project(CLI::App& sub) {
  auto args = std::make_shared<GeometryArgs>();
  sub.add_option("config", args->config, "configuration file (TOML)")->required();
  sub.add_option("xyz", args->coords, "fixed-frame point X Y Z in mm")->required()->expected(3);
  sub.footer(
      "Prints {\"pixel\":[px,py]}: the observed (distorted) 1-based pixel, null when the point is "
      "behind the camera or beyond the distortion model's field.");
  return [args] {
    const Vec3 point(parse_number(args->coords[0], "X"), parse_number(args->coords[1], "Y"),
                     parse_number(args->coords[2], "Z"));
    const CameraModel camera = camera_from(args->config);
    print_json_line(std::cout, Json{{"pixel", json_array(camera.pixel_from_point(point))}});
    return 0;
  };
}

CommandAction setup_ground(CLI::App& sub) {
  auto args = std::make_shared<GeometryArgs>();
  sub.add_option("config", args->config, "configuration file (TOML)")->required();
  sub.add_option("pixel", args->coords, "observed 1-based pixel PX PY (fractional allowed)")->required()->expected(2);
  sub.footer(
      "Prints {\"ground_mm\":[x,y,0]}: where the pixel's ray meets the road, null at or above the "
      "horizon or where the pixel has no undistorted counterpart.");
  return [args] {
    const Vec2 pixel(parse_number(args->coords[0], "PX"), parse_number(args->coords[1], "PY"));
    const CameraModel camera = camera_from(args->config);
    print_json_line(std::cout, Json{{"ground_mm", json_array(camera.ground_point_from_pixel(pixel))}});
    return 0;
  };
}

}  // namespace ccdlane::cli
