// How subcommands of the `ccdlane` tool plug in, and the errors they report.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

namespace ccdlane::cli {

// Bad usage or bad input: one line on stderr, exit status 2 (docs/interfaces.md).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A subcommand registers its options on `sub` and returns the action to run once the
// command line has been parsed. The action returns the exit status.
using CommandAction = std::function<int()>;
using CommandSetup = CommandAction (*)(CLI::App& sub);

struct Command {
  const char* name;
  const char* summary;
  CommandSetup setup;
};

// SIGINT/SIGTERM/SIGHUP set a flag instead of ending the process, so that a command that runs
// until interrupted (recording, printing samples) finishes its output cleanly. No
// SA_RESTART: a waiting poll() returns at once.
void catch_stop_signals();
bool stop_requested();

// A number > 0, refused as "must be greater than 0, got X" (CLI11's PositiveNumber
// prints its range up to DBL_MAX, 1.797e308, in full).
CLI::Validator positive_number();

// A number in [lo, hi] (NaN and infinities refused, which CLI::Range lets through),
// refused as "must be a number from LO to HI, got X".
CLI::Validator number_from_to(double lo, double hi);

// Parses a whole-string number; throws UsageError naming the argument otherwise.
double parse_number(const std::string& text, const std::string& what);

}  // namespace ccdlane::cli
