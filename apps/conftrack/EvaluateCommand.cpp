#include "conftrack/core/Error.hpp"
#include "conftrack/evaluation/PerformanceCollector.hpp"
#include "conftrack/evaluation/PerformanceReport.hpp"
#include "conftrack/frontend/ReportFiles.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/io/EventFiles.hpp"
#include "conftrack/io/TrackFiles.hpp"
#include "conftrack/io/TrackmlReader.hpp"

#include <filesystem>
#include <iostream>
#include <memory>

#include "Commands.hpp"
#include "EventLoop.hpp"
#include "OptionChecks.hpp"

namespace conftrack::cli {

namespace {

struct EvaluateOptions {
  std::string detector = "clicdet";
  std::string events;
  std::string tracks;
  std::string output = "report";
  std::size_t threads = 0;
  bool singleParticle = false;
  bool noPlots = false;
  ShardOption shard;
};

void runEvaluate(const EvaluateOptions& opt) {
  Detector detector = loadDetector(opt.detector);
  const std::vector<std::uint64_t> numbers = requireEvents(opt.events);
  prepareOutputFolder(opt.output, "-o");
  const auto [first, last] = shardRange(numbers.size(), opt.shard);
  PerformanceCollector collector(opt.singleParticle
                                     ? PerformanceConfig::singleParticleSample()
                                     : PerformanceConfig{},
                                 first);
  forEachEvent(last - first, opt.threads, "evaluate", [&](std::size_t i) {
    const std::uint64_t number = numbers[first + i];
    Event event = readEvent(opt.events, number, &detector.trackmlLayerMap());
    if (!event.hasTruth()) {
      throw InputError(opt.events, "event " + std::to_string(number) +
                                       " has no truth file: nothing to "
                                       "evaluate against");
    }
    std::vector<Track> tracks = readTracks(opt.tracks, number, event.hits);
    collector.addEvent(first + i, event, tracks, detector.bz(), {}, {});
  });
  RunMetadata meta;
  meta.detector = detector.name();
  meta.sample = opt.events;
  meta.events = numbers.size();
  meta.threads = effectiveThreads(opt.threads);
  meta.shard = {opt.shard.index, opt.shard.count, first};
  PerformanceSummary summary = collector.summary();
  printSummaryTable(std::cout, meta, summary);
  writePerformanceReport(opt.output, meta, summary, !opt.noPlots, std::cerr);
}

}  // namespace

void addEvaluateCommand(CLI::App& app) {
  auto opt = std::make_shared<EvaluateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "evaluate",
      "Evaluate tracks (track files) against events with truth: "
      "efficiency, fake and duplicate rates, resolutions, report");
  cmd->add_option("-i,--input", opt->events, "Folder with event files")
      ->required();
  cmd->add_option("-t,--tracks", opt->tracks, "Folder with track files")
      ->required();
  cmd->add_option("-o,--output", opt->output, "Report folder")
      ->capture_default_str();
  cmd->add_option("--detector", opt->detector, "Detector name or TOML file")
      ->capture_default_str();
  cmd->add_flag("--single-particle", opt->singleParticle,
                "Single-particle sample: residuals, pulls, >= 3 hits");
  cmd->add_flag("--no-plots", opt->noPlots, "Skip the Python plots");
  addThreadsOption(*cmd, opt->threads);
  addShardOption(*cmd, opt->shard);
  cmd->callback([opt]() { runEvaluate(*opt); });
}

}  // namespace conftrack::cli
