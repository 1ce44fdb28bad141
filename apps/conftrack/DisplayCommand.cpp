#include "conftrack/core/Error.hpp"
#include "conftrack/frontend/EventDisplay.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/io/EventFiles.hpp"
#include "conftrack/io/TrackFiles.hpp"
#include "conftrack/io/TrackmlReader.hpp"

#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "Commands.hpp"
#include "EventLoop.hpp"
#include "OptionChecks.hpp"
#include "ReconstructionOptions.hpp"

namespace conftrack::cli {

namespace {

struct DisplayOptions {
  ReconstructionOptions reco;
  std::string input;
  std::string tracks;
  /// Event number; none: the first in the folder.
  std::optional<std::uint64_t> event;
  std::string output = "event_display.png";
};

void runDisplay(const DisplayOptions& opt) {
  Detector detector = loadDetector(opt.reco.detector);
  std::vector<std::uint64_t> numbers = requireEvents(opt.input);
  prepareOutputFile(opt.output, "-o");
  std::uint64_t number = opt.event.value_or(numbers.front());
  Event event = readEvent(opt.input, number, &detector.trackmlLayerMap(),
                          ReadOptions{false, false});
  std::vector<Track> tracks;
  if (!opt.tracks.empty()) {
    tracks = readTracks(opt.tracks, number, event.hits);
  } else {
    // As reconstruct (without --module-level): TrackML hits on their
    // modules' planes.
    Reconstruction reco(detector, makeReconstructionConfig(opt.reco, detector),
                        loadSensorLayout(detector, false));
    tracks = reco.run(event.hits).tracks;
  }
  std::string title = detector.name() + " event " + std::to_string(number);
  if (drawEventDisplay(opt.output, event.hits, tracks, title, std::cerr)) {
    std::cout << "event display: " << opt.output << '\n';
  }
}

}  // namespace

void addDisplayCommand(CLI::App& app) {
  auto opt = std::make_shared<DisplayOptions>();
  CLI::App* cmd = app.add_subcommand(
      "display",
      "Draw one event's hits and tracks in (x,y), (u,v) and (z,r) as PNG");
  cmd->add_option("-i,--input", opt->input, "Folder with event files")
      ->required();
  cmd->add_option("-t,--tracks", opt->tracks,
                  "Folder with track files (default: reconstruct now)");
  cmd->add_option("--event", opt->event, "Event number (default: first)")
      ->check(wholeNumber(0, UINT64_MAX));
  cmd->add_option("-o,--output", opt->output, "PNG file")
      ->capture_default_str();
  addReconstructionOptions(*cmd, opt->reco);
  cmd->callback([opt]() { runDisplay(*opt); });
}

}  // namespace conftrack::cli
