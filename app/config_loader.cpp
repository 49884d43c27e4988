// TOML -> Config with strict checking: every key must be known, of the right type and
// of a possible value; the first problem is reported with file, line and key.
#include "app/config_loader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "base/unique_fd.hpp"
#include "bus/lcm_url.hpp"

namespace ccdlane {
namespace {

// Reads the keys of one table, remembering which it consumed so that whatever is left
// over can be reported as unknown.
class TableReader {
 public:
  TableReader(const toml::table& table, std::string name, const std::string& file)
      : table_(table), name_(std::move(name)), file_(file) {}

  [[noreturn]] void fail(const toml::node* node, const std::string& key, const std::string& what) const {
    std::ostringstream out;
    out << file_;
    const auto& src = node ? node->source() : table_.source();
    if (src.begin.line > 0) out << ':' << src.begin.line;
    out << ": " << qualified(key) << ": " << what;
    throw ConfigError(out.str());
  }

  std::string qualified(const std::string& key) const { return name_.empty() ? key : name_ + "." + key; }

  const toml::node* take(const std::string& key) {
    seen_.insert(key);
    return table_.get(key);
  }

  void number(const std::string& key, double& out) {
    const toml::node* n = take(key);
    if (!n) return;
    if (auto v = n->value<double>(); v && (n->is_floating_point() || n->is_integer())) {
      if (!std::isfinite(*v)) fail(n, key, "must be a finite number");
      out = *v;
      return;
    }
    fail(n, key, std::string("must be a number, got ") + type_name(*n));
  }

  void integer(const std::string& key, int& out) {
    const toml::node* n = take(key);
    if (!n) return;
    if (!n->is_integer()) fail(n, key, std::string("must be an integer, got ") + type_name(*n));
    const auto v = *n->value<std::int64_t>();
    if (v < -1'000'000'000 || v > 1'000'000'000) fail(n, key, "is out of range");
    out = static_cast<int>(v);
  }

  void boolean(const std::string& key, bool& out) {
    const toml::node* n = take(key);
    if (!n) return;
    if (!n->is_boolean()) fail(n, key, std::string("must be true or false, got ") + type_name(*n));
    out = *n->value<bool>();
  }

  void string(const std::string& key, std::string& out) {
    const toml::node* n = take(key);
    if (!n) return;
    if (!n->is_string()) fail(n, key, std::string("must be a string, got ") + type_name(*n));
    out = *n->value<std::string>();
  }

  // A string naming one of a fixed set of values. The message lists them: two or three
  // as "a", "b" or "c", more as one of "a", "b", "c", "d".
  template <class E>
  void choice(const std::string& key, E& out, std::initializer_list<std::pair<const char*, E>> options) {
    const toml::node* n = take(key);
    if (!n) return;
    if (!n->is_string()) fail(n, key, std::string("must be a string, got ") + type_name(*n));
    const std::string value = *n->value<std::string>();
    for (const auto& [name, e] : options) {
      if (value == name) {
        out = e;
        return;
      }
    }
    std::string list = options.size() > 3 ? "one of " : "";
    std::size_t i = 0;
    for (const auto& option : options) {
      if (i > 0) list += (i + 1 == options.size() && options.size() <= 3) ? " or " : ", ";
      list += std::string("\"") + option.first + "\"";
      ++i;
    }
    fail(n, key, "must be " + list + ", got \"" + value + "\"");
  }

  // A [mean, sigma] pair with sigma > 0.
  void prior(const std::string& key, std::optional<Prior>& out) {
    const toml::node* n = take(key);
    if (!n) return;
    const toml::array* a = n->as_array();
    if (!a || a->size() != 2 || !(*a)[0].is_number() || !(*a)[1].is_number())
      fail(n, key, "must be [mean, sigma], two numbers");
    Prior p{*(*a)[0].value<double>(), *(*a)[1].value<double>()};
    if (!std::isfinite(p.mean) || !std::isfinite(p.sigma) || !(p.sigma > 0.0))
      fail(n, key, "needs a finite mean and a sigma > 0");
    out = p;
  }

  const toml::node* node(const std::string& key) const { return table_.get(key); }
  const std::set<std::string>& taken() const { return seen_; }
  const toml::table& table() const { return table_; }

  // Every key not taken is unknown: a misspelt key must not silently become a default.
  void reject_unknown() const {
    for (auto&& [key, value] : table_) {
      const std::string k(key.str());
      if (!seen_.count(k)) fail(&value, k, "unknown key");
    }
  }

  static const char* type_name(const toml::node& n) {
    switch (n.type()) {
      case toml::node_type::string: return "a string";
      case toml::node_type::integer: return "an integer";
      case toml::node_type::floating_point: return "a number";
      case toml::node_type::boolean: return "a boolean";
      case toml::node_type::array: return "an array";
      case toml::node_type::table: return "a table";
      default: return "a date or time";
    }
  }

 private:
  const toml::table& table_;
  std::string name_;
  const std::string& file_;
  std::set<std::string> seen_;
};

// Positive and finite, with a message naming the key.
void require(bool ok, const TableReader& r, const std::string& key, const std::string& what) {
  if (!ok) r.fail(r.node(key), key, what);
}

std::string format_number(double v) {
  std::ostringstream out;
  out.precision(10);
  out << v;
  return out.str();
}

void read_camera(TableReader& r, Config& c) {
  CameraSpec& cam = c.camera;
  r.number("U_mm", cam.U_mm);
  r.number("V_mm", cam.V_mm);
  r.number("Uc_mm", cam.Uc_mm);
  r.number("Vc_mm", cam.Vc_mm);
  r.integer("Nu", cam.Nu);
  r.integer("Nv", cam.Nv);
  r.number("f_mm", c.f_mm);
  const bool has_cx = r.node("cx") != nullptr, has_cy = r.node("cy") != nullptr;
  r.number("cx", cam.cx);
  r.number("cy", cam.cy);
  r.number("k_px2", cam.k_px2);
  r.reject_unknown();

  const std::pair<const char*, double> sizes[] = {
      {"U_mm", cam.U_mm}, {"V_mm", cam.V_mm}, {"Uc_mm", cam.Uc_mm}, {"Vc_mm", cam.Vc_mm}};
  for (const auto& [key, value] : sizes) require(value > 0.0, r, key, "must be > 0, got " + format_number(value));
  require(cam.Nu >= 2, r, "Nu", "must be at least 2, got " + std::to_string(cam.Nu));
  require(cam.Nv >= 2, r, "Nv", "must be at least 2, got " + std::to_string(cam.Nv));
  // Frames are allocated at start-up from these: refuse what cannot be (a 16-bit frame
  // at the limit is 128 MiB, and the daemon holds queue_depth + 2 of them).
  require(cam.Nu <= kMaxImageSide, r, "Nu",
          "must be at most " + std::to_string(kMaxImageSide) + " pixels, got " + std::to_string(cam.Nu));
  require(cam.Nv <= kMaxImageSide, r, "Nv",
          "must be at most " + std::to_string(kMaxImageSide) + " pixels, got " + std::to_string(cam.Nv));
  require(cam.Uc_mm < cam.U_mm, r, "Uc_mm",
          "a cell cannot be as wide as the chip (U_mm = " + format_number(cam.U_mm) + ")");
  require(cam.Vc_mm < cam.V_mm, r, "Vc_mm",
          "a cell cannot be as tall as the chip (V_mm = " + format_number(cam.V_mm) + ")");
  // A cell size from a data sheet is rounded (1920 cells of 2.667 um on a 5.12 mm chip
  // are 5.1206 mm): a thousandth is rounding to four figures, more is a wrong number.
  constexpr double kRoundedCellSize = 1e-3;
  require(cam.Uc_mm * cam.Nu <= cam.U_mm * (1.0 + kRoundedCellSize), r, "Nu",
          "Nu cells of Uc_mm do not fit on a chip U_mm wide");
  require(cam.Vc_mm * cam.Nv <= cam.V_mm * (1.0 + kRoundedCellSize), r, "Nv",
          "Nv cells of Vc_mm do not fit on a chip V_mm tall");
  require(c.f_mm > 0.0, r, "f_mm", "must be > 0, got " + format_number(c.f_mm));
  if (!has_cx) cam.cx = CameraSpec::default_cx(cam.Nu);
  if (!has_cy) cam.cy = CameraSpec::default_cy(cam.Nv);
  require(cam.cx >= 0.5 && cam.cx <= cam.Nu + 0.5, r, "cx", "principal point must lie on the chip (0.5 .. Nu+0.5)");
  require(cam.cy >= 0.5 && cam.cy <= cam.Nv + 0.5, r, "cy", "principal point must lie on the chip (0.5 .. Nv+0.5)");
  // The division model is one-to-one over the picture only while k r^2 stays inside
  // (-1, 1) at the corners: beyond, barrel pixels have no ideal point and pincushion
  // pixels fold back onto ones nearer the centre.
  const double corner2 = std::pow(std::max(cam.cx - 0.5, cam.Nu + 0.5 - cam.cx), 2) +
                         std::pow(std::max(cam.cy - 0.5, cam.Nv + 0.5 - cam.cy), 2);
  require(std::abs(cam.k_px2) * corner2 < 1.0, r, "k_px2",
          "distortion this strong makes the image corners ambiguous (|k_px2| * r_corner^2 must be < 1)");
}

void read_mount(TableReader& r, Config& c) {
  r.number("yM_mm", c.camera.yM_mm);
  r.number("zM_mm", c.camera.zM_mm);
  r.number("H_mm", c.H_mm);
  r.reject_unknown();
  require(c.H_mm > 0.0, r, "H_mm", "the camera must be above the road (H_mm > 0), got " + format_number(c.H_mm));
}

void read_attitude(TableReader& r, Config& c) {
  r.number("psi_deg", c.attitude.psi_deg);
  r.number("theta_deg", c.attitude.theta_deg);
  r.number("phi_deg", c.attitude.phi_deg);
  r.reject_unknown();
  require(std::abs(c.attitude.psi_deg) < 90.0, r, "psi_deg", "must be within (-90, 90) degrees");
  require(std::abs(c.attitude.theta_deg) < 90.0, r, "theta_deg", "must be within (-90, 90) degrees");
  require(std::abs(c.attitude.phi_deg) <= 180.0, r, "phi_deg", "must be within [-180, 180] degrees");
}

void read_solver(TableReader& r, Config& c) {
  r.choice("mode", c.solver.mode, {{"reprojection", SolverMode::reprojection}, {"paper", SolverMode::paper}});

  if (const toml::node* n = r.take("free")) {
    const toml::array* a = n->as_array();
    if (!a) r.fail(n, "free", "must be an array of names (psi theta phi H f y0 m c)");
    FreeSet set;
    for (const toml::node& e : *a) {
      const auto name = e.value<std::string>();
      const auto p = name ? free_param_from_name(*name) : std::nullopt;
      if (!p)
        r.fail(&e, "free",
               "unknown parameter " + (name ? "\"" + *name + "\"" : std::string("(not a string)")) +
                   "; expected any of psi theta phi H f y0 m c");
      set.add(*p);
    }
    if (set == FreeSet{}) r.fail(n, "free", "must name at least one parameter (psi theta phi H f y0 m c)");
    c.solver.free = set;
  }
  // "curved" is the default, but a free c asks for a curvature per line: the straight
  // model's, so a free list naming c keeps meaning what it always did.
  if (c.solver.free.has(FreeParam::c) && !r.node("line_model")) c.solver.line_model = LineModel::per_line;
  r.choice("line_model", c.solver.line_model,
           {{"straight", LineModel::per_line}, {"curved", LineModel::shared_curvature}});
  if (c.solver.line_model == LineModel::shared_curvature && c.solver.free.has(FreeParam::c))
    r.fail(r.node("line_model"), "line_model",
           "\"curved\" solves one curvature shared by all lines: leave c out of free (c frees one per line)");
  r.number("pixel_sigma", c.solver.pixel_sigma);
  r.integer("max_iterations", c.solver.max_iterations);
  r.string("picks", c.solver.picks);
  r.reject_unknown();
  require(c.solver.pixel_sigma >= 1e-3 && c.solver.pixel_sigma <= 1000.0, r, "pixel_sigma",
          "must be 0.001 .. 1000 pixels");
  require(c.solver.max_iterations >= 1 && c.solver.max_iterations <= 10000, r, "max_iterations",
          "must be between 1 and 10000");
}

// The physical range of a prior's mean and sigma: beyond it (a sigma of 1e-300 or 1e300,
// a mean of 1e300) every solve came out rank deficient instead of the file being refused.
struct PriorRange {
  const char* key;
  std::optional<Prior> SolverPriors::*prior;
  double min_mean, max_mean, min_sigma, max_sigma;
};

void read_prior(TableReader& r, Config& c) {
  static constexpr PriorRange kRanges[] = {
      {"psi_deg", &SolverPriors::psi_deg, -90.0, 90.0, 1e-3, 90.0},
      {"theta_deg", &SolverPriors::theta_deg, -90.0, 90.0, 1e-3, 90.0},
      {"phi_deg", &SolverPriors::phi_deg, -90.0, 90.0, 1e-3, 90.0},
      {"H_mm", &SolverPriors::H_mm, 1.0, 20000.0, 1e-2, 20000.0},
      {"f_mm", &SolverPriors::f_mm, 0.1, 1000.0, 1e-4, 1000.0},
      {"lane_width_mm", &SolverPriors::lane_width_mm, 1000.0, 10000.0, 1e-2, 10000.0}};
  for (const PriorRange& k : kRanges) {
    std::optional<Prior>& p = c.prior.*k.prior;
    r.prior(k.key, p);
    if (!p) continue;
    require(p->mean >= k.min_mean && p->mean <= k.max_mean, r, k.key,
            "mean must be " + format_number(k.min_mean) + " .. " + format_number(k.max_mean) + ", got " +
                format_number(p->mean));
    require(p->sigma >= k.min_sigma && p->sigma <= k.max_sigma, r, k.key,
            "sigma must be " + format_number(k.min_sigma) + " .. " + format_number(k.max_sigma) + ", got " +
                format_number(p->sigma));
  }
  r.reject_unknown();
}

void read_line(TableReader& r, Config& c) {
  RoadLine line;
  r.number("y0_mm", line.y0_mm);
  r.number("m", line.m);
  r.number("c_per_mm", line.c_per_mm);
  r.reject_unknown();
  c.lines.push_back(line);
}

void read_gyro(TableReader& r, Config& c) {
  r.number("sigma_deg", c.gyro.sigma_deg);
  r.string("device", c.gyro.device);
  r.reject_unknown();
  require(c.gyro.sigma_deg >= 1e-3 && c.gyro.sigma_deg <= 90.0, r, "sigma_deg", "must be 0.001 .. 90 degrees");
}

void read_source(TableReader& r, Config& c) {
  r.choice("kind", c.source.kind,
           {{"synth", SourceKind::synth},
            {"frames", SourceKind::frames},
            {"v4l2", SourceKind::v4l2},
            {"aravis", SourceKind::aravis},
            {"video", SourceKind::video}});
  r.string("device", c.source.device);
  r.string("camera", c.source.camera);
  r.string("path", c.source.path);
  r.number("rate_hz", c.source.rate_hz);
  r.boolean("loop", c.source.loop);
  r.choice("pixel_format", c.source.pixel_format,
           {{"auto", SourcePixels::automatic}, {"grey", SourcePixels::grey}, {"colour", SourcePixels::colour}});
  r.string("device_format", c.source.device_format);
  r.reject_unknown();
  require(c.source.rate_hz == 0.0 || (c.source.rate_hz >= 0.1 && c.source.rate_hz <= 1000.0), r, "rate_hz",
          "must be 0 (as recorded) or 0.1 .. 1000");
  require(c.source.kind != SourceKind::frames || !c.source.path.empty(), r, "path",
          "a \"frames\" source needs path = the frame directory");
  require(c.source.kind != SourceKind::video || !c.source.path.empty(), r, "path",
          "a \"video\" source needs path = the video file");
}

void read_lcm(TableReader& r, Config& c) {
  r.string("url", c.lcm.url);
  r.string("prefix", c.lcm.prefix);
  r.boolean("publish_frames", c.lcm.publish_frames);
  r.string("instance", c.lcm.instance);
  r.reject_unknown();
  const std::string url_problem = lcm_url_problem(c.lcm.url);
  require(url_problem.empty(), r, "url", url_problem);
  // LCM channel names are at most 63 bytes; leave room for the longest suffix.
  require(c.lcm.prefix.size() <= 48, r, "prefix", "must be at most 48 characters");
  const bool plain = std::all_of(c.lcm.prefix.begin(), c.lcm.prefix.end(), [](unsigned char ch) {
    return std::isalnum(ch) || ch == '_' || ch == '-' || ch == '.' || ch == '/';
  });
  require(plain, r, "prefix", "may hold only letters, digits and _ - . /");
  // A name for logs and monitors: short, printable, no quoting needed anywhere.
  require(c.lcm.instance.size() <= kMaxInstanceChars, r, "instance",
          "must be at most " + std::to_string(kMaxInstanceChars) + " characters");
  const bool name = std::all_of(c.lcm.instance.begin(), c.lcm.instance.end(), [](unsigned char ch) {
    return std::isalnum(ch) || ch == '_' || ch == '-' || ch == '.' || ch == ':' || ch == '/' || ch == '@';
  });
  require(name, r, "instance", "may hold only letters, digits and _ - . : / @ (\"\" = host:pid)");
}

void read_realtime(TableReader& r, Config& c) {
  r.boolean("mlock", c.realtime.mlock);
  r.integer("capture_priority", c.realtime.capture_priority);
  r.integer("processing_priority", c.realtime.processing_priority);
  r.integer("gyro_priority", c.realtime.gyro_priority);
  if (const toml::node* n = r.take("cpus")) {
    const toml::array* a = n->as_array();
    if (!a) r.fail(n, "cpus", "must be an array of CPU numbers");
    for (const toml::node& e : *a) {
      if (!e.is_integer() || *e.value<std::int64_t>() < 0 || *e.value<std::int64_t>() > 1023)
        r.fail(&e, "cpus", "must hold CPU numbers 0..1023");
      c.realtime.cpus.push_back(static_cast<int>(*e.value<std::int64_t>()));
    }
  }
  r.reject_unknown();
  require(c.realtime.capture_priority >= 0 && c.realtime.capture_priority <= 99, r, "capture_priority",
          "must be a SCHED_FIFO priority 0..99");
  require(c.realtime.processing_priority >= 0 && c.realtime.processing_priority <= 99, r, "processing_priority",
          "must be a SCHED_FIFO priority 0..99");
  require(c.realtime.gyro_priority >= 0 && c.realtime.gyro_priority <= 99, r, "gyro_priority",
          "must be a SCHED_FIFO priority 0..99");
}

void read_daemon(TableReader& r, Config& c) {
  r.integer("queue_depth", c.daemon.queue_depth);
  r.number("stall_timeout_s", c.daemon.stall_timeout_s);
  r.reject_unknown();
  // The daemon's frame pool holds queue_depth + 2 frames, at most 64.
  require(c.daemon.queue_depth >= 1 && c.daemon.queue_depth <= 62, r, "queue_depth", "must be between 1 and 62 frames");
  require(c.daemon.stall_timeout_s >= 0.1 && c.daemon.stall_timeout_s <= 3600.0, r, "stall_timeout_s",
          "must be between 0.1 and 3600 seconds");
}

void read_synth(TableReader& r, Config& c) {
  SynthConfig& s = c.synth;
  int seed = static_cast<int>(s.seed);
  r.integer("seed", seed);
  require(seed >= 0, r, "seed", "must be >= 0");
  s.seed = static_cast<std::uint64_t>(seed);
  r.integer("frames", s.frames);
  r.number("rate_hz", s.rate_hz);
  r.number("speed_mps", s.speed_mps);
  r.integer("lanes", s.lanes);
  r.integer("ego_lane", s.ego_lane);
  r.number("lane_width_mm", s.lane_width_mm);
  r.number("line_width_mm", s.line_width_mm);
  r.number("edge_line_width_mm", s.edge_line_width_mm);
  r.choice("dashed", s.dashed, {{"inner", DashedLines::inner}, {"all", DashedLines::all}, {"none", DashedLines::none}});
  r.number("dash_length_mm", s.dash_length_mm);
  r.number("dash_gap_mm", s.dash_gap_mm);
  r.number("curvature_per_mm", s.curvature_per_mm);
  r.number("weave_mm", s.weave_mm);
  r.number("weave_period_s", s.weave_period_s);
  r.number("pitch_bump_deg", s.pitch_bump_deg);
  r.number("bump_period_s", s.bump_period_s);
  r.number("roll_sway_deg", s.roll_sway_deg);
  r.number("roll_period_s", s.roll_period_s);
  r.number("lane_change_at_s", s.lane_change_at_s);
  r.number("lane_change_s", s.lane_change_s);
  r.number("asphalt_grey", s.asphalt_grey);
  r.number("texture_grey", s.texture_grey);
  r.number("paint_grey", s.paint_grey);
  r.number("sky_grey", s.sky_grey);
  r.number("verge_grey", s.verge_grey);
  r.number("gradient", s.gradient);
  r.number("shadow_depth", s.shadow_depth);
  r.number("noise_sigma", s.noise_sigma);
  r.number("blur_px", s.blur_px);
  r.integer("supersample", s.supersample);
  r.integer("bits", s.bits);
  r.boolean("gyro", s.gyro);
  r.number("gyro_noise_deg", s.gyro_noise_deg);
  r.boolean("colour", s.colour);
  r.boolean("yellow_left_edge", s.yellow_left_edge);
  r.number("yellow_paint_grey", s.yellow_paint_grey);
  r.choice("surface", s.surface, {{"asphalt", RoadSurface::asphalt}, {"concrete", RoadSurface::concrete}});
  r.number("concrete_grey", s.concrete_grey);
  r.boolean("hard_shadows", s.hard_shadows);
  r.boolean("barrier", s.barrier);
  r.boolean("road_markings", s.road_markings);
  r.boolean("crosswalks", s.crosswalks);
  r.boolean("sealed_cracks", s.sealed_cracks);
  r.number("contrast_borders_mm", s.contrast_borders_mm);
  r.integer("cars", s.cars);
  r.boolean("night", s.night);
  r.reject_unknown();

  require(s.frames >= 1 && s.frames <= 1'000'000, r, "frames", "must be 1..1000000");
  require(s.contrast_borders_mm >= 0.0 && s.contrast_borders_mm <= 500.0, r, "contrast_borders_mm", "must be 0..500");
  require(s.rate_hz > 0.0 && s.rate_hz <= 1000.0, r, "rate_hz", "must be > 0 and <= 1000");
  require(s.speed_mps >= 0.0 && s.speed_mps <= 100.0, r, "speed_mps", "must be 0..100");
  require(s.lanes >= 2 && s.lanes <= 4, r, "lanes", "must be 2..4, got " + std::to_string(s.lanes));
  require(s.ego_lane >= 0 && s.ego_lane < s.lanes, r, "ego_lane",
          "must be a lane of the road, 0.." + std::to_string(s.lanes - 1));
  require(s.lane_width_mm >= 2000.0 && s.lane_width_mm <= 6000.0, r, "lane_width_mm", "must be 2000..6000");
  require(s.line_width_mm > 0.0 && s.line_width_mm <= 500.0, r, "line_width_mm", "must be > 0 and <= 500");
  require(s.edge_line_width_mm > 0.0 && s.edge_line_width_mm <= 500.0, r, "edge_line_width_mm",
          "must be > 0 and <= 500");
  require(s.dash_length_mm > 0.0, r, "dash_length_mm", "must be > 0");
  require(s.dash_gap_mm >= 0.0, r, "dash_gap_mm", "must be >= 0");
  require(std::abs(s.curvature_per_mm) <= 1e-5, r, "curvature_per_mm",
          "must be within +-1e-5 (a radius of at least 50 m)");
  require(s.weave_mm >= 0.0 && s.weave_mm < s.lane_width_mm / 2, r, "weave_mm", "must be 0 .. half a lane");
  const std::pair<const char*, double> periods[] = {{"weave_period_s", s.weave_period_s},
                                                    {"bump_period_s", s.bump_period_s},
                                                    {"roll_period_s", s.roll_period_s},
                                                    {"lane_change_s", s.lane_change_s}};
  for (const auto& [key, value] : periods) require(value > 0.0, r, key, "must be > 0");
  require(std::abs(s.pitch_bump_deg) <= 10.0, r, "pitch_bump_deg", "must be within +-10");
  require(std::abs(s.roll_sway_deg) <= 10.0, r, "roll_sway_deg", "must be within +-10");
  require(s.lane_change_at_s < 0.0 || s.ego_lane + 1 < s.lanes, r, "lane_change_at_s",
          "a lane change goes to the lane on the right, and ego_lane is the rightmost");
  const std::pair<const char*, double> greys[] = {{"asphalt_grey", s.asphalt_grey},
                                                  {"paint_grey", s.paint_grey},
                                                  {"sky_grey", s.sky_grey},
                                                  {"verge_grey", s.verge_grey},
                                                  {"yellow_paint_grey", s.yellow_paint_grey},
                                                  {"concrete_grey", s.concrete_grey}};
  for (const auto& [key, value] : greys) require(value >= 0.0 && value <= 255.0, r, key, "must be a grey level 0..255");
  require(s.texture_grey >= 0.0 && s.texture_grey <= 100.0, r, "texture_grey", "must be 0..100");
  require(s.gradient >= 0.0 && s.gradient < 1.0, r, "gradient", "must be 0 .. < 1");
  require(s.shadow_depth >= 0.0 && s.shadow_depth < 1.0, r, "shadow_depth", "must be 0 .. < 1");
  require(s.noise_sigma >= 0.0 && s.noise_sigma <= 100.0, r, "noise_sigma", "must be 0..100");
  require(s.blur_px >= 0.0 && s.blur_px <= 10.0, r, "blur_px", "must be 0..10");
  require(s.supersample >= 1 && s.supersample <= 16, r, "supersample", "must be 1..16");
  require(s.cars >= 0 && s.cars <= kMaxSynthCars, r, "cars", "must be 0.." + std::to_string(kMaxSynthCars));
  require(s.bits >= 8 && s.bits <= 16, r, "bits", "must be 8 (mono8) or 9..16 (mono16)");
  require(!s.colour || s.bits == 8, r, "colour", "colour frames are rgb8: leave bits at 8");
  require(s.gyro_noise_deg >= 0.0 && s.gyro_noise_deg <= 10.0, r, "gyro_noise_deg", "must be 0..10");
}

void read_detection(TableReader& r, Config& c) {
  DetectionConfig& d = c.detection;
  r.number("mark_width_mm", d.mark_width_mm);
  r.number("min_mark_width_mm", d.min_mark_width_mm);
  r.number("max_mark_width_mm", d.max_mark_width_mm);
  r.number("min_contrast", d.min_contrast);
  r.number("min_range_mm", d.min_range_mm);
  r.number("max_range_mm", d.max_range_mm);
  r.integer("roi_top_px", d.roi_top_px);
  r.integer("hood_px", d.hood_px);
  r.integer("max_lines", d.max_lines);
  r.integer("max_picks", d.max_picks);
  r.integer("min_marks", d.min_marks);
  r.number("departure_mm", d.departure_mm);
  r.reject_unknown();
  require(d.mark_width_mm >= 50.0 && d.mark_width_mm <= 500.0, r, "mark_width_mm", "must be 50..500");
  require(d.min_mark_width_mm >= 30.0 && d.min_mark_width_mm < d.max_mark_width_mm, r, "min_mark_width_mm",
          "must be 30 .. max_mark_width_mm (" + format_number(d.max_mark_width_mm) + ")");
  require(d.max_mark_width_mm <= 1000.0, r, "max_mark_width_mm", "must be <= 1000");
  require(d.mark_width_mm >= d.min_mark_width_mm && d.mark_width_mm <= d.max_mark_width_mm, r, "mark_width_mm",
          "must lie within min_mark_width_mm .. max_mark_width_mm (" + format_number(d.min_mark_width_mm) + " .. " +
              format_number(d.max_mark_width_mm) + "); set those too");
  require(d.min_contrast > 0.0 && d.min_contrast <= 200.0, r, "min_contrast", "must be > 0 and <= 200");
  require(d.min_range_mm >= 500.0, r, "min_range_mm", "must be >= 500");
  require(d.max_range_mm > d.min_range_mm * 1.5 && d.max_range_mm <= 200000.0, r, "max_range_mm",
          "must be more than 1.5 x min_range_mm and <= 200000");
  require(d.max_lines >= 2 && d.max_lines <= kMaxDetectedLines, r, "max_lines",
          "must be 2.." + std::to_string(kMaxDetectedLines));
  require(d.max_picks >= 20 && d.max_picks <= 4000, r, "max_picks", "must be 20..4000");
  require(d.min_marks >= 3 && d.min_marks <= 200, r, "min_marks", "must be 3..200");
  require(d.departure_mm >= 0.0 && d.departure_mm <= 5000.0, r, "departure_mm", "must be 0..5000");
  // [camera] is read first: the picture's height is known here.
  require(d.roi_top_px >= 0, r, "roi_top_px", "must be >= 0");
  require(d.hood_px >= 0, r, "hood_px", "must be >= 0");
  require(d.roi_top_px + d.hood_px <= c.camera.Nv - 10, r, r.node("hood_px") ? "hood_px" : "roi_top_px",
          "roi_top_px + hood_px must leave at least 10 rows of the picture's " + std::to_string(c.camera.Nv));
}

void read_vehicle(TableReader& r, Config& c) {
  ldw::VehicleConfig& v = c.vehicle;
  r.number("speed_kmh", v.speed_kmh);
  r.number("width_mm", v.width_mm);
  r.number("front_axle_behind_camera_mm", v.front_axle_behind_camera_mm);
  r.number("camera_left_of_centre_mm", v.camera_left_of_centre_mm);
  r.reject_unknown();
  require(v.speed_kmh >= 0.0 && v.speed_kmh <= 300.0, r, "speed_kmh", "must be 0..300");
  require(v.width_mm >= 1000.0 && v.width_mm <= 3000.0, r, "width_mm", "must be 1000..3000 (a road vehicle's track)");
  require(std::abs(v.front_axle_behind_camera_mm) <= 10000.0, r, "front_axle_behind_camera_mm",
          "must be within +-10000 (negative: the axle is ahead of the camera)");
  require(std::abs(v.camera_left_of_centre_mm) <= v.width_mm / 2, r, "camera_left_of_centre_mm",
          "must put the camera within the vehicle's width (+-width_mm / 2)");
}

void read_ldw(TableReader& r, Config& c) {
  ldw::LdwWarningConfig& w = c.ldw.warning;
  ldw::LaneFilterConfig& f = c.ldw.filter;
  r.number("min_speed_kmh", w.min_speed_kmh);
  r.number("speed_hysteresis_kmh", w.speed_hysteresis_kmh);
  r.number("indicator_hold_s", w.indicator_hold_s);
  r.number("warning_duration_s", w.warning_duration_s);
  r.number("earliest_warning_mm", w.earliest_warning_mm);
  r.number("latest_warning_mm", w.latest_warning_mm);
  r.number("earliest_margin_mm", w.earliest_margin_mm);
  r.number("tlc_threshold_s", w.tlc_threshold_s);
  r.number("min_threshold_mm", w.min_threshold_mm);
  r.number("min_approach_mps", w.min_approach_mps);
  r.number("rearm_mm", w.rearm_mm);
  r.number("rearm_margin_mm", w.rearm_margin_mm);
  r.number("coast_s", f.coast_s);
  r.number("gate_probability", f.gate_probability);
  r.integer("confirm_updates", f.confirm_updates);
  r.number("line_width_mm", c.ldw.line_width_mm);
  r.number("max_offset_sigma_mm", c.ldw.max_offset_sigma_mm);
  r.reject_unknown();
  require(w.min_speed_kmh >= 0.0 && w.min_speed_kmh <= 200.0, r, "min_speed_kmh", "must be 0..200");
  require(w.speed_hysteresis_kmh >= 0.0 && w.speed_hysteresis_kmh <= 50.0, r, "speed_hysteresis_kmh", "must be 0..50");
  require(w.indicator_hold_s >= 0.0 && w.indicator_hold_s <= 60.0, r, "indicator_hold_s", "must be 0..60");
  require(w.warning_duration_s > 0.0 && w.warning_duration_s <= 10.0, r, "warning_duration_s", "must be > 0 and <= 10");
  require(w.latest_warning_mm < 0.0 && w.latest_warning_mm >= -2000.0, r, "latest_warning_mm",
          "must be beyond the line: -2000 .. < 0");
  require(w.earliest_warning_mm > 0.0 && w.earliest_warning_mm <= 2000.0, r, "earliest_warning_mm",
          "must be inside the lane: > 0 and <= 2000");
  require(w.earliest_margin_mm >= 0.0 && w.earliest_margin_mm < w.earliest_warning_mm, r, "earliest_margin_mm",
          "must be 0 .. < earliest_warning_mm (" + format_number(w.earliest_warning_mm) + ")");
  require(w.tlc_threshold_s >= 0.0 && w.tlc_threshold_s <= 5.0, r, "tlc_threshold_s", "must be 0..5");
  require(
      w.min_threshold_mm > w.latest_warning_mm && w.min_threshold_mm <= w.earliest_warning_mm - w.earliest_margin_mm, r,
      "min_threshold_mm", "must lie between latest_warning_mm and earliest_warning_mm - earliest_margin_mm");
  require(w.min_approach_mps > 0.0 && w.min_approach_mps <= 1.0, r, "min_approach_mps", "must be > 0 and <= 1");
  require(w.rearm_mm >= 0.0 && w.rearm_mm <= 2000.0, r, "rearm_mm", "must be 0..2000");
  require(w.rearm_margin_mm >= 0.0 && w.rearm_margin_mm <= 2000.0, r, "rearm_margin_mm", "must be 0..2000");
  require(f.coast_s >= 0.0 && f.coast_s <= 10.0, r, "coast_s", "must be 0..10");
  require(f.gate_probability > 0.5 && f.gate_probability < 1.0, r, "gate_probability", "must be within (0.5, 1)");
  require(f.confirm_updates >= 1 && f.confirm_updates <= 100, r, "confirm_updates", "must be 1..100");
  require(c.ldw.line_width_mm >= 0.0 && c.ldw.line_width_mm <= 500.0, r, "line_width_mm", "must be 0..500");
  require(c.ldw.max_offset_sigma_mm > 0.0 && c.ldw.max_offset_sigma_mm <= 2000.0, r, "max_offset_sigma_mm",
          "must be > 0 and <= 2000");
}

void read_calibration(TableReader& r, Config& c) {
  CalibrationConfig& k = c.calibration;
  r.boolean("online", k.online);
  r.number("min_speed_kmh", k.min_speed_kmh);
  r.number("min_radius_m", k.min_radius_m);
  r.number("max_correction_deg", k.max_correction_deg);
  r.number("max_change_deg_per_min", k.max_change_deg_per_min);
  r.integer("frames_needed", k.frames_needed);
  r.string("state_file", k.state_file);
  r.number("save_period_s", k.save_period_s);
  r.reject_unknown();
  require(k.min_speed_kmh >= 0.0 && k.min_speed_kmh <= 200.0, r, "min_speed_kmh", "must be 0..200");
  require(k.min_radius_m >= 100.0 && k.min_radius_m <= 1e6, r, "min_radius_m", "must be 100..1000000");
  require(k.max_correction_deg > 0.0 && k.max_correction_deg <= 10.0, r, "max_correction_deg", "must be > 0 and <= 10");
  require(k.max_change_deg_per_min > 0.0 && k.max_change_deg_per_min <= 60.0, r, "max_change_deg_per_min",
          "must be > 0 and <= 60");
  require(k.frames_needed >= 30 && k.frames_needed <= 1'000'000, r, "frames_needed", "must be 30..1000000");
  require(k.state_file.empty() || k.state_file.front() == '/', r, "state_file",
          "must be an absolute path (or left out: $STATE_DIRECTORY/mount-refinement.toml)");
  require(k.save_period_s >= 1.0 && k.save_period_s <= 86400.0, r, "save_period_s", "must be 1..86400");
}

using SectionReader = void (*)(TableReader&, Config&);
struct Section {
  const char* name;
  SectionReader read;
};
constexpr Section kSections[] = {
    {"camera", read_camera},   {"mount", read_mount}, {"attitude", read_attitude},
    {"solver", read_solver},   {"prior", read_prior}, {"gyro", read_gyro},
    {"source", read_source},   {"lcm", read_lcm},     {"realtime", read_realtime},
    {"daemon", read_daemon},   {"synth", read_synth}, {"detection", read_detection},
    {"vehicle", read_vehicle}, {"ldw", read_ldw},     {"calibration", read_calibration},
};

}  // namespace

Config parse_config(std::string_view toml_text, const std::string& source_name) {
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    std::ostringstream out;
    out << source_name << ':' << e.source().begin.line << ": " << e.description();
    throw ConfigError(out.str());
  }

  Config c = default_config();
  c.path = source_name;
  TableReader top(root, "", source_name);
  // [camera] before [mount] matters only for defaults; each table is read exactly once.
  for (const Section& s : kSections) {
    const toml::node* n = top.take(s.name);
    if (!n) {
      if (std::string(s.name) == "camera") {  // defaults still need their derived values
        toml::table empty;
        TableReader r(empty, s.name, source_name);
        s.read(r, c);
      }
      continue;
    }
    const toml::table* t = n->as_table();
    if (!t) top.fail(n, s.name, "must be a table ([" + std::string(s.name) + "])");
    TableReader r(*t, s.name, source_name);
    s.read(r, c);
  }
  if (const toml::node* n = top.take("lines")) {
    const toml::array* a = n->as_array();
    if (!a || !a->is_array_of_tables()) top.fail(n, "lines", "must be [[lines]] tables");
    int index = 0;
    for (const toml::node& e : *a) {
      TableReader r(*e.as_table(), "lines[" + std::to_string(index++) + "]", source_name);
      read_line(r, c);
    }
  }
  top.reject_unknown();
  return c;
}

std::vector<std::string> config_keys() {
  // Each reader run over an empty table takes every key it knows: the list cannot drift
  // from what parse_config() accepts.
  const std::string file = "(schema)";
  const toml::table empty;
  Config c = default_config();
  std::vector<std::string> keys;
  const auto collect = [&](const char* table, SectionReader read) {
    TableReader r(empty, table, file);
    read(r, c);
    for (const std::string& key : r.taken()) keys.push_back(r.qualified(key));
  };
  for (const Section& s : kSections) collect(s.name, s.read);
  collect("lines", read_line);
  return keys;
}

Config load_config_file(const std::string& path) {
  const auto fail = [&](const std::string& why) { throw ConfigError(path + ": " + why); };
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) fail(std::string("cannot read the configuration file: ") + std::strerror(errno));
  const UniqueFd file(fd);
  struct stat st {};
  if (::fstat(fd, &st) != 0) fail(std::string("cannot read the configuration file: ") + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) fail("is a directory, not a configuration file");
  // A device or a pipe is read too (a process substitution), but never past the cap.
  std::string text;
  char chunk[16384];
  for (;;) {
    const ssize_t n = ::read(fd, chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(std::string("error while reading the configuration file: ") + std::strerror(errno));
    if (n == 0) break;
    text.append(chunk, static_cast<std::size_t>(n));
    if (text.size() > kMaxConfigBytes)
      fail("larger than " + std::to_string(kMaxConfigBytes >> 20) + " MB: not a configuration file");
  }
  Config c = parse_config(text, path);
  // A relative [source] path belongs with the file that names it, not with wherever the
  // program happens to be started (systemd starts it in /).
  if (!c.source.path.empty() && c.source.path.front() != '/') {
    const std::string::size_type slash = path.rfind('/');
    if (slash != std::string::npos) c.source.path = path.substr(0, slash + 1) + c.source.path;
  }
  return c;
}

}  // namespace ccdlane
