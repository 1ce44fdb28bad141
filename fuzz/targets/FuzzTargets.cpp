#include "FuzzTargets.hpp"

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/core/Hit.hpp"
#include "conftrack/core/JsonEntry.hpp"
#include "conftrack/core/TextFile.hpp"
#include "conftrack/evaluation/ShardMerge.hpp"
#include "conftrack/geometry/Detector.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/io/TrackFiles.hpp"
#include "conftrack/io/TrackmlReader.hpp"
#include "conftrack/io/TrackmlSubmission.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"
#include "conftrack/simulation/EventSimulation.hpp"
#include "conftrack/simulation/generators/HepMC3Generator.hpp"
#include "conftrack/simulation/generators/HepMCText.hpp"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace conftrack::fuzz {

namespace {

/// Runs `read`; InputError (bad input, refused cleanly) is caught.
template <typename Read>
Outcome refusedOr(Read&& read) {
  try {
    read();
    return Outcome::eAccepted;
  } catch (const InputError&) {
    return Outcome::eRefused;
  }
}

/// Accepted if one of two reader calls on the same bytes accepted them
/// (the calls differ in context: detector, event hits).
Outcome either(Outcome a, Outcome b) {
  return a == Outcome::eAccepted || b == Outcome::eAccepted ? Outcome::eAccepted
                                                            : Outcome::eRefused;
}

/// The shipped detectors, read once (the chain and generator readers
/// validate against a detector; the hits reader maps TrackML ids with one).
const Detector& shippedDetector(std::string_view name) {
  static const Detector clicdet = loadDetector("clicdet");
  static const Detector cld = loadDetector("cld");
  static const Detector trackml = loadDetector("trackml");
  if (name == "cld") {
    return cld;
  }
  if (name == "trackml") {
    return trackml;
  }
  return clicdet;
}

/// Hits of a small event for the readers of per-hit files (truth,
/// submission, track files): ids 1..8 as TrackML numbers them (the readers'
/// fast path) or scattered ids (their map path).
const std::vector<Hit>& eventHits(bool contiguousIds) {
  auto make = [](bool contiguous) {
    std::vector<Hit> hits(8);
    for (std::size_t i = 0; i < hits.size(); ++i) {
      hits[i].id = contiguous ? i + 1 : 1000 * i + 7;
      hits[i].position = {100.0 + 10.0 * static_cast<double>(i), 1.0, 2.0};
    }
    return hits;
  };
  static const std::vector<Hit> contiguous = make(true);
  static const std::vector<Hit> scattered = make(false);
  return contiguousIds ? contiguous : scattered;
}

/// Splits `data` at the first line "%%" into the texts of two files (the
/// second empty without one).
std::array<std::string, 2> splitFiles(std::string_view data) {
  constexpr std::string_view kSeparator = "\n%%\n";
  const std::size_t at = data.find(kSeparator);
  if (at == std::string_view::npos) {
    return {std::string(data), std::string()};
  }
  return {std::string(data.substr(0, at + 1)),
          std::string(data.substr(at + kSeparator.size()))};
}

Outcome trackmlHits(std::string_view data) {
  // Raw ids (no detector) and ids mapped onto the TrackML detector's layers.
  return either(
      refusedOr([&] { parseHits(std::string(data), "hits.csv", nullptr); }),
      refusedOr([&] {
        parseHits(std::string(data), "hits.csv",
                  &shippedDetector("trackml").trackmlLayerMap());
      }));
}

/// Output limit of the decompressors in the gzip target: the limit logic is
/// that of the readers (kMaxTextFileBytes, hepmc::kMaxFileBytes), at the
/// size of the plain CSV targets' largest input. The decompressors size
/// their first buffer from the gzip trailer, which mutations make random,
/// up to this limit. The hits reader itself is fuzzed by trackml_hits; at
/// 64 kB (the first choice) the fuzzer kept inputs that decompress to tens
/// of kB of CSV and the target ran at about 450 exec/s, most of it in the
/// CSV reader.
constexpr std::size_t kMaxGzipOutput = std::size_t{1} << 13;

Outcome trackmlHitsGz(std::string_view data) {
  // The decompression of readTextFile, then the hits reader on its output;
  // HepMC files have their own zlib loop (hepmc::gunzip), run on the same
  // bytes.
  Outcome hepmcGunzip =
      refusedOr([&] { hepmc::gunzip(data, "hits.csv.gz", kMaxGzipOutput); });
  return either(hepmcGunzip, refusedOr([&] {
                  std::string text = decompressIfGzip(
                      std::string(data), "hits.csv.gz", kMaxGzipOutput);
                  parseHits(std::move(text), "hits.csv.gz", nullptr);
                }));
}

Outcome trackmlTruth(std::string_view data) {
  return either(refusedOr([&] {
                  parseTruth(std::string(data), "truth.csv", eventHits(true));
                }),
                refusedOr([&] {
                  parseTruth(std::string(data), "truth.csv", eventHits(false));
                }));
}

Outcome trackmlParticles(std::string_view data) {
  return refusedOr([&] { parseParticles(std::string(data), "particles.csv"); });
}

Outcome submission(std::string_view data) {
  return either(refusedOr([&] {
                  parseSubmission(std::string(data), "submission.csv",
                                  eventHits(true));
                }),
                refusedOr([&] {
                  parseSubmission(std::string(data), "submission.csv",
                                  eventHits(false), 1000);
                }));
}

Outcome trackFiles(std::string_view data) {
  return refusedOr([&] {
    auto [tracks, trackHits] = splitFiles(data);
    parseTrackFiles(std::move(tracks), "tracks.csv", std::move(trackHits),
                    "track-hits.csv", eventHits(true));
  });
}

Outcome detectorToml(std::string_view data) {
  return refusedOr([&] { parseDetector(data, "detector.toml"); });
}

Outcome chainToml(std::string_view data) {
  // Steps name the subdetectors of a detector: read against each shipped
  // one. The TOML is parsed once (the parse is most of the cost).
  std::shared_ptr<toml::table> table;
  if (refusedOr([&] { table = ConfigTable::parse(data, "chain.toml"); }) ==
      Outcome::eRefused) {
    return Outcome::eRefused;
  }
  Outcome result = Outcome::eRefused;
  for (std::string_view detector : {"clicdet", "cld", "trackml"}) {
    result =
        either(result, refusedOr([&] {
                 readReconstructionTable(ConfigTable(*table, "chain.toml", ""),
                                         shippedDetector(detector));
               }));
  }
  return result;
}

Outcome generatorToml(std::string_view data) {
  // What `--config` / `--gen` give EventSimulation: builds the generators
  // (and the overlay) from the TOML, as `conftrack simulate` does before
  // its first event.
  return refusedOr([&] {
    EventSimulation::Config config;
    config.generatorToml = std::string(data);
    config.generatorTomlSource = "generator.toml";
    EventSimulation simulation(shippedDetector("clicdet"), config);
  });
}

Outcome hepmcText(std::string_view data) {
  return refusedOr([&] { readHepMCEvents(data, "events.hepmc"); });
}

Outcome performanceData(std::string_view data) {
  // What `conftrack merge` does with one shard's file: parse, merge (one
  // shard) and summarise (resolution and pull fits of the residuals).
  return refusedOr([&] {
    const std::string source = "performance_data.json";
    std::vector<ShardInput> shards;
    shards.push_back(
        {parsePerformanceDataJson(parseJsonObject(data, source), source),
         source});
    SavedPerformance merged = mergeShards(std::move(shards));
    summarizePerformance(merged.config, merged.data);
  });
}

constexpr std::array kTargets = {
    Target{"trackml_hits", trackmlHits},
    Target{"trackml_hits_gz", trackmlHitsGz},
    Target{"trackml_truth", trackmlTruth},
    Target{"trackml_particles", trackmlParticles},
    Target{"submission", submission},
    Target{"track_files", trackFiles},
    Target{"detector_toml", detectorToml},
    Target{"chain_toml", chainToml},
    Target{"generator_toml", generatorToml},
    // HepMC2 IO_GenEvent and HepMC3 Asciiv3 text (one reader entry point;
    // the corpus holds both formats).
    Target{"hepmc_text", hepmcText},
    // The mergeable results of a report (conftrack merge).
    Target{"performance_data", performanceData},
};

}  // namespace

std::span<const Target> targets() { return kTargets; }

const Target* findTarget(std::string_view name) {
  for (const Target& t : kTargets) {
    if (t.name == name) {
      return &t;
    }
  }
  return nullptr;
}

}  // namespace conftrack::fuzz
