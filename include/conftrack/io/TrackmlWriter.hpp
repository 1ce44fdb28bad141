#pragma once

/// @file TrackmlWriter.hpp
/// Writes events in the TrackML CSV format with conftrack's extra columns
/// after the standard ones (TrackmlFormat.hpp, docs/formats.md).
///
/// Doubles are written in their shortest exact form, so reading a written
/// event gives back the same bits. The low-level writers compress when the
/// file name ends in ".gz" (with zlib level `gzipLevel`). Files appear
/// atomically (written to a temporary file, then renamed).

#include "conftrack/core/Event.hpp"
#include "conftrack/core/Hit.hpp"
#include "conftrack/core/Particle.hpp"
#include "conftrack/core/TextFile.hpp"
#include "conftrack/core/TrackmlLayerMap.hpp"

#include <filesystem>
#include <vector>

namespace conftrack {

/// How writeEvent writes.
struct WriteOptions {
  /// Write `.csv.gz` instead of `.csv`.
  bool gzip = false;
  /// zlib level, 1 (fastest) to 9 (smallest); see kDefaultGzipLevel.
  int gzipLevel = kDefaultGzipLevel;
};

/// Writes a hits file. With a detector's layer map (`layers`,
/// Detector::trackmlLayerMap), each hit's detId must name one of its layers,
/// whose TrackML ids are written; without one (nullptr) the ids are written
/// raw (TrackmlIds.hpp), which needs side = barrel. The sigma_u and
/// sigma_v columns are left out if all resolutions are 0 (unknown), so that
/// such files stay plain TrackML files. Throws InputError
/// for an id that cannot be written and for non-finite values.
void writeHits(const std::filesystem::path& file, const std::vector<Hit>& hits,
               const TrackmlLayerMap* layers,
               int gzipLevel = kDefaultGzipLevel);

/// Writes a truth file, one row per hit in hit order; `truth` must be
/// parallel to `hits` (throws std::invalid_argument otherwise).
void writeTruth(const std::filesystem::path& file, const std::vector<Hit>& hits,
                const std::vector<HitTruth>& truth,
                int gzipLevel = kDefaultGzipLevel);

/// Writes a particles file in the full TrackML format (with particle_type)
/// plus conftrack's extra columns, in the given order.
void writeParticles(const std::filesystem::path& file,
                    const std::vector<Particle>& particles,
                    int gzipLevel = kDefaultGzipLevel);

/// Writes event `event.number` into `dir` (created if needed): hits,
/// particles, and truth if the event has truth. Files of the same event left
/// from earlier writes are removed where they would be read instead of or
/// beside the new ones (the other compression variant; a truth file when the
/// event has no truth), so that readEvent returns what was written.
void writeEvent(const std::filesystem::path& dir, const Event& event,
                const TrackmlLayerMap* layers,
                const WriteOptions& options = {});

}  // namespace conftrack
