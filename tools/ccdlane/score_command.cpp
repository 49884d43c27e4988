// `ccdlane score`: how well replay's lines match lane annotations in image space
// (TuSimple's rules; the annotation format is in docs/interfaces.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>

#include "app/config_loader.hpp"
#include "base/image_buffer.hpp"
#include "base/output_path.hpp"
#include "drivers/frames/frame_directory.hpp"
#include "drivers/frames/png.hpp"
#include "tools/ccdlane/command.hpp"
#include "tools/ccdlane/json_output.hpp"
#include "tools/ccdlane/lane_score.hpp"
#include "tools/ccdlane/overlay_png.hpp"
#include "tools/ccdlane/replay_line.hpp"
#include "tools/ccdlane/road_line_picture.hpp"
#include "tools/ccdlane/tusimple_labels.hpp"
#include "tools/ccdlane/video_recording.hpp"

namespace ccdlane::cli {
namespace {

struct ScoreArgs {
  std::string config;
  std::string frames;
  std::string replay;
  std::string annotations;
  bool json = false;
  std::string overlay;
};

std::string stem_of(const std::string& file) {
  const std::filesystem::path p(file);
  return p.stem().string();
}

double ratio(double a, double b) { return b > 0.0 ? a / b : std::nan(""); }

Json score_json(const FrameScore& s) {
  return Json{
      {"lanes", s.lanes},
      {"found", s.found},
      {"reported_lines", s.reported},
      {"false_lines", s.false_lines},
      {"points", s.points},
      {"hit_points", s.hit_points},
      {"accuracy", json_number(ratio(static_cast<double>(s.hit_points), static_cast<double>(s.points)))},
      {"ego_lanes", s.ego_lanes},
      {"ego_found", s.ego_found},
      {"ego_accuracy", json_number(ratio(static_cast<double>(s.ego_hit_points), static_cast<double>(s.ego_points)))}};
}

// Each annotated lane of a frame, in the annotation's order: which it is (its mask's grey
// level or its label's index; the own lane's or not, and where it meets the picture's
// bottom row), its points and those the line that hits most of them hits, whether
// that is enough for it to be found, and the rows of the points that line misses.
Json lane_results_json(std::span<const AnnotatedLane> lanes, const LanePointHits& hits) {
  Json out = Json::array();
  for (std::size_t i = 0; i < lanes.size() && i < hits.size(); ++i) {
    const LaneHits& h = hits[i];
    const auto hit = std::count(h.hit.begin(), h.hit.end(), true);
    const auto points = lanes[i].points.size();
    std::vector<int> missed_rows;
    Json offsets = Json::array();
    for (std::size_t j = 0; j < points && j < h.hit.size(); ++j) {
      if (!h.hit[j]) missed_rows.push_back(static_cast<int>(lanes[i].points[j].y()));
      offsets.push_back(h.offset_px[j] ? json_number(*h.offset_px[j]) : Json());
    }
    out.push_back(Json{{"level", lanes[i].level},
                       {"ego", lanes[i].ego},
                       {"x_bottom_px", json_number(lanes[i].x_bottom)},
                       {"points", points},
                       {"hit_points", hit},
                       {"found", ScoreRules{}.lane_found(static_cast<std::size_t>(hit), points)},
                       {"missed_rows", missed_rows},
                       {"line", h.line >= 0 ? Json(h.line) : Json()},
                       {"offsets_px", std::move(offsets)}});
  }
  return out;
}

// Each reported line of a frame, in the replay's order: its points (its columns on the
// annotated rows), those on a lane, whether it is false, the rows where it is off, and
// the row its nearest mark is on (`nearest_mark_row`, null where the replay does not say):
// below it the line is drawn on from its marks farther off, through a dash gap or where
// nothing was found.
Json line_results_json(std::span<const ReportedLineResult> lines, std::span<const std::optional<double>> nearest_rows) {
  Json out = Json::array();
  for (std::size_t k = 0; k < lines.size(); ++k)
    out.push_back(Json{
        {"line", k},
        {"points", lines[k].points},
        {"on_lane_points", lines[k].on_lane},
        {"false", lines[k].false_line},
        {"off_rows", lines[k].off_rows},
        {"nearest_mark_row", k < nearest_rows.size() && nearest_rows[k] ? json_number(*nearest_rows[k]) : Json()}});
  return out;
}

std::string score_text(const FrameScore& s) {
  char text[240];
  std::snprintf(text, sizeof text,
                "lanes %d/%d found, %d false line%s of %d, accuracy %.3f (%zu/%zu points); ego lanes %d/%d, "
                "accuracy %.3f",
                s.found, s.lanes, s.false_lines, s.false_lines == 1 ? "" : "s", s.reported,
                ratio(static_cast<double>(s.hit_points), static_cast<double>(s.points)), s.hit_points, s.points,
                s.ego_found, s.ego_lanes,
                ratio(static_cast<double>(s.ego_hit_points), static_cast<double>(s.ego_points)));
  return text;
}

// Where the lanes of each frame come from: a directory of PNG masks (or CULane
// .lines.txt files) named as the frames, or one TuSimple label file.
class Annotations {
 public:
  Annotations(const std::string& path, const Config& config)
      : path_(path), width_(config.camera.Nu), height_(config.camera.Nv) {
    if (std::filesystem::is_directory(path)) return;
    if (!std::filesystem::is_regular_file(path))
      throw UsageError(path + ": neither a directory of lane masks nor a TuSimple label file");
    labels_ = read_tusimple_labels(path, width_, height_);
    tusimple_ = true;
  }

  // The lanes of the frame stored in `file` (as frames.csv names it), and for a TuSimple
  // label the rows it samples; empty when it has no annotation.
  std::optional<LabelledPicture> labelled_picture_of(const std::string& file) const {
    if (tusimple_) {
      for (const LabelledPicture& p : labels_)
        for (const std::string& image : p.images)
          if (same_picture(file, image)) return p;
      return std::nullopt;
    }
    const std::string mask_path = path_ + "/" + stem_of(file) + ".png";
    if (std::filesystem::exists(mask_path)) return LabelledPicture{{}, read_mask(mask_path), {}};
    const std::string culane_path = path_ + "/" + stem_of(file) + ".lines.txt";
    if (std::filesystem::exists(culane_path))
      return LabelledPicture{{}, read_culane_lines(culane_path, width_, height_), {}};
    return std::nullopt;
  }

  const char* looked_for() const {
    return tusimple_ ? "a label whose path ends as the frame's file" : "<frame name>.png or <frame name>.lines.txt";
  }

 private:
  std::vector<AnnotatedLane> read_mask(const std::string& mask_path) const {
    OwnedPicture mask;
    try {
      mask = read_png_picture(mask_path);
    } catch (const std::runtime_error& failure) {
      throw UsageError(failure.what());
    }
    if (mask.format != PixelFormat::mono8)
      throw UsageError(mask_path + ": a lane mask is an 8-bit grey PNG (one grey level per lane), this one is colour");
    if (mask.width != width_ || mask.height != height_)
      throw UsageError(mask_path + ": " + std::to_string(mask.width) + "x" + std::to_string(mask.height) +
                       ", the camera is " + std::to_string(width_) + "x" + std::to_string(height_));
    return lanes_of_mask(mask.view());
  }

  std::string path_;
  int width_, height_;
  bool tusimple_ = false;
  std::vector<LabelledPicture> labels_;
};

// The camera at the pose replay solved a frame at (the configured one when it did not).
CameraModel replayed_camera(const ReplayLine& e, const Config& config) {
  CameraPose pose = config.nominal_pose();
  if (e.attitude) {
    pose.attitude = {deg_to_rad(e.attitude->psi_deg), deg_to_rad(e.attitude->theta_deg),
                     deg_to_rad(e.attitude->phi_deg)};
    if (e.attitude->H_mm) pose.H_mm = *e.attitude->H_mm;
  }
  return CameraModel(config.camera, pose);
}

// The lines replay reported for one frame (none when it was not solved).
std::span<const RoadLine> replayed_lines(const ReplayLine& e) {
  return e.attitude ? std::span<const RoadLine>(e.lines) : std::span<const RoadLine>{};
}

// The picture row (1-based) of each line's nearest mark, where the replay gave its view
// range and the point is in front of the camera.
std::vector<std::optional<double>> nearest_mark_rows(const ReplayLine& e, const CameraModel& camera) {
  const std::span<const RoadLine> lines = replayed_lines(e);
  std::vector<std::optional<double>> rows(lines.size());
  for (std::size_t k = 0; k < lines.size() && k < e.near_mm.size(); ++k)
    if (const std::optional<double> x = e.near_mm[k])
      if (const auto px = road_line_pixel(camera, lines[k], *x)) rows[k] = px->y();
  return rows;
}

// TuSimple's benchmark summed over frames (lane.py's bench_one_submit divides by them).
struct LaneEvalTotal {
  double accuracy = 0.0, fp = 0.0, fn = 0.0;
  int frames = 0;
  void add(const LaneEvalScore& s) {
    accuracy += s.accuracy;
    fp += s.fp;
    fn += s.fn;
    ++frames;
  }
  LaneEvalScore mean() const { return {accuracy / frames, fp / frames, fn / frames}; }
};

Json lane_eval_json(const LaneEvalScore& s) {
  return Json{{"accuracy", json_number(s.accuracy)}, {"fp", json_number(s.fp)}, {"fn", json_number(s.fn)}};
}

// Each frame's name, which its annotation takes: a directory's file, a video's frame
// number in six digits.
std::map<std::uint64_t, std::string> frame_names(const ScoreArgs& args, const Config& config, std::string& index_name) {
  std::map<std::uint64_t, std::string> file_of_frame;
  if (is_video_recording(args.frames)) {
    const auto video = open_video_recording(args.frames, config, args.config);
    index_name = args.frames;
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
    return file_of_frame;
  }
  try {
    const FrameDirectory dir(args.frames);
    index_name = dir.csv_path();
    for (std::size_t i = 0; i < dir.size(); ++i) file_of_frame[dir.row(i).index] = dir.row(i).file;
  } catch (const std::runtime_error& e) {
    throw UsageError(e.what());
  }
  return file_of_frame;
}

// `--overlay DIR`: each scored frame's picture with the reported lines as they were
// scored and every annotated point, hit or missed, as NNNNNN.png (the frame's number).
class ScoreOverlays {
 public:
  ScoreOverlays(const ScoreArgs& args, const Config& config) : dir_(args.overlay) {
    if (is_video_recording(args.frames))
      throw UsageError("--overlay needs a frame directory; for a video, `ccdlane replay --overlay` draws the lines");
    if (lies_within(dir_, args.frames))
      throw UsageError(dir_ + ": is or lies inside the frame directory scored (" + args.frames +
                       "); choose another --overlay");
    try {
      frames_ = std::make_unique<FrameDirectory>(args.frames);
    } catch (const std::runtime_error& e) {
      throw UsageError(e.what());
    }
    for (std::size_t i = 0; i < frames_->size(); ++i) row_of_frame_[frames_->row(i).index] = i;
    const auto header = frames_->probe_first();
    const PixelFormat format = header ? header->format() : PixelFormat::mono8;
    const int bits = header && format == PixelFormat::mono16 ? header->significant_bits() : 8;
    buffer_ = std::make_unique<ImageBuffer>(config.camera.Nu, config.camera.Nv, format, bits);
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec) throw UsageError(dir_ + ": cannot create the overlay directory: " + ec.message());
  }

  // A frame that cannot be read is said once on stderr and gets no overlay.
  void write(std::uint64_t frame, const CameraModel& camera, std::span<const RoadLine> lines,
             std::span<const AnnotatedLane> lanes, const LanePointHits& hits) {
    const auto row = row_of_frame_.find(frame);  // there is one: the frame was scored
    if (row == row_of_frame_.end()) return;
    if (frames_->read(row->second, buffer_->view()) != PgmFault::none) {
      std::cerr << "ccdlane score: no overlay for frame " << frame << ": " << frames_->error() << '\n';
      return;
    }
    Overlay o(buffer_->view());
    const ScoreRules rules;
    for (std::size_t k = 0; k < lines.size(); ++k)
      o.draw_road_line_by_rows(camera, lines[k], rules.near_mm, rules.far_mm, static_cast<int>(k));
    for (std::size_t i = 0; i < lanes.size() && i < hits.size(); ++i)
      for (std::size_t p = 0; p < lanes[i].points.size() && p < hits[i].hit.size(); ++p)
        o.draw_lane_point(lanes[i].points[p], hits[i].hit[p], lanes[i].ego);
    char name[32];
    std::snprintf(name, sizeof name, "/%06llu.png", static_cast<unsigned long long>(frame));
    try {
      o.write_png(dir_ + name);
    } catch (const std::runtime_error& e) {
      throw UsageError(e.what());
    }
  }

 private:
  std::string dir_;
  std::unique_ptr<FrameDirectory> frames_;
  std::map<std::uint64_t, std::size_t> row_of_frame_;
  std::unique_ptr<ImageBuffer> buffer_;
};

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
                 "the lanes: a directory of lane masks (one 8-bit grey PNG per frame, named as the frame with .png, "
                 "each lane its own grey level, 0 = no lane) or of CULane labels (<frame name>.lines.txt), or a "
                 "TuSimple label file (JSON Lines: h_samples, lanes, raw_file or image)")
      ->required();
  sub.add_flag("--json", a->json, "print one JSON object (per frame and total) instead of text");
  sub.add_option("--overlay", a->overlay,
                 "write here, per scored frame of a frame directory, its picture with the reported lines as scored "
                 "and each annotated point as a ring, green where a line hits it and red where none does (larger "
                 "for the own lane's lines), as NNNNNN.png (the frame's number)");
  sub.footer(
      "TuSimple's rules in image space: a lane point (the centre of a lane's pixels on a mask row, or a labelled "
      "point) is hit when a reported line, projected into the picture at the frame's solved attitude, passes "
      "within 20 px scaled by width/1280 on that row (for labelled lanes also divided by the cosine of the lane's "
      "angle to the vertical, as TuSimple does); a lane is found when >= 85 % of its points are hit by one line; a "
      "reported line "
      "is false when < 85 % of its points on the annotated rows lie within that distance of a lane. Frames "
      "without a mask are not scored.");
  return [a] {
    const Config config = load_config_file(a->config);
    std::unique_ptr<ScoreOverlays> overlays;
    if (!a->overlay.empty()) overlays = std::make_unique<ScoreOverlays>(*a, config);
    LanePointHits hits;
    std::vector<ReportedLineResult> line_results;
    std::string index_name;  // where the frame numbers come from, for errors
    const std::map<std::uint64_t, std::string> file_of_frame = frame_names(*a, config, index_name);
    std::ifstream in(a->replay);
    if (!in) throw UsageError(a->replay + ": cannot read the replay output");
    const Annotations annotations(a->annotations, config);
    if (config.solver.free.has(FreeParam::f))
      std::cerr << "ccdlane score: " << a->config
                << ": f is solved per frame, but replay's output has only the attitude and height: lines are "
                   "projected with the configuration's f_mm\n";

    FrameScore total;
    LaneEvalTotal eval_total;
    int scored = 0, unannotated = 0;
    Json frames = Json::array();
    std::string line;
    for (int line_number = 1; std::getline(in, line); ++line_number) {
      if (line.empty()) continue;
      ReplayLine e;
      if (const std::string why = parse_replay_line(line, e); !why.empty())
        throw UsageError(a->replay + ":" + std::to_string(line_number) + ": " + why);
      const std::uint64_t frame = e.frame;
      const auto file = file_of_frame.find(frame);
      if (file == file_of_frame.end())
        throw UsageError(a->replay + ":" + std::to_string(line_number) + ": frame " + std::to_string(frame) +
                         " is not in " + index_name);
      const std::optional<LabelledPicture> labelled = annotations.labelled_picture_of(file->second);
      if (!labelled) {
        ++unannotated;
        continue;
      }
      const CameraModel camera = replayed_camera(e, config);
      const FrameScore s = score_frame(labelled->lanes, config.camera.Nu, camera, replayed_lines(e), {},
                                       overlays || a->json ? &hits : nullptr, a->json ? &line_results : nullptr);
      if (overlays) overlays->write(frame, camera, replayed_lines(e), labelled->lanes, hits);
      ++scored;
      total += s;
      std::optional<LaneEvalScore> eval;
      if (!labelled->rows.empty()) {
        eval = lane_eval_frame(labelled->lanes, labelled->rows, config.camera.Nu, camera, replayed_lines(e));
        eval_total.add(*eval);
      }
      if (a->json) {
        Json j{{"frame", frame}, {"file", file->second}};
        j.update(score_json(s));
        if (eval) j["lane_eval"] = lane_eval_json(*eval);
        j["lane_results"] = lane_results_json(labelled->lanes, hits);
        j["line_results"] = line_results_json(line_results, nearest_mark_rows(e, camera));
        frames.push_back(std::move(j));
      } else {
        std::cout << "frame " << frame << " (" << file->second << "): " << score_text(s) << '\n';
      }
    }
    if (scored == 0)
      throw UsageError(a->annotations + ": no mask for any frame of " + a->replay + " (" + std::to_string(unannotated) +
                       " frames looked for " + annotations.looked_for() + ")");
    const double threshold = ScoreRules::threshold_for_width(ScoreRules{}.threshold_px, config.camera.Nu);
    if (a->json) {
      Json t = score_json(total);
      t["frames"] = scored;
      t["frames_without_mask"] = unannotated;
      if (eval_total.frames > 0) t["lane_eval"] = lane_eval_json(eval_total.mean());
      std::cout << Json{{"threshold_px", threshold}, {"frames", std::move(frames)}, {"total", std::move(t)}}.dump()
                << '\n';
    } else {
      std::printf("total: %d frames scored (%d without a mask), threshold %.1f px: %s\n", scored, unannotated,
                  threshold, score_text(total).c_str());
      if (eval_total.frames > 0) {
        const LaneEvalScore m = eval_total.mean();
        std::printf("TuSimple's LaneEval over %d labelled frames: accuracy %.3f, FP %.3f, FN %.3f\n", eval_total.frames,
                    m.accuracy, m.fp, m.fn);
      }
    }
    return std::cout.flush() ? 0 : 1;
  };
}

}  // namespace ccdlane::cli
