// TrackML commands: score submissions, make TrackML-like events with truth
// from real particle files, and compare such a simulation with the real
// files (validate-trackml).

#include "conftrack/core/DataFiles.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/core/Random.hpp"
#include "conftrack/core/TextFile.hpp"
#include "conftrack/evaluation/SimulationValidation.hpp"
#include "conftrack/frontend/SubmissionScore.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/TrackmlDetector.hpp"
#include "conftrack/geometry/TrackmlModuleLayout.hpp"
#include "conftrack/io/CsvWriter.hpp"
#include "conftrack/io/EventFiles.hpp"
#include "conftrack/io/TrackmlIds.hpp"
#include "conftrack/io/TrackmlReader.hpp"
#include "conftrack/io/TrackmlSubmission.hpp"
#include "conftrack/io/TrackmlWriter.hpp"
#include "conftrack/simulation/TrackmlEvents.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "Commands.hpp"
#include "EventLoop.hpp"
#include "OptionChecks.hpp"

namespace conftrack::cli {

namespace {

/// Noise with --ideal-layers, which have no sensors to carry a rate: the
/// real files' mean share of hits without a particle (16-19 %).
constexpr double kIdealLayersNoiseFraction = 0.17;

/// A number as tables and help texts show it ("0.943", not "0.943000";
/// "inf").
std::string formatNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof text, std::isinf(value) ? "inf" : "%g", value);
  return text;
}

struct ScoreOptions {
  std::string submissions;
  std::string events;
  std::size_t threads = 0;
};

void runScore(const ScoreOptions& opt) {
  std::vector<std::uint64_t> numbers = requireEvents(opt.events);
  std::vector<TrackmlScore> scores(numbers.size());
  forEachEvent(numbers.size(), opt.threads, "score", [&](std::size_t i) {
    std::filesystem::path file =
        std::filesystem::path(opt.submissions) / submissionFileName(numbers[i]);
    if (!std::filesystem::exists(file)) {
      file += ".gz";
    }
    scores[i] = scoreSubmission(file, opt.events, numbers[i]);
  });
  std::printf("%10s %8s %10s %10s\n", "event", "score", "efficiency",
              "fake rate");
  double sum = 0.0;
  double eff = 0.0;
  double fake = 0.0;
  for (std::size_t i = 0; i < numbers.size(); ++i) {
    std::printf("%10llu %8.4f %10.4f %10.4f\n",
                static_cast<unsigned long long>(numbers[i]), scores[i].score,
                scores[i].efficiency, scores[i].fakeRate);
    sum += scores[i].score;
    eff += scores[i].efficiency;
    fake += scores[i].fakeRate;
  }
  double n = static_cast<double>(numbers.size());
  std::printf(
      "%10s %8.4f %10.4f %10.4f   (TrackML score: mean over events;"
      " efficiency and fake rate: double 50 %% matching)\n",
      "mean", sum / n, eff / n, fake / n);
}

struct TrackmlSimOptions {
  std::string input;
  std::string output = "trackml-events";
  std::string detectorsCsv =
      (dataDirectory() / "data/trackml/detectors.csv.gz").string();
  /// Noise as a fraction of all hits; unset: noisePerSensor with sensors,
  /// kIdealLayersNoiseFraction with --ideal-layers.
  std::optional<double> noise;
  /// Mean noise hits per sensor and event (with sensors, without --noise).
  std::optional<double> noisePerSensor;
  double minPt = 0.15;
  /// The layers as ideal cylinders and disks, not their real sensors.
  bool idealLayers = false;
  /// Follow loopers for Simulator::Config::maxTurns turns instead of half
  /// a turn.
  bool followLoopers = false;
  std::uint64_t seed = 1;
  std::size_t threads = 0;
  /// Unset: the real vertices; set: the interactions are moved to it.
  std::optional<LuminousRegion::Config> luminousRegion = std::nullopt;
  /// --beam-line X,Y [mm, as typed]: the whole event moved transversely.
  std::vector<double> beamLine;
};

/// The TrackML detector and its sensors from detectors.csv, and the
/// simulation of real particle lists on it.
struct TrackmlSimulationSetup {
  explicit TrackmlSimulationSetup(const TrackmlSimOptions& opt)
      : modules(parseTrackmlModules(readTextFile(opt.detectorsCsv),
                                    opt.detectorsCsv)),
        detector(buildTrackmlDetector(modules, detectorOptions(opt))),
        sensors(
            opt.idealLayers
                ? nullptr
                : std::make_shared<const ModuleLayout>(buildTrackmlModuleLayout(
                      modules, detector, detectorOptions(opt)))),
        simulation(detector, sensors, simulationConfig(opt)) {}

  static TrackmlDetectorOptions detectorOptions(const TrackmlSimOptions& opt) {
    TrackmlDetectorOptions options;
    options.source = opt.detectorsCsv;
    return options;
  }
  static TrackmlEventSimulation::Config simulationConfig(
      const TrackmlSimOptions& opt) {
    TrackmlEventSimulation::Config cfg;
    if (opt.noisePerSensor && (opt.noise || opt.idealLayers)) {
      throw InputError(
          "--noise-per-sensor: not with --noise or --ideal-layers (a rate "
          "per sensor needs the sensors; give one noise model)");
    }
    if (opt.noise) {
      cfg.noiseFraction = *opt.noise;
    } else if (opt.idealLayers) {
      cfg.noiseFraction = kIdealLayersNoiseFraction;
    } else {
      cfg.noisePerSensor = opt.noisePerSensor.value_or(kTrackmlNoisePerSensor);
    }
    cfg.minPt = opt.minPt;
    cfg.seed = opt.seed;
    if (opt.followLoopers) {
      cfg.simulator.maxTurns = Simulator::Config().maxTurns;
    }
    cfg.luminousRegion = opt.luminousRegion;
    if (opt.beamLine.size() == 2) {
      cfg.beamLine = Vector2(opt.beamLine[0], opt.beamLine[1]) * units::mm;
    }
    return cfg;
  }

  /// The real event's particles (with their real nhits) and hits (raw
  /// ids), and the simulation of those particles.
  struct EventPair {
    Event real;
    Event simulated;
  };
  EventPair simulate(const std::string& dir, std::uint64_t number) const {
    EventPair pair;
    pair.real = readEvent(dir, number, nullptr, ReadOptions{false, true});
    if (pair.real.particles.empty()) {
      throw InputError(
          dir, "event " + std::to_string(number) + " has no particles file");
    }
    try {
      pair.simulated = simulation.simulate(number, pair.real.particles);
    } catch (const InputError& e) {
      // Particle ids without TrackML vertex ids (--luminous-region).
      throw InputError(
          EventFiles::locate(dir, number).particles.value().string(), e.what());
    }
    return pair;
  }

  /// The same simulation with the run seed of repeat `repeat` (>= 1) of
  /// validate-trackml: independent random streams for every event.
  TrackmlEventSimulation repeatSimulation(std::uint64_t repeat) const {
    TrackmlEventSimulation::Config config = simulation.config();
    config.seed = mix64(config.seed ^ mix64(repeat));
    return TrackmlEventSimulation(detector, sensors, config);
  }

  std::vector<TrackmlModule> modules;
  Detector detector;
  std::shared_ptr<const ModuleLayout> sensors;
  TrackmlEventSimulation simulation;
};

/// The options of the TrackML simulation, shared by simulate-trackml and
/// validate-trackml.
void addSimulationOptions(CLI::App& command, TrackmlSimOptions& sim) {
  command
      .add_option("--detectors-csv", sim.detectorsCsv,
                  "The TrackML detectors.csv(.gz): the sensors")
      ->capture_default_str();
  command
      .add_option("--noise-per-sensor", sim.noisePerSensor,
                  "Mean noise hits per sensor and event, a Poisson count per "
                  "layer whatever the occupancy (default: " +
                      formatNumber(kTrackmlNoisePerSensor) +
                      ", the real files')")
      ->check(finiteNumber(0.0, 1e3));
  command
      .add_option("--noise", sim.noise,
                  "Noise as a fraction of all hits instead (the model before; "
                  "default with --ideal-layers: " +
                      formatNumber(kIdealLayersNoiseFraction) + ")")
      ->check(finiteNumber(0.0, 0.99));
  command
      .add_option("--min-pt", sim.minPt,
                  "The simulation's pT cut [GeV]: a particle ends after the "
                  "first surface it crosses below it")
      ->capture_default_str()
      ->check(finiteNumber(0.0, 1e6));
  command.add_flag("--ideal-layers", sim.idealLayers,
                   "Layers as ideal cylinders and disks instead of their "
                   "real sensors (the simulation before module level)");
  command.add_flag("--follow-loopers", sim.followLoopers,
                   "Follow loopers for up to 10 turns instead of half a turn "
                   "(the ACTS loop protection of the real files)");
  command.add_option("--seed", sim.seed, "Run seed")
      ->capture_default_str()
      ->check(wholeNumber(0, UINT64_MAX));
}

void runTrackmlSim(const TrackmlSimOptions& opt) {
  const TrackmlSimulationSetup setup(opt);
  std::vector<std::uint64_t> numbers = requireEvents(opt.input);
  prepareOutputFolder(opt.output, "-o");
  forEachEvent(numbers.size(), opt.threads, "simulate", [&](std::size_t i) {
    writeEvent(opt.output, setup.simulate(opt.input, numbers[i]).simulated,
               &setup.detector.trackmlLayerMap(), {});
  });
}

struct ValidateOptions {
  TrackmlSimOptions sim;
  std::vector<std::uint64_t> events;
  std::size_t minParticles = 100;
  double tolerance = 0.05;
  std::size_t repeats = 1;
  std::string output;
};

std::string formatDeviation(double deviation) {
  if (std::isnan(deviation)) {
    return "-";
  }
  char text[32];
  std::snprintf(text, sizeof text, "%+.1f %%", 100.0 * deviation);
  return text;
}

void printValidation(const SimulationValidationTables& t,
                     const ValidateOptions& opt,
                     const TrackmlEventSimulation::Config& simulation) {
  std::printf(
      "Hits per particle, real (nhits column) and simulated (mean of %zu "
      "simulation%s), %zu events, %zu particles (%zu outside the table):\n",
      opt.repeats, opt.repeats == 1 ? "" : "s", t.events, t.particles,
      t.outsideBins);
  std::printf("%-12s %-10s %-9s %9s %8s %9s %10s\n", "pT [GeV]", "|eta|",
              "origin", "particles", "real", "simulated", "deviation");
  for (const HitCountBin& b : t.bins) {
    if (b.particles == 0) {
      continue;
    }
    const std::string pt = formatNumber(b.ptMin) + "-" + formatNumber(b.ptMax);
    const std::string eta =
        formatNumber(b.absEtaMin) + "-" + formatNumber(b.absEtaMax);
    std::printf("%-12s %-10s %-9s %9zu %8.2f %9.2f %10s%s\n", pt.c_str(),
                eta.c_str(), b.displaced ? "displaced" : "prompt", b.particles,
                b.realMean(), b.simulatedMean(),
                formatDeviation(b.deviation()).c_str(),
                b.particles >= opt.minParticles ? "" : "  (few)");
  }
  const BinAgreement agreement =
      binAgreement(t, opt.minParticles, opt.tolerance);
  std::printf(
      "Bins with >= %zu particles: %zu, within %.1f %%: %zu; worst %s\n\n",
      opt.minParticles, agreement.bins, 100.0 * opt.tolerance, agreement.within,
      formatDeviation(agreement.worst).c_str());
  const std::string noise =
      simulation.noisePerSensor > 0.0
          ? formatNumber(simulation.noisePerSensor) + " noise hits per sensor"
          : "noise fraction " + formatNumber(simulation.noiseFraction);
  std::printf("Hits per (volume, layer), real and simulated (%s included):\n",
              noise.c_str());
  std::printf("%6s %6s %9s %9s %10s\n", "volume", "layer", "real", "simulated",
              "deviation");
  for (const LayerHitCount& l : t.layers) {
    std::printf("%6u %6u %9zu %9zu %10s\n", l.id.volume, l.id.layer, l.real,
                l.simulated, formatDeviation(l.deviation()).c_str());
  }
}

void writeValidation(const SimulationValidationTables& t,
                     const std::string& folder) {
  const std::filesystem::path dir(folder);
  CsvWriter bins((dir / "hit_counts.csv").string(),
                 {"pt_min_GeV", "pt_max_GeV", "abs_eta_min", "abs_eta_max",
                  "displaced", "particles", "real_mean", "simulated_mean"});
  for (const HitCountBin& b : t.bins) {
    bins.add(b.ptMin);
    // CSV numbers are finite: an open last edge is written as -1.
    bins.add(std::isinf(b.ptMax) ? -1.0 : b.ptMax);
    bins.add(b.absEtaMin);
    bins.add(b.absEtaMax);
    bins.add(b.displaced ? 1 : 0);
    bins.add(b.particles);
    bins.add(b.realMean());
    bins.add(b.simulatedMean());
    bins.endRow();
  }
  bins.write(dir / "hit_counts.csv", false);
  CsvWriter layers((dir / "layer_hits.csv").string(),
                   {"volume_id", "layer_id", "real_hits", "simulated_hits"});
  for (const LayerHitCount& l : t.layers) {
    layers.add(l.id.volume);
    layers.add(l.id.layer);
    layers.add(l.real);
    layers.add(l.simulated);
    layers.endRow();
  }
  layers.write(dir / "layer_hits.csv", false);
}

void runValidate(const ValidateOptions& opt) {
  const std::vector<std::uint64_t> numbers =
      selectEvents(opt.sim.input, opt.events);
  if (!opt.output.empty()) {
    prepareOutputFolder(opt.output, "-o");
  }
  const TrackmlSimulationSetup setup(opt.sim);
  const SimulationValidation validation(SimulationValidation::Config{});
  // Built once: repeat r >= 1 simulates with repeatSimulations[r - 1].
  std::vector<TrackmlEventSimulation> repeatSimulations;
  for (std::size_t r = 1; r < opt.repeats; ++r) {
    repeatSimulations.push_back(setup.repeatSimulation(r));
  }
  std::vector<SimulationValidationTables> perEvent(numbers.size());
  forEachEvent(numbers.size(), opt.sim.threads, "validate", [&](std::size_t i) {
    const auto pair = setup.simulate(opt.sim.input, numbers[i]);
    std::vector<VolumeLayer> realHits;
    realHits.reserve(pair.real.hits.size());
    for (const Hit& h : pair.real.hits) {
      // Raw ids (no detector): subdetector = volume_id.
      realHits.push_back({h.detId.subdetector, h.detId.layer});
    }
    std::vector<SimulationValidationTables> repeats;
    std::vector<VolumeLayer> simulatedHits;
    for (std::size_t r = 0; r < opt.repeats; ++r) {
      Event again;
      if (r > 0) {
        again =
            repeatSimulations[r - 1].simulate(numbers[i], pair.real.particles);
      }
      const Event& simulated = r == 0 ? pair.simulated : again;
      simulatedHits.clear();
      simulatedHits.reserve(simulated.hits.size());
      for (const Hit& h : simulated.hits) {
        const std::optional<TrackmlId> id =
            toTrackml(h.detId, &setup.detector.trackmlLayerMap());
        if (id) {
          simulatedHits.push_back({id->volume, id->layer});
        }
      }
      repeats.push_back(validation.run(
          {pair.real.particles, simulated.particles, realHits, simulatedHits}));
    }
    perEvent[i] = SimulationValidationTables::averageRepeats(repeats);
  });
  // Summed in event order: the same tables for any thread count.
  SimulationValidationTables total = validation.empty();
  for (const SimulationValidationTables& t : perEvent) {
    total.merge(t);
  }
  printValidation(total, opt, setup.simulation.config());
  if (!opt.output.empty()) {
    writeValidation(total, opt.output);
  }
}

}  // namespace

void addTrackmlCommands(CLI::App& app) {
  auto score = std::make_shared<ScoreOptions>();
  CLI::App* cmd = app.add_subcommand(
      "score", "TrackML score of submission files against events with truth");
  cmd->add_option("-s,--submissions", score->submissions,
                  "Folder with eventNNNNNNNNN-submission.csv files")
      ->required();
  cmd->add_option("-i,--input", score->events,
                  "Folder with the events (hits, truth, particles)")
      ->required();
  addThreadsOption(*cmd, score->threads);
  cmd->callback([score]() { runScore(*score); });

  auto sim = std::make_shared<TrackmlSimOptions>();
  CLI::App* s = app.add_subcommand(
      "simulate-trackml",
      "TrackML-like events with truth: the particles of real TrackML events "
      "through the fast simulation of the TrackML detector");
  s->add_option("-i,--input", sim->input,
                "Folder with TrackML events (particles files are used)")
      ->required();
  s->add_option("-o,--output", sim->output, "Output folder")
      ->capture_default_str();
  addSimulationOptions(*s, *sim);
  auto region = std::make_shared<LuminousRegionOptions>();
  addLuminousRegionOptions(
      *s, *region,
      "moves every interaction (particles with one TrackML vertex id) along "
      "z to a point drawn from it, e.g. hllhc; default: the real vertices");
  addBeamLineOption(*s, "--beam-line", sim->beamLine,
                    "Transverse position X,Y [mm] where the beams collide: "
                    "every particle moves by it (the real events' beams are "
                    "on the axis); reconstruct with --beam-spot X,Y");
  addThreadsOption(*s, sim->threads);
  s->callback([sim, region]() {
    sim->luminousRegion = chosenLuminousRegion(*region);
    runTrackmlSim(*sim);
  });

  auto val = std::make_shared<ValidateOptions>();
  CLI::App* v = app.add_subcommand(
      "validate-trackml",
      "Simulate the particles of real TrackML events and compare with the "
      "real files: mean hits per particle (nhits) in pT x |eta| x production "
      "radius bins, hits per (volume, layer)");
  v->add_option("-i,--input", val->sim.input,
                "Folder with real TrackML events (hits and particles files)")
      ->required();
  v->add_option("--events", val->events,
                "Event numbers (default: all in the folder)");
  v->add_option("-o,--output", val->output,
                "Folder for hit_counts.csv and layer_hits.csv (default: "
                "print only)");
  addSimulationOptions(*v, val->sim);
  v->add_option("--min-particles", val->minParticles,
                "Bins with fewer particles are marked (few)")
      ->capture_default_str()
      ->check(wholeNumber(1, 1e9));
  v->add_option("--repeat", val->repeats,
                "Simulate every event this many times (independent random "
                "streams) and compare the mean: the simulation's own "
                "spread out of the comparison")
      ->capture_default_str()
      ->check(wholeNumber(1, 100));
  v->add_option("--tolerance", val->tolerance,
                "Relative deviation counted as agreement")
      ->capture_default_str()
      ->check(finiteNumber(0.0, 10.0));
  addThreadsOption(*v, val->sim.threads);
  v->callback([val]() { runValidate(*val); });
}

}  // namespace conftrack::cli
