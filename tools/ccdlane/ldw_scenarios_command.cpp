// `ccdlane ldw-scenarios [CONFIG] [--seeds N] [--minutes M]`: the lane departure
// warning's full scenario set (ISO 17361 warning generation on straight and curved
// roads, repeatability over noise seeds, false alarms in normal driving, suppression),
// run on the vehicle drive's truth, and its summary table (README "Lane departure
// warning").
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "app/config_loader.hpp"
#include "core/evaluation/ldw_scenarios.hpp"
#include "tools/ccdlane/command.hpp"

namespace ccdlane::cli {
namespace {

struct LdwScenariosArgs {
  std::string config;
  int seeds = 20;
  double minutes = 10.0;
};

}  // namespace

CommandAction setup_ldw_scenarios(CLI::App& sub) {
  auto a = std::make_shared<LdwScenariosArgs>();
  sub.add_option("config", a->config, "configuration file (TOML) for [vehicle] and [ldw]; default: built-in defaults");
  sub.add_option("--seeds", a->seeds, "noise seeds per case (default 20)")->check(CLI::Range(1, 1000));
  sub.add_option("--minutes", a->minutes, "minutes of normal driving per seed (default 10)")
      ->check(CLI::Range(0.5, 600.0));
  sub.footer(
      "Drifts of 0.1, 0.3, 0.5, 0.8 and 1.0 m/s to either side on a straight road and on curves of "
      "R 500 m, each with --seeds noise seeds; the warning's wheel position (DLC, m, + inside) against "
      "the earliest (0.75 m inside) and latest (0.3 m outside) warning lines; false alarms per hour of "
      "normal driving (weaving, curves, signalled lane changes); suppression cases. The per-frame solve "
      "is the truth plus the noise the solver reports on rendered frames (core/evaluation/ldw_scenarios.hpp).");
  return [a] {
    const Config config = a->config.empty() ? default_config() : load_config_file(a->config);
    ldw::LdwConfig ldw = config.ldw;
    ldw.vehicle = config.vehicle;
    ldw.filter.track_roll = false;  // the scenarios' frames carry the gyro's roll
    const ldw::ScenarioSummary summary = ldw::run_scenarios(a->seeds, a->minutes, ldw);
    std::fputs(ldw::format_summary(summary).c_str(), stdout);
    int failed = summary.false_alarms > 0 || summary.suppression_passed < summary.suppression_runs;
    for (const ldw::SummaryRow& row : summary.rows) failed |= row.passed < row.runs;
    return failed ? 1 : 0;
  };
}

}  // namespace ccdlane::cli
