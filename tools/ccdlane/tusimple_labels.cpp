// TuSimple JSON Lines and CULane text labels -> annotated lanes.
#include "tools/ccdlane/tusimple_labels.hpp"

#include <fstream>
#include <sstream>

#include "tools/ccdlane/command.hpp"
#include "tools/ccdlane/json_output.hpp"

namespace ccdlane::cli {
namespace {

// The lanes' threshold scale and ego marks, once their points are in.
std::vector<AnnotatedLane> finish(std::vector<AnnotatedLane> lanes, int width, int height) {
  std::erase_if(lanes, [](const AnnotatedLane& l) { return l.points.empty(); });
  for (AnnotatedLane& l : lanes) l.threshold_scale = tusimple_threshold_scale(l);
  mark_ego_lanes(lanes, width, height);
  return lanes;
}

}  // namespace

std::vector<LabelledPicture> read_tusimple_labels(const std::string& path, int width, int height) {
  std::ifstream in(path);
  if (!in) throw UsageError(path + ": cannot read the labels");
  std::vector<LabelledPicture> out;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = path + ":" + std::to_string(line) + ": ";
    const Json j = Json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object()) throw UsageError(where + "not a JSON object");
    std::vector<std::string> images;
    for (const char* key : {"image", "raw_file"})
      if (j.contains(key) && j[key].is_string()) images.push_back(j[key].get<std::string>());
    if (images.empty()) throw UsageError(where + "no \"raw_file\" or \"image\" naming the picture");
    if (!j.contains("h_samples") || !j["h_samples"].is_array() || !j.contains("lanes") || !j["lanes"].is_array())
      throw UsageError(where + "a TuSimple label needs \"h_samples\" and \"lanes\" arrays");
    const Json& rows = j["h_samples"];
    std::vector<double> sampled;
    for (const Json& y : rows) {
      if (!y.is_number()) throw UsageError(where + "h_samples and lanes hold numbers");
      sampled.push_back(y.get<double>() + 1.0);  // to 1-based rows
    }
    std::vector<AnnotatedLane> lanes;
    for (const Json& xs : j["lanes"]) {
      if (!xs.is_array() || xs.size() != rows.size())
        throw UsageError(where + "each lane needs one x per h_sample (" + std::to_string(rows.size()) + ")");
      AnnotatedLane lane;
      lane.level = static_cast<int>(lanes.size()) + 1;
      for (std::size_t k = 0; k < rows.size(); ++k) {
        if (!xs[k].is_number()) throw UsageError(where + "h_samples and lanes hold numbers");
        const double x = xs[k].get<double>();
        if (x >= 0.0) lane.points.emplace_back(x + 1.0, sampled[k]);  // to 1-based pixels
      }
      lanes.push_back(std::move(lane));
    }
    out.push_back({std::move(images), finish(std::move(lanes), width, height), std::move(sampled)});
  }
  return out;
}

std::vector<AnnotatedLane> read_culane_lines(const std::string& path, int width, int height) {
  std::ifstream in(path);
  if (!in) throw UsageError(path + ": cannot read the labels");
  std::vector<AnnotatedLane> lanes;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    std::istringstream fields(text);
    AnnotatedLane lane;
    lane.level = line;
    double x = 0, y = 0;
    while (fields >> x) {
      if (!(fields >> y)) throw UsageError(path + ":" + std::to_string(line) + ": x without its y");
      if (x >= 0.0) lane.points.emplace_back(x + 1.0, y + 1.0);
    }
    if (!fields.eof()) throw UsageError(path + ":" + std::to_string(line) + ": not a list of numbers");
    lanes.push_back(std::move(lane));
  }
  return finish(std::move(lanes), width, height);
}

bool same_picture(std::string_view frame_file, std::string_view image) {
  auto ends_with = [](std::string_view a, std::string_view b) {
    return a.size() >= b.size() && a.substr(a.size() - b.size()) == b &&
           (a.size() == b.size() || a[a.size() - b.size() - 1] == '/' || b.front() == '/');
  };
  return !frame_file.empty() && !image.empty() && (ends_with(frame_file, image) || ends_with(image, frame_file));
}

}  // namespace ccdlane::cli
