#include "conftrack/core/Log.hpp"
#include "conftrack/evaluation/PerformanceCollector.hpp"
#include "conftrack/evaluation/PerformanceReport.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/simulation/EventSimulation.hpp"

#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>

#include "Commands.hpp"
#include "EventLoop.hpp"
#include "ReconstructionOptions.hpp"

namespace conftrack::cli {

namespace {

struct RunOptions {
  ReconstructionOptions reco;
  SampleOptions sample;
  std::size_t events = 100;
  std::string output = "conftrack-out";
  std::size_t threads = 0;
  bool noPlots = false;
};

bool isSingleParticle(const std::string& sample) {
  return sample == "muons" || sample == "gun";
}

void runRun(const RunOptions& opt) {
  using Clock = std::chrono::steady_clock;
  Detector detector = loadDetector(opt.reco.detector);
  EventSimulation sim(detector, makeSimulationConfig(opt.sample));
  Reconstruction reco(detector, makeReconstructionConfig(opt.reco, detector));
  PerformanceCollector collector(isSingleParticle(sim.config().sample)
                                     ? PerformanceConfig::singleParticleSample()
                                     : PerformanceConfig{});
  CONFTRACK_INFO("run: " << opt.events << " events of " << sim.description()
                         << " in " << detector.name() << ", seed "
                         << opt.sample.seed << ", "
                         << effectiveThreads(opt.threads) << " threads");
  forEachEvent(opt.events, opt.threads, "run", [&](std::size_t i) {
    auto t0 = Clock::now();
    Event event = sim.simulate(i + 1);
    double simMs =
        std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    Reconstruction::Result r = reco.run(event.hits);
    collector.addEvent(i, event, r.tracks, detector.bz(), r.steps,
                       {simMs, r.findingMs, r.fittingMs + r.selectionMs});
  });
  RunMetadata meta;
  meta.detector = detector.name();
  meta.sample = sim.config().sample;
  meta.overlayBx = sim.config().overlayBx;
  meta.events = opt.events;
  meta.seed = opt.sample.seed;
  meta.threads = effectiveThreads(opt.threads);
  PerformanceSummary summary = collector.summary();
  std::filesystem::create_directories(opt.output);
  printSummaryTable(std::cout, meta, summary);
  writePerformanceReport(opt.output, meta, summary, !opt.noPlots, std::cerr);
  std::cout << "report: " << (std::filesystem::path(opt.output) / "index.html")
            << '\n';
}

}  // namespace

void addRunCommand(CLI::App& app) {
  auto opt = std::make_shared<RunOptions>();
  opt->sample.overlayBx = 30;
  CLI::App* cmd = app.add_subcommand(
      "run",
      "Simulate, reconstruct and evaluate in one go (default: CLICdet, "
      "ttbar at 3 TeV with 30 BX of gamma gamma -> hadrons)");
  addSampleOptions(*cmd, opt->sample);
  addReconstructionOptions(*cmd, opt->reco);
  cmd->add_option("-n,--events", opt->events, "Number of events")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{1}, std::size_t{100000000}));
  cmd->add_option("-o,--output", opt->output, "Output folder")
      ->capture_default_str();
  addThreadsOption(*cmd, opt->threads);
  cmd->add_flag("--no-plots", opt->noPlots, "Skip the Python plots");
  cmd->callback([opt]() { runRun(*opt); });
}

}  // namespace conftrack::cli
