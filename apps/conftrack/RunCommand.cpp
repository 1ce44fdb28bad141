#include "conftrack/core/Error.hpp"
#include "conftrack/core/Log.hpp"
#include "conftrack/evaluation/PerformanceCollector.hpp"
#include "conftrack/evaluation/PerformanceReport.hpp"
#include "conftrack/frontend/EventDisplay.hpp"
#include "conftrack/frontend/ReportFiles.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/simulation/EventSimulation.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>

#include "Commands.hpp"
#include "EventLoop.hpp"
#include "OptionChecks.hpp"
#include "ReconstructionOptions.hpp"
#include "StepReport.hpp"

namespace conftrack::cli {

namespace {

struct RunOptions {
  ReconstructionOptions reco;
  SampleOptions sample;
  std::size_t events = 100;
  std::string output = "conftrack-out";
  std::size_t threads = 0;
  bool noPlots = false;
  std::string study;
  ShardOption shard;
};

/// One simulated sample of a report.
struct SubSample {
  EventSimulation::Config sim;
  std::size_t events = 0;
};

/// One report: a folder, its samples, evaluated together.
struct ReportSpec {
  std::string folder;
  std::string sample;  ///< description in the report
  bool singleParticle = false;
  std::vector<SubSample> samples;
};

bool isSingleParticle(const std::string& sample) {
  return sample == "muons" || sample == "gun";
}

/// A particle-gun sample of muons of both charges.
SubSample muonGun(const RunOptions& opt, const std::string& settings,
                  std::size_t events) {
  SubSample s;
  s.sim = makeSimulationConfig(opt.sample);
  s.sim.sample = "muons";
  s.sim.overlayBx = 0;
  s.sim.generatorToml =
      "[generator]\nsample = \"gun\"\nparticle = \"mu-\"\n"
      "random_charge = true\n" +
      settings;
  s.sim.generatorTomlSource = "study settings";
  s.events = events;
  return s;
}

/// The reports of `--study` (the paper's section 5 figures) or of a plain
/// run.
std::vector<ReportSpec> reportsOf(const RunOptions& opt) {
  std::vector<ReportSpec> reports;
  const std::size_t n = opt.events;
  if (opt.study.empty()) {
    ReportSpec r{"",
                 opt.sample.sample,
                 isSingleParticle(opt.sample.sample),
                 {{makeSimulationConfig(opt.sample), n}}};
    reports.push_back(r);
  } else if (opt.study == "muons") {
    // Resolutions versus pT at five polar angles (figure 5b and the d0, z0,
    // phi, theta studies), and efficiency versus theta for each pT (5a).
    ReportSpec res{
        "resolutions", "muons pT 1/10/100 GeV, theta 10-89 deg", true, {}};
    for (double pt : {1.0, 10.0, 100.0}) {
      for (double theta : {10.0, 30.0, 50.0, 70.0, 89.0}) {
        res.samples.push_back(
            muonGun(opt,
                    "pt_GeV = " + std::to_string(pt) +
                        "\ntheta_deg = " + std::to_string(theta) + "\n",
                    n));
      }
    }
    reports.push_back(res);
    for (double pt : {1.0, 10.0, 100.0}) {
      std::string name = "efficiency_pt" + std::to_string(int(pt));
      reports.push_back(
          {name,
           "muons pT " + std::to_string(int(pt)) + " GeV",
           true,
           {muonGun(opt,
                    "pt_GeV = " + std::to_string(pt) +
                        "\ntheta_min_deg = 8.0\ntheta_max_deg = 90.0\n"
                        "theta_sampling = \"theta\"\n",
                    5 * n)}});
    }
  } else if (opt.study == "ttbar") {
    // Figures 6 and 7: with and without 30 BX of gamma gamma -> hadrons.
    for (std::size_t bx : {std::size_t{0}, std::size_t{30}}) {
      SampleOptions so = opt.sample;
      so.sample = "ttbar3tev";
      so.overlayBx = bx;
      reports.push_back({bx == 0 ? "ttbar" : "ttbar_30bx",
                         "ttbar3tev",
                         false,
                         {{makeSimulationConfig(so), n}}});
    }
  } else if (opt.study == "displaced") {
    // Efficiency versus production radius of displaced muons (80 < theta,
    // phi < 100 deg, radius up to 600 mm), as the CLICdp validation.
    for (double p : {1.0, 10.0, 100.0}) {
      reports.push_back(
          {"displaced_p" + std::to_string(int(p)),
           "displaced muons p " + std::to_string(int(p)) + " GeV",
           true,
           {muonGun(opt,
                    "p_GeV = " + std::to_string(p) +
                        "\ntheta_min_deg = 80.0\ntheta_max_deg = 100.0\n"
                        "phi_min_deg = 80.0\nphi_max_deg = 100.0\n"
                        "r_min_mm = 0.0\nr_max_mm = 600.0\n",
                    5 * n)}});
    }
  } else {
    throw InputError("--study " + opt.study +
                     ": unknown study (muons, ttbar, displaced)");
  }
  return reports;
}

void runReport(const RunOptions& opt, const Detector& detector,
               const std::shared_ptr<const ModuleLayout>& modules,
               const Reconstruction& reco, const ReportSpec& spec) {
  using Clock = std::chrono::steady_clock;
  std::filesystem::path dir = std::filesystem::path(opt.output) / spec.folder;
  std::size_t totalEvents = 0;
  for (const SubSample& sub : spec.samples) {
    totalEvents += sub.events;
  }
  // This process's events: indices [first, last) of the report's events,
  // which run on across its sub-samples.
  const auto [first, last] = shardRange(totalEvents, opt.shard);
  PerformanceCollector collector(spec.singleParticle
                                     ? PerformanceConfig::singleParticleSample()
                                     : PerformanceConfig{},
                                 first);
  std::size_t offset = 0;
  std::size_t overlayBx = 0;
  std::string description;
  Event firstEvent;
  std::vector<Track> firstTracks;
  for (const SubSample& sub : spec.samples) {
    EventSimulation::Config config = sub.sim;
    config.modules = modules;
    EventSimulation sim(detector, config);
    overlayBx = sim.config().overlayBx;
    description = sim.description();
    const std::size_t subStart = offset;
    offset += sub.events;
    const std::size_t begin = std::clamp(first, subStart, offset);
    const std::size_t end = std::clamp(last, subStart, offset);
    if (begin == end) {
      continue;
    }
    CONFTRACK_INFO("run: " << end - begin << " events of " << description
                           << " in " << detector.name() << ", seed "
                           << sub.sim.seed << ", "
                           << effectiveThreads(opt.threads) << " threads");
    forEachEvent(end - begin, opt.threads, "run", [&](std::size_t i) {
      const std::size_t index = begin + i;
      const std::size_t local = index - subStart;
      auto t0 = Clock::now();
      // Event numbers run on across the sub-samples of a report: with the
      // same seed, event k of every sub-sample would reuse the same random
      // streams (smearing, scattering), and the 15 points of --study muons
      // would be one sample of -n independent tracks, not 15 (their pull
      // widths then scattered by +-10 % at -n 200).
      Event event = sim.simulate(index + 1);
      double simMs =
          std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      Reconstruction::Result r = reco.run(event.hits);
      warnIfTruncated(spec.folder.empty()
                          ? "event " + std::to_string(local + 1)
                          : spec.folder + " event " + std::to_string(local + 1),
                      r.steps);
      collector.addEvent(index, event, r.tracks, detector.bz(), r.steps,
                         {simMs, r.findingMs, r.fittingMs + r.selectionMs});
      if (index == first) {
        firstEvent = std::move(event);
        firstTracks = std::move(r.tracks);
      }
    });
  }
  RunMetadata meta;
  meta.detector = detector.name();
  meta.sample =
      spec.samples.size() == 1 ? spec.samples.front().sim.sample : spec.sample;
  meta.overlayBx = overlayBx;
  meta.events = totalEvents;
  meta.seed = opt.sample.seed;
  meta.threads = effectiveThreads(opt.threads);
  meta.shard = {opt.shard.index, opt.shard.count, first};
  PerformanceSummary summary = collector.summary();
  std::filesystem::create_directories(dir);
  if (!opt.noPlots && first < last) {
    drawEventDisplay(dir / "event_display.png", firstEvent.hits, firstTracks,
                     detector.name() + ", " + description + ", event " +
                         std::to_string(first + 1),
                     std::cerr);
  }
  printSummaryTable(std::cout, meta, summary);
  writePerformanceReport(dir, meta, summary, !opt.noPlots, std::cerr);
  std::cout << "report: " << (dir / "index.html").string() << '\n';
}

void runRun(const RunOptions& opt) {
  Detector detector = loadDetector(opt.reco.detector);
  Reconstruction reco(detector, makeReconstructionConfig(opt.reco, detector));
  const std::vector<ReportSpec> reports = reportsOf(opt);
  const std::shared_ptr<const ModuleLayout> modules =
      loadModuleLayout(opt.sample, detector);
  for (const ReportSpec& spec : reports) {
    // Not opt.output / "": the trailing "/" hides that a file has the name.
    prepareOutputFolder(spec.folder.empty()
                            ? std::filesystem::path(opt.output)
                            : std::filesystem::path(opt.output) / spec.folder,
                        "-o");
  }
  for (const ReportSpec& spec : reports) {
    runReport(opt, detector, modules, reco, spec);
  }
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
      ->check(wholeNumber(1, 100000000));
  cmd->add_option("-o,--output", opt->output, "Output folder")
      ->capture_default_str();
  addThreadsOption(*cmd, opt->threads);
  addShardOption(*cmd, opt->shard);
  cmd->add_flag("--no-plots", opt->noPlots, "Skip the Python plots");
  cmd->add_option("--study", opt->study,
                  "Preset reproducing the paper's figures: muons (-n events "
                  "per pT and theta point), ttbar (with and without 30 BX), "
                  "displaced; one report per sub-folder of -o");
  cmd->callback([opt]() { runRun(*opt); });
}

}  // namespace conftrack::cli
