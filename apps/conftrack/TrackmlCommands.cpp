// TrackML commands: score submissions, and make TrackML-like events with
// truth from real particle files.

#include "conftrack/core/DataFiles.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/TrackmlDetector.hpp"
#include "conftrack/io/EventFiles.hpp"
#include "conftrack/io/TextFile.hpp"
#include "conftrack/io/TrackmlReader.hpp"
#include "conftrack/io/TrackmlSubmission.hpp"
#include "conftrack/io/TrackmlWriter.hpp"
#include "conftrack/simulation/TrackmlEvents.hpp"

#include <cstdio>
#include <filesystem>
#include <memory>

#include "Commands.hpp"
#include "EventLoop.hpp"
#include "OptionChecks.hpp"

namespace conftrack::cli {

namespace {

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
  double noise = 0.17;
  double minPt = 0.15;
  std::uint64_t seed = 1;
  std::size_t threads = 0;
};

void runTrackmlSim(const TrackmlSimOptions& opt) {
  std::vector<TrackmlModule> modules =
      parseTrackmlModules(readTextFile(opt.detectorsCsv), opt.detectorsCsv);
  TrackmlDetectorOptions detOptions;
  detOptions.source = opt.detectorsCsv;
  Detector detector = buildTrackmlDetector(modules, detOptions);
  TrackmlModuleMap map(modules);
  TrackmlEventSimulation::Config cfg;
  cfg.noiseFraction = opt.noise;
  cfg.minPt = opt.minPt;
  cfg.seed = opt.seed;
  TrackmlEventSimulation sim(detector, &map, cfg);
  std::vector<std::uint64_t> numbers = requireEvents(opt.input);
  prepareOutputFolder(opt.output, "-o");
  forEachEvent(numbers.size(), opt.threads, "simulate", [&](std::size_t i) {
    Event real =
        readEvent(opt.input, numbers[i], nullptr, ReadOptions{false, true});
    if (real.particles.empty()) {
      throw InputError(opt.input, "event " + std::to_string(numbers[i]) +
                                      " has no particles file");
    }
    Event event = sim.simulate(numbers[i], real.particles);
    writeEvent(opt.output, event, &detector, {});
  });
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
  s->add_option("--detectors-csv", sim->detectorsCsv,
                "The TrackML detectors.csv(.gz) (for the module ids)")
      ->capture_default_str();
  s->add_option("--noise", sim->noise, "Fraction of noise hits per layer")
      ->capture_default_str()
      ->check(finiteNumber(0.0, 0.99));
  s->add_option("--min-pt", sim->minPt,
                "Particles below this pT [GeV] are "
                "not simulated")
      ->capture_default_str()
      ->check(finiteNumber(0.0, 1e6));
  s->add_option("--seed", sim->seed, "Run seed")
      ->capture_default_str()
      ->check(wholeNumber(0, UINT64_MAX));
  addThreadsOption(*s, sim->threads);
  s->callback([sim]() { runTrackmlSim(*sim); });
}

}  // namespace conftrack::cli
