#include "conftrack/core/Error.hpp"
#include "conftrack/core/Log.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/io/EventFiles.hpp"
#include "conftrack/io/TrackFiles.hpp"
#include "conftrack/io/TrackmlReader.hpp"
#include "conftrack/io/TrackmlSubmission.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "Commands.hpp"
#include "EventLoop.hpp"
#include "OptionChecks.hpp"
#include "ReconstructionOptions.hpp"
#include "StepReport.hpp"

namespace conftrack::cli {

namespace {

struct ReconstructOptions {
  ReconstructionOptions reco;
  std::string input;
  std::string output = "tracks";
  std::size_t threads = 0;
  bool gzip = false;
  /// Also write TrackML submission files.
  bool submission = false;
  /// The hits come from a module-level simulation (loadSensorLayout).
  bool moduleLevel = false;
  ShardOption shard;
};

struct EventReport {
  std::size_t hits = 0;
  std::size_t tracks = 0;
  double findingMs = 0.0;
  double fittingMs = 0.0;
  std::vector<StepStats> steps;
};

void runReconstruct(const ReconstructOptions& opt) {
  Detector detector = loadDetector(opt.reco.detector);
  Reconstruction reco(detector, makeReconstructionConfig(opt.reco, detector),
                      loadSensorLayout(detector, opt.moduleLevel));
  std::vector<std::uint64_t> events = requireEvents(opt.input);
  const auto [first, last] = shardRange(events.size(), opt.shard);
  events =
      std::vector<std::uint64_t>(events.begin() + first, events.begin() + last);
  prepareOutputFolder(opt.output, "-o");
  std::vector<EventReport> reports(events.size());
  forEachEvent(events.size(), opt.threads, "reconstruct", [&](std::size_t i) {
    Event event = readEvent(opt.input, events[i], &detector.trackmlLayerMap(),
                            ReadOptions{false, false});
    Reconstruction::Result r = reco.run(event.hits);
    WriteOptions wo;
    wo.gzip = opt.gzip;
    writeTracks(opt.output, events[i], event.hits, r.tracks, wo);
    if (opt.submission) {
      std::vector<std::vector<HitIndex>> lists;
      lists.reserve(r.tracks.size());
      for (const Track& t : r.tracks) {
        lists.push_back(t.hits);
      }
      writeSubmission(opt.output, events[i], event.hits, lists, opt.gzip);
    }
    warnIfTruncated("event " + std::to_string(events[i]), r.steps);
    logVertexRegions(events[i], r.vertexRegions);
    reports[i] = {event.hits.size(), r.tracks.size(), r.findingMs, r.fittingMs,
                  std::move(r.steps)};
  });
  EventReport total;
  for (const EventReport& e : reports) {
    accumulateSteps(total.steps, e.steps);
    total.hits += e.hits;
    total.tracks += e.tracks;
    total.findingMs += e.findingMs;
    total.fittingMs += e.fittingMs;
  }
  double n = static_cast<double>(std::max<std::size_t>(1, events.size()));
  std::printf(
      "%zu events: %.1f hits and %.1f tracks per event; finding %.1f ms, "
      "fitting %.1f ms per event; tracks in %s\n",
      events.size(), total.hits / n, total.tracks / n, total.findingMs / n,
      total.fittingMs / n, opt.output.c_str());
  printStepTable(stdout, total.steps, events.size());
}

}  // namespace

void addReconstructCommand(CLI::App& app) {
  auto opt = std::make_shared<ReconstructOptions>();
  CLI::App* cmd = app.add_subcommand(
      "reconstruct",
      "Find, fit and select tracks in TrackML-format events; write track "
      "files");
  cmd->add_option("-i,--input", opt->input, "Folder with event files")
      ->required();
  cmd->add_option("-o,--output", opt->output, "Output folder")
      ->capture_default_str();
  addReconstructionOptions(*cmd, opt->reco);
  addThreadsOption(*cmd, opt->threads);
  addShardOption(*cmd, opt->shard);
  cmd->add_flag("--gzip", opt->gzip, "Write .csv.gz files");
  cmd->add_flag("--submission", opt->submission,
                "Also write TrackML submission files "
                "(eventNNNNNNNNN-submission.csv)");
  cmd->add_flag("--module-level", opt->moduleLevel,
                "The hits come from the sensors of data/layouts/<detector>"
                "_layout.json.gz (simulate --module-level): the fit measures "
                "them on their sensors' planes (TrackML: always, with the "
                "modules of data/trackml/detectors.csv.gz)");
  cmd->callback([opt]() { runReconstruct(*opt); });
}

}  // namespace conftrack::cli
