// conftrack bench: end-to-end timing of simulation and reconstruction on
// one thread, versus the number of overlaid bunch crossings. Events are
// simulated once; each is reconstructed --repeat times and the median is
// reported, so figures are stable on a busy machine.

#include "conftrack/evaluation/ResourceUsage.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/simulation/EventSimulation.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "Commands.hpp"
#include "EventLoop.hpp"
#include "OptionChecks.hpp"
#include "ReconstructionOptions.hpp"
#include "StepReport.hpp"

namespace conftrack::cli {

namespace {

struct BenchOptions {
  ReconstructionOptions reco;
  SampleOptions sample;
  std::vector<std::size_t> overlays{0, 10, 30, 60};
  std::size_t events = 3;
  std::size_t repeat = 3;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

void runBench(const BenchOptions& opt) {
  using Clock = std::chrono::steady_clock;
  auto ms = [](Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  };
  Detector detector = loadDetector(opt.reco.detector);
  Reconstruction reco(detector, makeReconstructionConfig(opt.reco, detector));
  std::printf("%s, %s, one thread; median of %zu runs over %zu events\n",
              detector.name().c_str(), opt.sample.sample.c_str(), opt.repeat,
              opt.events);
  std::printf("%6s %9s %8s %12s %12s %12s %12s\n", "BX", "hits", "tracks",
              "sim [ms]", "find [ms]", "fit [ms]", "total [ms]");
  const std::shared_ptr<const ModuleLayout> modules =
      loadModuleLayout(opt.sample, detector);
  for (std::size_t bx : opt.overlays) {
    SampleOptions so = opt.sample;
    so.overlayBx = bx;
    EventSimulation::Config config = makeSimulationConfig(so);
    config.modules = modules;
    EventSimulation sim(detector, config);
    std::vector<double> simMs, findMs, fitMs, totalMs;
    double hits = 0.0;
    double tracks = 0.0;
    for (std::size_t e = 0; e < opt.events; ++e) {
      auto t0 = Clock::now();
      Event event = sim.simulate(e + 1);
      simMs.push_back(ms(t0));
      hits += static_cast<double>(event.hits.size());
      std::vector<double> f, g, t;
      for (std::size_t k = 0; k < opt.repeat; ++k) {
        auto t1 = Clock::now();
        Reconstruction::Result r = reco.run(event.hits);
        t.push_back(ms(t1));
        f.push_back(r.findingMs);
        g.push_back(r.fittingMs + r.selectionMs);
        if (k == 0) {
          tracks += static_cast<double>(r.tracks.size());
          warnIfTruncated(
              std::to_string(bx) + " BX, event " + std::to_string(e + 1),
              r.steps);
        }
      }
      findMs.push_back(median(f));
      fitMs.push_back(median(g));
      totalMs.push_back(median(t));
    }
    double n = static_cast<double>(opt.events);
    std::printf("%6zu %9.0f %8.0f %12.1f %12.1f %12.1f %12.1f\n", bx, hits / n,
                tracks / n, median(simMs), median(findMs), median(fitMs),
                median(totalMs));
  }
  std::printf("peak RSS %.0f MiB\n", peakRssMb());
}

}  // namespace

void addBenchCommand(CLI::App& app) {
  auto opt = std::make_shared<BenchOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bench",
      "End-to-end timing (one thread) versus overlaid bunch crossings");
  addSampleOptions(*cmd, opt->sample);
  addReconstructionOptions(*cmd, opt->reco);
  cmd->add_option("--overlays", opt->overlays,
                  "Numbers of overlaid bunch crossings")
      ->capture_default_str()
      ->check(wholeNumber(0, 100000));
  cmd->add_option("-n,--events", opt->events, "Events per setting")
      ->capture_default_str()
      ->check(wholeNumber(1, 100000));
  cmd->add_option("--repeat", opt->repeat, "Reconstructions per event")
      ->capture_default_str()
      ->check(wholeNumber(1, 1000));
  cmd->callback([opt]() { runBench(*opt); });
}

}  // namespace conftrack::cli
