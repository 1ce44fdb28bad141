// conftrack overlay: one event made of the hits of several events, each
// added several times with an azimuthal rotation (EventOverlay.hpp). A load
// test of the reconstruction, e.g. the five real TrackML events twice each
// (about 10^6 hits, ten times their pile-up):
//   conftrack overlay -i data/trackml/train_100_events_no_truth
//       --detector trackml --copies 2 -o big

#include "conftrack/core/Error.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/io/TrackmlReader.hpp"
#include "conftrack/io/TrackmlWriter.hpp"
#include "conftrack/simulation/EventOverlay.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "Commands.hpp"
#include "EventLoop.hpp"

namespace conftrack::cli {

namespace {

struct OverlayOptions {
  std::string input;
  std::string output = "overlay";
  std::string detector = "clicdet";
  /// Event numbers to overlay; empty: every event in the input folder.
  std::vector<std::uint64_t> events;
  EventOverlayConfig overlay{2, 1.0, 1};
  bool gzip = false;
};

void runOverlay(const OverlayOptions& opt) {
  opt.overlay.validate();
  Detector detector = loadDetector(opt.detector);
  std::vector<std::uint64_t> numbers = selectEvents(opt.input, opt.events);
  std::vector<Event> inputs;
  inputs.reserve(numbers.size());
  for (std::uint64_t n : numbers) {
    inputs.push_back(readEvent(opt.input, n, &detector.trackmlLayerMap(),
                               ReadOptions{false, false}));
  }
  Event out = overlayEvents(inputs, opt.overlay);
  WriteOptions wo;
  wo.gzip = opt.gzip;
  writeEvent(opt.output, out, &detector.trackmlLayerMap(), wo);
  std::printf("event %llu: %zu hits from %zu events x %u copies in %s\n",
              static_cast<unsigned long long>(out.number), out.hits.size(),
              inputs.size(), opt.overlay.copies, opt.output.c_str());
}

}  // namespace

void addOverlayCommand(CLI::App& app) {
  auto opt = std::make_shared<OverlayOptions>();
  CLI::App* cmd = app.add_subcommand(
      "overlay",
      "Overlay the hits of several events into one (each several times, "
      "rotated in azimuth): a high-occupancy load test");
  cmd->add_option("-i,--input", opt->input, "Folder with event files")
      ->required();
  cmd->add_option("-o,--output", opt->output, "Output folder")
      ->capture_default_str();
  cmd->add_option("--detector", opt->detector, "Detector name or TOML file")
      ->capture_default_str();
  cmd->add_option("--events", opt->events,
                  "Event numbers to overlay (default: all in the folder)");
  cmd->add_option("--copies", opt->overlay.copies, "Times each event is added")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1000u));
  cmd->add_option("--rotation", opt->overlay.rotation,
                  "Azimuthal rotation between copies [rad]")
      ->capture_default_str();
  cmd->add_option("--number", opt->overlay.number, "Event number of the result")
      ->capture_default_str();
  cmd->add_flag("--gzip", opt->gzip, "Write .csv.gz files");
  cmd->callback([opt]() { runOverlay(*opt); });
}

}  // namespace conftrack::cli
