// ccdlaned's life: start the pipeline from a configuration, report status once a second
// (LCM and systemd), stop cleanly on SIGTERM/SIGINT or when a finite source ends.
#pragma once

#include <string>

#include "app/config.hpp"

namespace ccdlane {

// Everything in a configuration that the daemon cannot run with although the schema
// accepts it ("" when none): solves that cannot determine what they are asked for.
std::string daemon_config_problem(const Config& config);

// Solver settings that are not well-posed with the priors this configuration gives
// (docs/solver.md, "What is and is not observable"), "" when well-posed.
std::string solver_observability_problem(const Config& config);

// The built-in demo: the reference camera, the synthetic road at 30 fps, the emulated
// gyro, the default bus.
Config demo_config();

// Runs until SIGTERM/SIGINT (exit status 0), the end of a finite source (0) or a
// failure to start (1, after one line on stderr). SIGHUP is logged as not supported.
int run_daemon(const Config& config);

}  // namespace ccdlane
