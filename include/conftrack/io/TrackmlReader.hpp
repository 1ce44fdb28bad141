#pragma once

/// @file TrackmlReader.hpp
/// Reads events in the TrackML CSV format with conftrack's extra columns
/// (TrackmlFormat.hpp, docs/formats.md).
///
/// Files may be plain or gzip-compressed (detected by content). Columns are
/// found by header name; unknown columns are ignored. Any problem throws a
/// one-line InputError "file:line: problem".

#include "conftrack/core/Event.hpp"
#include "conftrack/core/Hit.hpp"
#include "conftrack/core/Particle.hpp"
#include "conftrack/core/TrackmlLayerMap.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace conftrack {

/// What readEvent reads besides the hits.
struct ReadOptions {
  /// Read the truth file if it exists.
  bool truth = true;
  /// Read the particles file if it exists.
  bool particles = true;
};

/// Reads a hits file, in file order.
///
/// With a detector's layer map (`layers`, Detector::trackmlLayerMap),
/// (volume_id, layer_id) must name one of its layers and module_id must be
/// within the layer's segmentation; detId, the local axes
/// (TrackmlLayer::localAxes) and, where the sigma_u/sigma_v columns are
/// absent, the resolutions come from the layer. Without one (nullptr) the
/// ids are taken raw (TrackmlIds.hpp), the axes keep their defaults and
/// missing resolutions are 0.
///
/// Errors: missing columns, bad numbers, NaN/inf, negative resolutions,
/// unknown layers, duplicate hit ids, and hits within 1 um of the beam line
/// (no layer is there; conformal coordinates are undefined). With a layer
/// map also hits outside its envelope (r <= envelopeR, |z| <=
/// envelopeZ) and hits more than 25 mm away from the surface of the layer
/// they name (real modules are staggered around the nominal layer by a few
/// mm, the CLICdet vertex-endcap spiral petals by up to 20.7 mm).
std::vector<Hit> readHits(const std::filesystem::path& file,
                          const TrackmlLayerMap* layers);

/// Reads a truth file; returns the truth parallel to `hits`.
///
/// The file must have exactly one row per hit, in any order: rows for an
/// unknown hit id, duplicate rows and hits without a row are errors, and so
/// are negative weights (the TrackML score sums them).
std::vector<HitTruth> readTruth(const std::filesystem::path& file,
                                const std::vector<Hit>& hits);

/// Reads a particles file, in the full TrackML format or the Kaggle format
/// without particle_type; returns the particles sorted by id. Particle id 0
/// (reserved for noise) and duplicate ids are errors.
std::vector<Particle> readParticles(const std::filesystem::path& file);

/// readHits, readTruth and readParticles on text already in memory (plain,
/// see decompressIfGzip); `source` names it in error messages.
std::vector<Hit> parseHits(std::string text, const std::string& source,
                           const TrackmlLayerMap* layers);
std::vector<HitTruth> parseTruth(std::string text, const std::string& source,
                                 const std::vector<Hit>& hits);
std::vector<Particle> parseParticles(std::string text,
                                     const std::string& source);

/// Reads event `eventNumber` from `dir`: the hits file (required) and, if
/// they exist and `options` asks for them, the truth and particles files.
/// See readHits for the role of `layers`.
Event readEvent(const std::filesystem::path& dir, std::uint64_t eventNumber,
                const TrackmlLayerMap* layers, const ReadOptions& options = {});

}  // namespace conftrack
