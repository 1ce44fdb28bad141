/// conftrack: conformal tracking for all-silicon trackers.
/// Exit codes: 0 success, 1 bad input or usage, 2 internal error.

#include "conftrack/core/Error.hpp"
#include "conftrack/core/Log.hpp"

#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>

#include "Commands.hpp"

int main(int argc, char** argv) {
  using namespace conftrack;
  CLI::App app{
      "conftrack: conformal track finding, Kalman fitting and evaluation "
      "for all-silicon trackers (CLICdet, CLD, TrackML)"};
  app.set_version_flag("--version", std::string(CONFTRACK_VERSION));
  app.require_subcommand(1);
  int verbosity = 0;
  app.add_flag("-v,--verbose", verbosity, "More output (repeat for debug)");
  bool quiet = false;
  app.add_flag("-q,--quiet", quiet, "Only warnings and errors");
  app.parse_complete_callback([&]() {
    if (quiet) {
      log::setLevel(log::Level::eWarning);
    } else if (verbosity > 0) {
      log::setLevel(log::Level::eDebug);
    }
  });

  cli::addDetectorCommand(app);
  cli::addSimulateCommand(app);
  cli::addReconstructCommand(app);
  cli::addRunCommand(app);
  cli::addEvaluateCommand(app);
  cli::addTrackmlCommands(app);
  cli::addDisplayCommand(app);
  cli::addBenchCommand(app);
  cli::addOverlayCommand(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? 0 : 1;
  } catch (const InputError& e) {
    std::cerr << "conftrack: error: " << e.what() << '\n';
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "conftrack: internal error: " << e.what() << '\n';
    return 2;
  }
  return 0;
}
