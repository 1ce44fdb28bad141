/// conftrack: conformal tracking for all-silicon trackers.
/// Exit codes: 0 success, 1 bad input or usage, 2 internal error.

#include "conftrack/core/Error.hpp"
#include "conftrack/core/Log.hpp"

#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "AllocatorSetup.hpp"
#include "Commands.hpp"

namespace {

/// The first argument that is not an option must name a subcommand (the
/// options before it are flags), and so on down ("detector show"): CLI11
/// would report an unknown one as "A subcommand is required".
void requireKnownSubcommands(const CLI::App& app, int argc, char** argv) {
  const CLI::App* current = &app;
  std::string path = "conftrack";
  for (int i = 1; i < argc; ++i) {
    std::string_view arg = argv[i];
    if (arg.starts_with("-")) {
      continue;
    }
    std::vector<const CLI::App*> subs = current->get_subcommands({});
    if (subs.empty()) {
      return;  // a positional argument of the subcommand
    }
    std::string known;
    const CLI::App* next = nullptr;
    for (const CLI::App* sub : subs) {
      if (sub->get_name() == arg) {
        next = sub;
      }
      known += (known.empty() ? "" : ", ") + sub->get_name();
    }
    if (next == nullptr) {
      throw conftrack::InputError("unknown subcommand '" + std::string(arg) +
                                  "' of " + path + " (subcommands: " + known +
                                  ")");
    }
    path += " " + next->get_name();
    current = next;
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace conftrack;
  cli::setUpAllocator();
  CLI::App app{
      "conftrack: conformal track finding, Kalman fitting and evaluation "
      "for all-silicon trackers (CLICdet, CLD, TrackML)"};
  app.set_version_flag("--version", std::string(CONFTRACK_VERSION));
  app.require_subcommand(1);
  // Usage errors are one line like every other bad input.
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return std::string("conftrack: error: ") + e.what() +
           " (run with --help for usage)\n";
  });
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
  cli::addMergeCommand(app);
  cli::addSlurmCommand(app);
  cli::addTrackmlCommands(app);
  cli::addDiagnoseCommand(app);
  cli::addDisplayCommand(app);
  cli::addBenchCommand(app);
  cli::addOverlayCommand(app);

  try {
    requireKnownSubcommands(app, argc, argv);
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
