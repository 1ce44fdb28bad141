// The diagnose command: TrackML truth diagnostics of submission files (where
// the weight the score does not get goes, by cause, in pT, |eta| and
// production radius bins; docs/diagnostics.md).

#include "conftrack/core/Error.hpp"
#include "conftrack/core/TextFile.hpp"
#include "conftrack/evaluation/TrackmlDiagnostics.hpp"
#include "conftrack/io/TrackmlSubmission.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "Commands.hpp"
#include "EventLoop.hpp"
#include "OptionChecks.hpp"

namespace conftrack::cli {

namespace {

using Json = nlohmann::ordered_json;

struct DiagnoseOptions {
  std::string submissions;
  std::string events;
  std::string output;
  std::uint32_t maxStrayHits = TrackmlDiagnosticsConfig().maxStrayHits;
  std::size_t threads = 0;
};

/// The causes of lost weight: column title, JSON key and value.
struct Cause {
  const char* title;
  const char* key;
  double WeightBreakdown::*value;
};

constexpr Cause kCauses[] = {
    {"never", "never_found", &WeightBreakdown::neverFound},
    {"split", "split", &WeightBreakdown::split},
    {"partial", "partial", &WeightBreakdown::partial},
    {"impure", "impure", &WeightBreakdown::impure},
    {"off-same", "left_off_same_layer", &WeightBreakdown::leftOffSameLayer},
    {"off-new", "left_off_new_layer", &WeightBreakdown::leftOffNewLayer},
    {"other", "other_tracks", &WeightBreakdown::otherTracks},
    {"noise", "noise", &WeightBreakdown::noise},
};

void printCauses(const WeightBreakdown& w) {
  for (const Cause& c : kCauses) {
    std::printf(" %8.4f", w.*c.value);
  }
}

void printEventRow(const std::string& name, const TrackmlDiagnostics& d) {
  std::printf("%10s %8.4f", name.c_str(), d.weight.found);
  printCauses(d.weight);
  std::printf(" %8.1f %8.4f %8.4f %8.1f\n", d.tracks, d.fakeFraction,
              d.meanFoundHitFraction, d.foreignHitsOnMatched);
}

std::string edge(double value) {
  char text[32];
  std::snprintf(text, sizeof text, std::isinf(value) ? "inf" : "%g", value);
  return text;
}

void printHistogram(const DiagnosticsHistogram& h, const char* title) {
  std::printf("%-12s %9s %8s %8s %8s", title, "particles", "weight", "found",
              "lost");
  for (const Cause& c : kCauses) {
    std::printf(" %8s", c.title);
  }
  std::printf("\n");
  auto row = [](const std::string& name, double particles,
                const WeightBreakdown& w) {
    std::printf("%-12s %9.1f %8.4f %8.4f %8.4f", name.c_str(), particles,
                w.total(), w.found, w.lost());
    printCauses(w);
    std::printf("\n");
  };
  for (const DiagnosticsBin& b : h.bins) {
    row(edge(b.min) + "-" + edge(b.max), b.particles, b.weight);
  }
  row("outside", 0.0, h.outside);
  std::printf("\n");
}

void printDiagnostics(const std::vector<std::uint64_t>& numbers,
                      const std::vector<TrackmlDiagnostics>& perEvent,
                      const TrackmlDiagnostics& mean) {
  std::printf(
      "TrackML weight by cause (fractions of the total weight; score + "
      "causes = 1):\n");
  std::printf("%10s %8s", "event", "score");
  for (const Cause& c : kCauses) {
    std::printf(" %8s", c.title);
  }
  std::printf(" %8s %8s %8s %8s\n", "tracks", "fakes", "hitfrac", "foreign");
  for (std::size_t i = 0; i < numbers.size(); ++i) {
    printEventRow(std::to_string(numbers[i]), perEvent[i]);
  }
  printEventRow("mean", mean);
  std::printf(
      "(fakes: fraction of tracks with no particle > 50 %%; hitfrac: mean "
      "fraction of a found particle's hits on its track; foreign: hits of "
      "others on found particles' tracks per event)\n\n");
  const LostHitPlaces& p = mean.places;
  std::printf(
      "Where found particles lose hits (mean): left off before their "
      "track's first hit %.4f, between its hits %.4f, after its last %.4f; on "
      "another track as its first or last hit %.4f, inside it %.4f\n\n",
      p.leftOffBefore, p.leftOffBetween, p.leftOffAfter, p.otherAtHolderEnd,
      p.otherInsideHolder);
  std::printf("In bins (mean over events):\n");
  printHistogram(mean.pt, "pT [GeV]");
  printHistogram(mean.absEta, "|eta|");
  printHistogram(mean.radius, "r_prod [mm]");
}

/// JSON numbers are finite: an open last edge is written as null.
Json edgeJson(double value) {
  return std::isinf(value) ? Json(nullptr) : Json(value);
}

Json breakdownJson(const WeightBreakdown& w) {
  Json j;
  j["found"] = w.found;
  j["lost"] = w.lost();
  for (const Cause& c : kCauses) {
    j[c.key] = w.*c.value;
  }
  return j;
}

Json histogramJson(const DiagnosticsHistogram& h) {
  Json bins = Json::array();
  for (const DiagnosticsBin& b : h.bins) {
    Json j;
    j["min"] = edgeJson(b.min);
    j["max"] = edgeJson(b.max);
    j["particles"] = b.particles;
    j["weight"] = b.weight.total();
    j["breakdown"] = breakdownJson(b.weight);
    bins.push_back(j);
  }
  Json j;
  j["bins"] = bins;
  j["outside"] = breakdownJson(h.outside);
  return j;
}

Json diagnosticsJson(const TrackmlDiagnostics& d) {
  Json j;
  j["score"] = d.weight.found;
  j["total_weight"] = d.totalWeight;
  j["weights_computed"] = d.weightsComputed;
  j["breakdown"] = breakdownJson(d.weight);
  Json places;
  places["left_off_before"] = d.places.leftOffBefore;
  places["left_off_between"] = d.places.leftOffBetween;
  places["left_off_after"] = d.places.leftOffAfter;
  places["other_at_holder_end"] = d.places.otherAtHolderEnd;
  places["other_inside_holder"] = d.places.otherInsideHolder;
  j["lost_hit_places"] = places;
  j["tracks"] = d.tracks;
  j["fake_tracks"] = d.fakeTracks;
  j["fake_fraction"] = d.fakeFraction;
  j["found_particles"] = d.foundParticles;
  j["mean_found_hit_fraction"] = d.meanFoundHitFraction;
  j["foreign_hits_on_matched"] = d.foreignHitsOnMatched;
  j["foreign_weight_on_matched"] = d.foreignWeightOnMatched;
  j[d.pt.quantity] = histogramJson(d.pt);
  j[d.absEta.quantity] = histogramJson(d.absEta);
  j[d.radius.quantity] = histogramJson(d.radius);
  return j;
}

void writeDiagnostics(const std::filesystem::path& file,
                      const DiagnoseOptions& opt,
                      const std::vector<std::uint64_t>& numbers,
                      const std::vector<TrackmlDiagnostics>& perEvent,
                      const TrackmlDiagnostics& mean) {
  Json j;
  j["max_stray_hits"] = opt.maxStrayHits;
  j["mean"] = diagnosticsJson(mean);
  Json events = Json::array();
  for (std::size_t i = 0; i < numbers.size(); ++i) {
    Json e = diagnosticsJson(perEvent[i]);
    e["event"] = numbers[i];
    events.push_back(e);
  }
  j["events"] = events;
  writeTextFile(file, j.dump(1) + "\n", false);
}

void runDiagnose(const DiagnoseOptions& opt) {
  const std::vector<std::uint64_t> numbers = requireEvents(opt.events);
  if (!opt.output.empty()) {
    prepareOutputFile(opt.output, "-o");
  }
  TrackmlDiagnosticsConfig config;
  config.maxStrayHits = opt.maxStrayHits;
  std::vector<TrackmlDiagnostics> perEvent(numbers.size());
  forEachEvent(numbers.size(), opt.threads, "diagnose", [&](std::size_t i) {
    std::filesystem::path file =
        std::filesystem::path(opt.submissions) / submissionFileName(numbers[i]);
    if (!std::filesystem::exists(file)) {
      file += ".gz";
    }
    const SubmittedEvent submitted =
        readSubmittedEvent(file, opt.events, numbers[i]);
    perEvent[i] = diagnoseTrackml(
        submitted.event, std::span<const std::uint64_t>(submitted.labels),
        config);
  });
  const TrackmlDiagnostics mean =
      averageDiagnostics(std::span<const TrackmlDiagnostics>(perEvent));
  printDiagnostics(numbers, perEvent, mean);
  if (!opt.output.empty()) {
    writeDiagnostics(opt.output, opt, numbers, perEvent, mean);
  }
}

}  // namespace

void addDiagnoseCommand(CLI::App& app) {
  auto opt = std::make_shared<DiagnoseOptions>();
  CLI::App* cmd = app.add_subcommand(
      "diagnose",
      "TrackML truth diagnostics of submission files: the weight the score "
      "loses by cause (never found, split, partial, impure, hits left off, "
      "hits on other tracks) in pT, |eta| and production radius bins");
  cmd->add_option("-s,--submissions", opt->submissions,
                  "Folder with eventNNNNNNNNN-submission.csv files")
      ->required();
  cmd->add_option("-i,--input", opt->events,
                  "Folder with the events (hits, truth, particles)")
      ->required();
  cmd->add_option("-o,--output", opt->output,
                  "JSON file for the per-event and mean diagnostics "
                  "(default: print only)");
  cmd->add_option("--stray-hits", opt->maxStrayHits,
                  "A track with at most this many hits of an unmatched "
                  "particle does not count as a piece of it")
      ->capture_default_str()
      ->check(wholeNumber(0, 1000));
  addThreadsOption(*cmd, opt->threads);
  cmd->callback([opt]() { runDiagnose(*opt); });
}

}  // namespace conftrack::cli
