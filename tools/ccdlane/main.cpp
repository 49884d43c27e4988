// `ccdlane`: the command-line front end. Each subcommand lives in its own file; this one
// holds the table of them and turns errors into one line and an exit status.
#include <iostream>

#include "app/config_loader.hpp"
#include "tools/ccdlane/checked_output.hpp"
#include "tools/ccdlane/command.hpp"

namespace ccdlane::cli {
CommandAction setup_project(CLI::App& sub);
CommandAction setup_ground(CLI::App& sub);
CommandAction setup_monitor(CLI::App& sub);
CommandAction setup_solve(CLI::App& sub);
CommandAction setup_synth(CLI::App& sub);
CommandAction setup_grab(CLI::App& sub);
CommandAction setup_replay(CLI::App& sub);
CommandAction setup_gx1(CLI::App& sub);
CommandAction setup_gx1_emulate(CLI::App& sub);
CommandAction setup_spy(CLI::App& sub);
CommandAction setup_record(CLI::App& sub);
CommandAction setup_calibrate(CLI::App& sub);
CommandAction setup_ldw_scenarios(CLI::App& sub);
CommandAction setup_score(CLI::App& sub);
CommandAction setup_report(CLI::App& sub);

namespace {
constexpr Command kCommands[] = {
    {"project", "project a fixed-frame point to the observed pixel (JSON)", setup_project},
    {"ground", "intersect an observed pixel's ray with the road (JSON)", setup_ground},
    {"solve", "solve attitude and lane lines from labelled picks (JSON)", setup_solve},
    {"monitor", "watch ccdlaned's lane and status messages on the LCM bus", setup_monitor},
    {"spy", "lcm-spy with the ccdlane types: every channel and message, decoded (needs a display)", setup_spy},
    {"synth", "render a frame directory of a synthetic road with known truth", setup_synth},
    {"grab", "grab frames from a V4L2 or Aravis camera: rate, drops, latency; optionally record", setup_grab},
    {"record", "record frames (and the gyro) from a camera, synth or a frame directory: frame directory or LCM log",
     setup_record},
    {"replay", "run detect, solve, track and lane metrics over recorded frames (JSON Lines)", setup_replay},
    {"score", "score replay's lines against lane annotations (PNG masks), TuSimple's rules", setup_score},
    {"report", "a drive report from replay's output: plots over time and a summary, one HTML page", setup_report},
    {"gx1", "talk to a 3DM-GX1 gyro: firmware, serial number, then one line per sample", setup_gx1},
    {"calibrate", "calibrate the camera (chessboard pictures) or its mount (a recorded drive)", setup_calibrate},
    {"ldw-scenarios", "run the lane departure warning's ISO 17361 scenario set and print its summary table",
     setup_ldw_scenarios},
    {"gx1-emulate", "emulate a 3DM-GX1 on a pty until interrupted (prints the device path)", setup_gx1_emulate},
};
}  // namespace
}  // namespace ccdlane::cli

int main(int argc, char** argv) {
  using namespace ccdlane::cli;
  CLI::App app{"ccdlane: lane attitude and lane lines from one camera with a known CCD geometry"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string(CCDLANE_VERSION));
  CommandAction action;
  for (const Command& c : kCommands) {
    CLI::App* sub = app.add_subcommand(c.name, c.summary);
    CommandAction a = c.setup(*sub);
    sub->callback([&action, a] { action = a; });
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ccdlane: " << e.what() << " (see ccdlane --help)\n";
    return 2;
  }
  try {
    const int status = action ? action() : 2;
    // What a command printed must have reached its reader: a full disk or a closed pipe
    // behind standard output is a failure, whatever the command returned.
    flush_checked(std::cout, "standard output");
    return status;
  } catch (const std::bad_alloc&) {
    std::cerr << "ccdlane: out of memory: the configuration or input asks for more than this machine has\n";
    return 1;
  } catch (const UsageError& e) {
    std::cerr << "ccdlane: " << e.what() << '\n';
    return 2;
  } catch (const ccdlane::ConfigError& e) {
    std::cerr << "ccdlane: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ccdlane: " << e.what() << '\n';
    return 1;
  }
}
