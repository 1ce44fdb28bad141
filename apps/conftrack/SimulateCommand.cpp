
#include "conftrack/core/DataFiles.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/core/Log.hpp"
#include "conftrack/evaluation/TruthMatching.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/io/TrackmlWriter.hpp"
#include "conftrack/simulation/EventSimulation.hpp"

#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>

#include "Commands.hpp"
#include "EventLoop.hpp"
#include "OptionChecks.hpp"
#include "Progress.hpp"

namespace conftrack::cli {

namespace {

struct SimulateOptions {
  std::string detector = "clicdet";
  SampleOptions sample;
  std::size_t events = 10;
  std::uint64_t firstEvent = 1;
  std::string output = "events";
  std::size_t threads = 0;
  bool summary = false;
  bool gzip = false;
  ShardOption shard;
};

/// Per-event numbers for --summary.
struct EventCounts {
  std::size_t hits = 0;
  std::size_t signalReconstructable = 0;
  std::size_t backgroundReconstructable = 0;
};

EventCounts countEvent(const Event& event) {
  EventCounts c;
  c.hits = event.hits.size();
  EventMatching m = matchTracks(event, {});
  for (std::size_t p = 0; p < event.particles.size(); ++p) {
    if (m.particles[p].reconstructable) {
      (event.particles[p].isBackground() ? c.backgroundReconstructable
                                         : c.signalReconstructable)++;
    }
  }
  return c;
}

void runSimulate(const SimulateOptions& opt) {
  // Event numbers seed the simulation and name the files: they must not
  // wrap around.
  if (opt.firstEvent >
      std::numeric_limits<std::uint64_t>::max() - (opt.events - 1)) {
    throw InputError("--first-event " + std::to_string(opt.firstEvent) +
                     " with --events " + std::to_string(opt.events) +
                     ": the last event number would exceed " +
                     std::to_string(std::numeric_limits<std::uint64_t>::max()));
  }
  Detector detector = loadDetector(opt.detector);
  EventSimulation::Config config = makeSimulationConfig(opt.sample);
  config.modules = loadModuleLayout(opt.sample, detector);
  EventSimulation sim(detector, config);
  prepareOutputFolder(opt.output, "-o");
  // With --shard, events [first, last) of the -n requested.
  const auto [first, last] = shardRange(opt.events, opt.shard);
  const std::uint64_t firstNumber = opt.firstEvent + first;
  std::vector<EventCounts> counts(last - first);
  CONFTRACK_INFO("simulating " << counts.size() << " events of "
                               << sim.description() << " in " << detector.name()
                               << ", seed " << opt.sample.seed);
  forEachEvent(counts.size(), opt.threads, "simulate", [&](std::size_t i) {
    Event event = sim.simulate(firstNumber + i);
    writeEvent(opt.output, event, &detector.trackmlLayerMap(), {opt.gzip});
    if (opt.summary) {
      counts[i] = countEvent(event);
    }
  });
  if (opt.summary) {
    std::printf("%8s %10s %16s %16s\n", "event", "hits", "reco. signal",
                "reco. background");
    EventCounts total;
    for (std::size_t i = 0; i < counts.size(); ++i) {
      std::printf("%8llu %10zu %16zu %16zu\n",
                  static_cast<unsigned long long>(firstNumber + i),
                  counts[i].hits, counts[i].signalReconstructable,
                  counts[i].backgroundReconstructable);
      total.hits += counts[i].hits;
      total.signalReconstructable += counts[i].signalReconstructable;
      total.backgroundReconstructable += counts[i].backgroundReconstructable;
    }
    double n = static_cast<double>(std::max<std::size_t>(1, counts.size()));
    std::printf(
        "%8s %10.1f %16.1f %16.1f   (reconstructable: stable, "
        "charged, pT > 0.1 GeV, |cos theta| < 0.99, >= 4 layers)\n",
        "mean", total.hits / n, total.signalReconstructable / n,
        total.backgroundReconstructable / n);
  }
}

}  // namespace

void addSimulateCommand(CLI::App& app) {
  auto opt = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "simulate", "Generate and simulate events, write TrackML-format files");
  cmd->add_option("--detector", opt->detector, "Detector name or TOML file")
      ->capture_default_str();
  addSampleOptions(*cmd, opt->sample);
  cmd->add_option("-n,--events", opt->events, "Number of events")
      ->capture_default_str()
      ->check(wholeNumber(1, 100000000));
  cmd->add_option("--first-event", opt->firstEvent, "Number of the first event")
      ->capture_default_str()
      ->check(wholeNumber(0, std::numeric_limits<std::uint64_t>::max()));
  cmd->add_option("-o,--output", opt->output, "Output folder")
      ->capture_default_str();
  addThreadsOption(*cmd, opt->threads);
  addShardOption(*cmd, opt->shard);
  cmd->add_flag("--summary", opt->summary,
                "Print hits and reconstructable particles per event");
  cmd->add_flag("--gzip", opt->gzip, "Write .csv.gz files");
  cmd->callback([opt]() { runSimulate(*opt); });
}

}  // namespace conftrack::cli
