// `ccdlane solve PROBLEM.toml [--picks FILE.csv]`: one lane problem solved, printed as
// the JSON of docs/interfaces.md.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "app/config_loader.hpp"
#include "core/solver/lane_solver.hpp"
#include "core/solver/picks_csv.hpp"
#include "tools/ccdlane/command.hpp"
#include "tools/ccdlane/json_output.hpp"

namespace ccdlane::cli {
namespace {

struct SolveArgs {
  std::string problem;
  std::string picks;
};

// The picks file: --picks as given, else [solver] picks relative to the problem file.
std::string picks_path(const SolveArgs& args, const Config& config) {
  if (!args.picks.empty()) return args.picks;
  if (config.solver.picks.empty())
    throw UsageError(args.problem + ": no picks: give --picks FILE.csv or [solver] picks = \"FILE.csv\"");
  const std::filesystem::path p(config.solver.picks);
  return p.is_absolute() ? p.string() : (std::filesystem::path(args.problem).parent_path() / p).string();
}

PicksCsv read_picks(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError(path + ": cannot read the picks file");
  std::ostringstream text;
  text << in.rdbuf();
  try {
    return parse_picks_csv(text.str(), path);
  } catch (const PicksCsvError& e) {
    throw UsageError(e.what());
  }
}

// Lines come from the problem's [[lines]] when it has them (ids must be among them),
// otherwise from the picks: ids 0..N-1, each with picks.
int count_lines(const Config& config, const PicksCsv& csv, const std::string& problem, const std::string& path) {
  const int configured = static_cast<int>(config.lines.size());
  if (configured > kMaxLaneLines)
    throw UsageError(problem + ": lines: " + std::to_string(configured) +
                     " [[lines]] tables, the solver handles at most " + std::to_string(kMaxLaneLines));
  int highest = -1;
  for (std::size_t i = 0; i < csv.picks.size(); ++i) {
    const int id = csv.picks[i].line;
    const std::string where = path + ":" + std::to_string(csv.source_lines[i]) + ": line: ";
    if (configured > 0 && id >= configured)
      throw UsageError(where + "unknown lane-line id " + std::to_string(id) + " (" + problem + " has [[lines]] 0.." +
                       std::to_string(configured - 1) + ")");
    if (id >= kMaxLaneLines)
      throw UsageError(where + "lane-line id " + std::to_string(id) + " is beyond the solver's " +
                       std::to_string(kMaxLaneLines) + " lines (0.." + std::to_string(kMaxLaneLines - 1) + ")");
    highest = std::max(highest, id);
  }
  if (configured > 0) return configured;
  for (int id = 0; id <= highest; ++id) {
    bool seen = false;
    for (const Pick& p : csv.picks) seen = seen || p.line == id;
    if (!seen)
      throw UsageError(path + ": lane line " + std::to_string(id) + " has no picks (ids must run 0.." +
                       std::to_string(highest) + ", or list the lines as [[lines]] in " + problem + ")");
  }
  return highest + 1;
}

SolverPriors priors_from(const PriorConfig& p) {
  return {p.psi_deg, p.theta_deg, p.phi_deg, p.H_mm, p.f_mm, p.lane_width_mm};
}

Json json_per_line(const SolveResult& r, const std::array<double, kMaxLaneLines>& values) {
  Json a = Json::array();
  for (int j = 0; j < r.num_lines; ++j) a.push_back(json_number(values[j]));
  return a;
}

Json result_json(const SolveResult& r, const SolveRequest& request) {
  Json lines = Json::array();
  for (int j = 0; j < r.num_lines; ++j)
    lines.push_back({{"id", j},
                     {"y0_mm", json_number(r.lines[j].y0_mm)},
                     {"m", json_number(r.lines[j].m)},
                     {"c_per_mm", json_number(r.lines[j].c_per_mm)}});
  Json points = Json::array();
  for (std::size_t i = 0; i < request.picks.size(); ++i) {
    const Pick& p = request.picks[i];
    points.push_back({{"line", p.line},
                      {"px", json_number(p.px)},
                      {"py", json_number(p.py)},
                      {"x_mm", json_number(r.points_mm[i].x())},
                      {"y_mm", json_number(r.points_mm[i].y())}});
  }
  // Entries for the free parameters only; null where the data do not determine them.
  const FreeSet& f = request.free;
  Json sigma = Json::object();
  if (f.has(FreeParam::psi)) sigma["psi_deg"] = json_number(r.sigma.psi_deg);
  if (f.has(FreeParam::theta)) sigma["theta_deg"] = json_number(r.sigma.theta_deg);
  if (f.has(FreeParam::phi)) sigma["phi_deg"] = json_number(r.sigma.phi_deg);
  if (f.has(FreeParam::H)) sigma["H_mm"] = json_number(r.sigma.H_mm);
  if (f.has(FreeParam::f)) sigma["f_mm"] = json_number(r.sigma.f_mm);
  if (f.has(FreeParam::y0)) sigma["y0_mm"] = json_per_line(r, r.sigma.y0_mm);
  if (f.has(FreeParam::m)) sigma["m"] = json_per_line(r, r.sigma.m);
  if (f.has(FreeParam::c)) sigma["c_per_mm"] = json_per_line(r, r.sigma.c_per_mm);

  return Json{{"mode", request.mode == SolverMode::paper ? "paper" : "reprojection"},
              {"converged", r.converged},
              {"rank_deficient", r.rank_deficient},
              {"iterations", r.iterations},
              {"cost", json_number(r.cost)},
              {"rms_px", json_number(r.rms_px)},
              {"psi_deg", json_number(rad_to_deg(r.pose.attitude.psi))},
              {"theta_deg", json_number(rad_to_deg(r.pose.attitude.theta))},
              {"phi_deg", json_number(rad_to_deg(r.pose.attitude.phi))},
              {"H_mm", json_number(r.pose.H_mm)},
              {"f_mm", json_number(r.pose.f_mm)},
              {"lines", lines},
              {"points", points},
              {"sigma", sigma}};
}

int run_solve(const SolveArgs& args) {
  const Config config = load_config_file(args.problem);
  const std::string path = picks_path(args, config);
  const PicksCsv csv = read_picks(path);

  std::vector<RoadLine> initial_lines;
  for (const RoadLine& l : config.lines) initial_lines.push_back({l.y0_mm, l.m, l.c_per_mm});
  SolveRequest request;
  request.mode = config.solver.mode;
  request.free = config.solver.free;
  request.pixel_sigma = config.solver.pixel_sigma;
  request.max_iterations = config.solver.max_iterations;
  request.priors = priors_from(config.prior);
  request.initial_pose = config.nominal_pose();
  request.picks = csv.picks;
  request.num_lines = count_lines(config, csv, args.problem, path);
  request.initial_lines = initial_lines;

  // A pick is a pixel of the picture: outside it, it is a typo or another camera's
  // pixel, not a point beyond the horizon.
  for (std::size_t i = 0; i < csv.picks.size(); ++i) {
    const Pick& p = csv.picks[i];
    const double Nu = config.camera.Nu, Nv = config.camera.Nv;
    if (p.px < 0.5 || p.px > Nu + 0.5 || p.py < 0.5 || p.py > Nv + 0.5) {
      std::ostringstream out;
      out << path << ':' << csv.source_lines[i] << ": pick (" << p.px << ", " << p.py
          << ") is outside the image (px 0.5.." << Nu + 0.5 << ", py 0.5.." << Nv + 0.5 << " for the "
          << config.camera.Nu << "x" << config.camera.Nv << " camera of " << args.problem << ")";
      throw UsageError(out.str());
    }
  }

  const int needed = required_picks(request);
  if (static_cast<int>(csv.picks.size()) < needed)
    throw UsageError(path + ": " + std::to_string(csv.picks.size()) + " picks, but " + args.problem +
                     "'s free parameters need at least " + std::to_string(needed) +
                     " (each pick gives two equations and adds its own unknown x)");

  LaneSolver solver(config.camera, static_cast<int>(csv.picks.size()), kMaxLaneLines);
  const SolveResult& result = solver.solve(request);
  const auto pick_at = [&](int i) {
    const Pick& p = csv.picks[static_cast<std::size_t>(i)];
    std::ostringstream out;
    out << path << ':' << csv.source_lines[static_cast<std::size_t>(i)] << ": pick (" << p.px << ", " << p.py << ")";
    return out.str();
  };
  switch (result.status) {
    case SolveStatus::no_ground_point:
      throw UsageError(pick_at(result.failed_pick) +
                       ": its ray misses the road at the initial attitude ([attitude] of " + args.problem +
                       "): at or above the horizon");
    case SolveStatus::invalid_input:
      throw UsageError((result.failed_pick >= 0 ? pick_at(result.failed_pick) : args.problem) +
                       ": rejected by the solver (invalid input)");
    case SolveStatus::too_few_picks: throw UsageError(path + ": too few picks for the free parameters");
    case SolveStatus::numerical_failure:
      throw std::runtime_error(args.problem + ": the solver could not compute a step (numerical failure)");
    default: break;
  }
  print_json_line(std::cout, result_json(result, request));
  return 0;
}

}  // namespace

CommandAction setup_solve(CLI::App& sub) {
  auto args = std::make_shared<SolveArgs>();
  sub.add_option("problem", args->problem,
                 "problem file: a configuration (TOML) with [solver] and optional [prior], [[lines]]")
      ->required();
  sub.add_option("--picks", args->picks,
                 "picks CSV (line,px,py); default: [solver] picks, relative to the problem file");
  sub.footer(
      "Prints one JSON object: attitude, H, f, lines, each pick's road point, cost, RMS, iterations, "
      "convergence, rank deficiency, and the sigma of every free parameter (null where undetermined).");
  return [args] { return run_solve(*args); };
}

}  // namespace ccdlane::cli
