// `ccdlane score`: how well replay's lines match lane annotations in image space
// (TuSimple's rules; the annotation format is in docs/interfaces.md).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>

#include "app/config_loader.hpp"
#include "drivers/frames/frame_directory.hpp"
#include "drivers/frames/png.hpp"
#include "tools/ccdlane/command.hpp"
#include "tools/ccdlane/json_output.hpp"
#include "tools/ccdlane/lane_score.hpp"
#include "tools/ccdlane/video_recording.hpp"

namespace ccdlane::cli {
namespace {

struct ScoreArgs {
  std::string config;
  std::string frames;
  std::string replay;
  std::string annotations;
  bool json = false;
};

std::string stem_of(const std::string& file) {
  const std::filesystem::path p(file);
  return p.stem().string();
}

double ratio(double a, double b) { return b > 0.0 ? a / b : std::nan(""); }

Json score_json(const FrameScore& s) {
  return Json{{"lanes", s.lanes},
              {"found", s.found},
              {"reported_lines", s.reported},
              {"false_lines", s.false_lines},
              {"points", s.points},
              {"hit_points", s.hit_points},
              {"accuracy", json_number(ratio(static_cast<double>(s.hit_points), static_cast<double>(s.points)))}};
}

std::string score_text(const FrameScore& s) {
  char text[160];
  std::snprintf(text, sizeof text, "lanes %d/%d found, %d false line%s of %d, accuracy %.3f (%zu/%zu points)", s.found,
                s.lanes, s.false_lines, s.false_lines == 1 ? "" : "s", s.reported,
                ratio(static_cast<double>(s.hit_points), static_cast<double>(s.points)), s.hit_points, s.points);
  return text;
}

}  // namespace

CommandAction setup_score(CLI::App& sub) {
  auto a = std::make_shared<ScoreArgs>();
  sub.add_option("config", a->config, "the configuration replay ran with (TOML): its camera projects the lines")
      ->required();
  sub.add_option("frames", a->frames,
                 "the frame directory replayed (frames.csv names each frame's file), or the video (frame N's mask is "
                 "NNNNNN.png, its number in six digits)")
      ->required();
  sub.add_option("replay", a->replay, "replay's JSON Lines for it (ccdlane replay --out)")->required();
  sub.add_option("annotations", a->annotations,
                 "directory of lane masks: one 8-bit grey PNG per frame, named as the frame with .png, each lane "
                 "its own grey level, 0 = no lane")
      ->required();
  sub.add_flag("--json", a->json, "print one JSON object (per frame and total) instead of text");
  sub.footer(
      "TuSimple's rules in image space: a lane point (the centre of a lane's pixels on a mask row) is hit when a "
      "reported line, projected into the picture at the frame's solved attitude, passes within 20 px scaled by "
      "width/1280 on that row; a lane is found when >= 85 % of its points are hit by one line; a reported line "
      "is false when < 85 % of its points on the annotated rows lie within that distance of a lane. Frames "
      "without a mask are not scored.");
  return [a] {
    const Config config = load_config_file(a->config);
    // Each frame's name, which its mask takes: a directory's file, a video's frame number.
    std::map<std::uint64_t, std::string> file_of_frame;
    std::string index_name;  // where the frame numbers come from, for errors
    if (is_video_recording(a->frames)) {
      const auto video = open_video_recording(a->frames, config, a->config);
      index_name = a->frames;
      char name[32];
      // A container that does not count its frames (MKV) is counted by reading it.
      std::int64_t count = video->frames_in_index();
      if (count == 0) {
        (void)read_video_recording(*video, [](const ImageView&, std::uint64_t, std::int64_t) {});
        count = static_cast<std::int64_t>(video->frame_index() + 1);
      }
      for (std::int64_t i = 0; i < count; ++i) {
        std::snprintf(name, sizeof name, "%06lld", static_cast<long long>(i));
        file_of_frame[static_cast<std::uint64_t>(i)] = name;
      }
    } else {
      try {
        const FrameDirectory dir(a->frames);
        index_name = dir.csv_path();
        for (std::size_t i = 0; i < dir.size(); ++i) file_of_frame[dir.row(i).index] = dir.row(i).file;
      } catch (const std::runtime_error& e) {
        throw UsageError(e.what());
      }
    }
    std::ifstream in(a->replay);
    if (!in) throw UsageError(a->replay + ": cannot read the replay output");
    if (!std::filesystem::is_directory(a->annotations))
      throw UsageError(a->annotations + ": not a directory of lane masks");
    if (config.solver.free.has(FreeParam::H) || config.solver.free.has(FreeParam::f))
      std::cerr << "ccdlane score: " << a->config
                << ": H or f is solved per frame, but replay's output has only the attitude: lines are projected "
                   "with the configuration's H_mm and f_mm\n";

    const ScoreRules rules;
    FrameScore total;
    int scored = 0, unannotated = 0;
    Json frames = Json::array();
    std::string line;
    for (int line_number = 1; std::getline(in, line); ++line_number) {
      if (line.empty()) continue;
      const Json e = Json::parse(line, nullptr, false);
      if (e.is_discarded() || !e.is_object() || !e.contains("frame"))
        throw UsageError(a->replay + ":" + std::to_string(line_number) + ": not a replay JSON object");
      const auto frame = e["frame"].get<std::uint64_t>();
      const auto file = file_of_frame.find(frame);
      if (file == file_of_frame.end())
        throw UsageError(a->replay + ":" + std::to_string(line_number) + ": frame " + std::to_string(frame) +
                         " is not in " + index_name);
      const std::string mask_path = a->annotations + "/" + stem_of(file->second) + ".png";
      if (!std::filesystem::exists(mask_path)) {
        ++unannotated;
        continue;
      }
      OwnedPicture mask;
      try {
        mask = read_png_picture(mask_path);
      } catch (const std::runtime_error& failure) {
        throw UsageError(failure.what());
      }
      if (mask.format != PixelFormat::mono8)
        throw UsageError(mask_path +
                         ": a lane mask is an 8-bit grey PNG (one grey level per lane), this one is colour");
      if (mask.width != config.camera.Nu || mask.height != config.camera.Nv)
        throw UsageError(mask_path + ": " + std::to_string(mask.width) + "x" + std::to_string(mask.height) +
                         ", the camera of " + a->config + " is " + std::to_string(config.camera.Nu) + "x" +
                         std::to_string(config.camera.Nv));
      const std::vector<AnnotatedLane> lanes = lanes_of_mask(mask.view());
      std::vector<LinePrior> reported;
      CameraPose pose = config.nominal_pose();
      if (e.value("psi_deg", Json()).is_number()) {
        pose.attitude = {deg_to_rad(e["psi_deg"].get<double>()), deg_to_rad(e["theta_deg"].get<double>()),
                         deg_to_rad(e["phi_deg"].get<double>())};
        for (const Json& l : e.value("lines", Json::array()))
          reported.push_back({l["y0_mm"].get<double>(), l["m"].get<double>(), l["c_per_mm"].get<double>()});
      }
      const FrameScore s = score_frame(lanes, mask.width, CameraModel(config.camera, pose), reported, rules);
      ++scored;
      total.lanes += s.lanes;
      total.found += s.found;
      total.reported += s.reported;
      total.false_lines += s.false_lines;
      total.points += s.points;
      total.hit_points += s.hit_points;
      if (a->json) {
        Json j{{"frame", frame}, {"file", file->second}};
        j.update(score_json(s));
        frames.push_back(std::move(j));
      } else {
        std::cout << "frame " << frame << " (" << file->second << "): " << score_text(s) << '\n';
      }
    }
    if (scored == 0)
      throw UsageError(a->annotations + ": no mask for any frame of " + a->replay + " (" + std::to_string(unannotated) +
                       " frames looked for <frame name>.png)");
    const double threshold = ScoreRules::threshold_for_width(rules.threshold_px, config.camera.Nu);
    if (a->json) {
      Json t = score_json(total);
      t["frames"] = scored;
      t["frames_without_mask"] = unannotated;
      std::cout << Json{{"threshold_px", threshold}, {"frames", std::move(frames)}, {"total", std::move(t)}}.dump()
                << '\n';
    } else {
      std::printf("total: %d frames scored (%d without a mask), threshold %.1f px: %s\n", scored, unannotated,
                  threshold, score_text(total).c_str());
    }
    return std::cout.flush() ? 0 : 1;
  };
}

}  // namespace ccdlane::cli
