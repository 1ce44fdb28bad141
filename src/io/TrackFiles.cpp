#include "conftrack/io/TrackFiles.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/TextFile.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/io/CsvReader.hpp"
#include "conftrack/io/CsvWriter.hpp"
#include "conftrack/io/EventFiles.hpp"

#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

namespace conftrack {

namespace {

namespace c = trackfiles;

/// (row, column) of the i-th lower-triangle covariance element.
constexpr std::array<std::pair<int, int>, 15> kCovarianceIndex = {{{0, 0},
                                                                   {1, 0},
                                                                   {1, 1},
                                                                   {2, 0},
                                                                   {2, 1},
                                                                   {2, 2},
                                                                   {3, 0},
                                                                   {3, 1},
                                                                   {3, 2},
                                                                   {3, 3},
                                                                   {4, 0},
                                                                   {4, 1},
                                                                   {4, 2},
                                                                   {4, 3},
                                                                   {4, 4}}};

std::vector<std::string_view> trackColumns() {
  std::vector<std::string_view> columns = {c::kTrackId, c::kD0, c::kPhi0,
                                           c::kOmega,   c::kZ0, c::kTanLambda};
  columns.insert(columns.end(), c::kCovariance.begin(), c::kCovariance.end());
  columns.insert(columns.end(),
                 {c::kChi2, c::kNdf, c::kNHits, c::kNOutliers, c::kStep,
                  c::kPtEstimate, c::kFitted, c::kRefX, c::kRefY});
  return columns;
}

/// The plain or the .gz variant of a file, whichever exists.
std::filesystem::path locate(const std::filesystem::path& dir,
                             std::uint64_t eventNumber, TrackFileKind kind) {
  const std::filesystem::path plain =
      dir / trackFileName(eventNumber, kind, false);
  const std::filesystem::path gz = dir / trackFileName(eventNumber, kind, true);
  std::error_code ec;
  const bool hasPlain = std::filesystem::exists(plain, ec);
  const bool hasGz = std::filesystem::exists(gz, ec);
  if (hasPlain && hasGz) {
    throw InputError(location(plain.string()),
                     "both " + plain.filename().string() + " and " +
                         gz.filename().string() + " exist: remove one of them");
  }
  if (!hasPlain && !hasGz) {
    throw MissingFileError(location(plain.string()),
                           "no such file (nor with .gz)");
  }
  return hasPlain ? plain : gz;
}

/// A small integer field of at most `max`; `what` names the values.
std::uint8_t smallField(const CsvReader& csv, std::size_t column,
                        std::uint8_t max, const char* what) {
  const auto value = csv.getInteger<std::uint8_t>(column);
  if (value > max) {
    csv.failField(column, what);
  }
  return value;
}

/// A track-hits `outlier` field: a HitUse.
std::uint8_t hitUse(const CsvReader& csv, std::size_t column) {
  return smallField(csv, column, kTurnHit, "is not 0, 1 or 2");
}

/// A 0/1 field as a bool.
bool flag(const CsvReader& csv, std::size_t column) {
  return smallField(csv, column, 1, "is not 0 or 1") == 1;
}

/// Hit id -> hit index.
std::unordered_map<std::uint64_t, HitIndex> hitIndexById(
    std::span<const Hit> hits) {
  std::unordered_map<std::uint64_t, HitIndex> map;
  map.reserve(hits.size());
  for (std::size_t i = 0; i < hits.size(); ++i) {
    map.emplace(hits[i].id, static_cast<HitIndex>(i));
  }
  return map;
}

}  // namespace

std::string trackFileName(std::uint64_t eventNumber, TrackFileKind kind,
                          bool gzip) {
  std::string name = eventFileStem(eventNumber);
  name += kind == TrackFileKind::eTracks ? "-tracks.csv" : "-track-hits.csv";
  if (gzip) {
    name += ".gz";
  }
  return name;
}

void writeTrackTable(const std::filesystem::path& file,
                     const std::vector<Track>& tracks, int gzipLevel) {
  CsvWriter csv(file.string(), trackColumns(), tracks.size());
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    const Track& t = tracks[i];
    const TrackVector& a = t.atIp.parameters;
    csv.add(static_cast<std::uint64_t>(i));
    csv.add(a[eD0] / units::mm);
    csv.add(a[ePhi0]);
    csv.add(a[eOmega] * units::mm);
    csv.add(a[eZ0] / units::mm);
    csv.add(a[eTanLambda]);
    // Native units throughout (mm, rad, 1/mm), so no conversion.
    for (const auto& [row, column] : kCovarianceIndex) {
      csv.add(t.atIp.covariance(row, column));
    }
    csv.add(t.chi2);
    csv.add(t.ndf);
    csv.add(static_cast<std::uint32_t>(t.hits.size()));
    csv.add(t.numOutliers());
    csv.add(t.findingStep);
    csv.add(t.ptEstimate / units::GeV);
    csv.add(t.fitted ? 1 : 0);
    csv.add(t.atIp.reference.x() / units::mm);
    csv.add(t.atIp.reference.y() / units::mm);
    csv.endRow();
  }
  csv.write(file, hasGzipExtension(file), gzipLevel);
}

void writeTrackHitTable(const std::filesystem::path& file,
                        std::span<const Hit> hits,
                        const std::vector<Track>& tracks, int gzipLevel) {
  std::size_t rows = 0;
  for (const Track& t : tracks) {
    rows += t.hits.size();
  }
  CsvWriter csv(file.string(), {c::kTrackId, c::kHitId, c::kOutlier}, rows);
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    const Track& t = tracks[i];
    if (!t.outlier.empty() && t.outlier.size() != t.hits.size()) {
      throw std::invalid_argument(
          "writeTrackHitTable: outlier flags not parallel to the hits of "
          "track " +
          std::to_string(i));
    }
    for (std::size_t k = 0; k < t.hits.size(); ++k) {
      if (t.hits[k] >= hits.size()) {
        throw std::out_of_range("writeTrackHitTable: hit index " +
                                std::to_string(t.hits[k]) + " of track " +
                                std::to_string(i) + " out of range");
      }
      csv.add(static_cast<std::uint64_t>(i));
      csv.add(hits[t.hits[k]].id);
      const std::uint8_t use =
          t.outlier.empty() ? std::uint8_t{kFittedHit} : t.outlier[k];
      if (use > kTurnHit) {
        throw std::invalid_argument("writeTrackHitTable: hit use " +
                                    std::to_string(use) + " of track " +
                                    std::to_string(i) + " is not a HitUse");
      }
      csv.add(static_cast<std::uint64_t>(use));
      csv.endRow();
    }
  }
  csv.write(file, hasGzipExtension(file), gzipLevel);
}

void writeTracks(const std::filesystem::path& dir, std::uint64_t eventNumber,
                 std::span<const Hit> hits, const std::vector<Track>& tracks,
                 const WriteOptions& options) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    throw InputError(location(dir.string()),
                     "cannot create folder: " + ec.message());
  }
  const bool gz = options.gzip;
  auto path = [&](TrackFileKind kind, bool gzip) {
    return dir / trackFileName(eventNumber, kind, gzip);
  };
  writeTrackTable(path(TrackFileKind::eTracks, gz), tracks, options.gzipLevel);
  removeIfExists(path(TrackFileKind::eTracks, !gz));
  writeTrackHitTable(path(TrackFileKind::eTrackHits, gz), hits, tracks,
                     options.gzipLevel);
  removeIfExists(path(TrackFileKind::eTrackHits, !gz));
}

std::vector<Track> parseTrackFiles(std::string tracksText,
                                   const std::string& tracksSource,
                                   std::string trackHitsText,
                                   const std::string& trackHitsSource,
                                   std::span<const Hit> hits) {
  std::vector<Track> tracks;
  // Per track: its id, declared n_hits and n_outliers, and its line.
  struct Declared {
    std::uint32_t hits = 0;
    std::uint32_t outliers = 0;
    std::size_t line = 0;
  };
  std::vector<Declared> declared;
  std::unordered_map<std::uint64_t, std::size_t> indexById;
  {
    CsvReader csv(std::move(tracksText), tracksSource);
    std::vector<std::size_t> col;
    for (std::string_view name : trackColumns()) {
      if (name == c::kRefX || name == c::kRefY) {
        continue;  // optional, below
      }
      col.push_back(csv.requireColumn(name));
    }
    // The perigee's reference: absent in files written before it (the
    // origin then); one without the other is an error.
    const auto cRefX = csv.findColumn(c::kRefX);
    const auto cRefY = csv.findColumn(c::kRefY);
    if (cRefX.has_value() != cRefY.has_value()) {
      csv.fail("column '" + std::string(cRefX ? c::kRefX : c::kRefY) +
               "' without '" + std::string(cRefX ? c::kRefY : c::kRefX) + "'");
    }
    const std::size_t cId = col[0];
    const std::size_t cCov = 6;
    const std::size_t cRest = cCov + c::kCovariance.size();
    tracks.reserve(csv.estimateRows());
    while (csv.next()) {
      const auto id = csv.getInteger<std::uint64_t>(cId);
      if (!indexById.emplace(id, tracks.size()).second) {
        csv.fail("duplicate track_id " + std::to_string(id));
      }
      Track& t = tracks.emplace_back();
      TrackVector& a = t.atIp.parameters;
      a[eD0] = csv.getDouble(col[1]) * units::mm;
      a[ePhi0] = csv.getDouble(col[2]);
      a[eOmega] = csv.getDouble(col[3]) / units::mm;
      a[eZ0] = csv.getDouble(col[4]) * units::mm;
      a[eTanLambda] = csv.getDouble(col[5]);
      for (std::size_t k = 0; k < kCovarianceIndex.size(); ++k) {
        const auto [row, column] = kCovarianceIndex[k];
        const double value = csv.getDouble(col[cCov + k]);
        if (row == column && value < 0.0) {
          csv.failField(col[cCov + k], "is negative (a variance)");
        }
        t.atIp.covariance(row, column) = value;
        t.atIp.covariance(column, row) = value;
      }
      t.chi2 = csv.getDouble(col[cRest]);
      if (t.chi2 < 0.0) {
        csv.failField(col[cRest], "is negative");
      }
      t.ndf = csv.getInteger<int>(col[cRest + 1]);
      Declared& d = declared.emplace_back();
      d.hits = csv.getInteger<std::uint32_t>(col[cRest + 2]);
      d.outliers = csv.getInteger<std::uint32_t>(col[cRest + 3]);
      d.line = csv.line();
      if (d.outliers > d.hits) {
        csv.failField(col[cRest + 3],
                      "exceeds n_hits " + std::to_string(d.hits));
      }
      t.findingStep = csv.getInteger<std::uint16_t>(col[cRest + 4]);
      t.ptEstimate = csv.getDouble(col[cRest + 5]) * units::GeV;
      if (t.ptEstimate < 0.0) {
        csv.failField(col[cRest + 5], "is negative");
      }
      t.fitted = flag(csv, col[cRest + 6]);
      if (cRefX) {
        t.atIp.reference = Vector3(csv.getDouble(*cRefX) * units::mm,
                                   csv.getDouble(*cRefY) * units::mm, 0.0);
      }
      // Unfitted tracks carry zeros; a fitted one in a magnetic field is
      // curved. Omega = 0 would be a straight track of infinite pT, which
      // the evaluation cannot place in any pT bin.
      if (t.fitted && a[eOmega] == 0.0) {
        csv.failField(col[3],
                      "is 0 on a fitted track (a straight track, infinite "
                      "pT: not a fit in a magnetic field)");
      }
      // No reserve(d.hits): n_hits is not trusted before the track-hits
      // rows confirm it (n_hits = 4294967295 asked for 16 GB; fuzzing).
    }
  }
  {
    CsvReader csv(std::move(trackHitsText), trackHitsSource);
    const std::size_t cTrack = csv.requireColumn(c::kTrackId);
    const std::size_t cHit = csv.requireColumn(c::kHitId);
    const auto cOutlier = csv.findColumn(c::kOutlier);
    const auto hitIndex = hitIndexById(hits);
    // Hits already on each track, to reject duplicates.
    std::unordered_set<std::uint64_t> seen;
    seen.reserve(csv.estimateRows());
    while (csv.next()) {
      const auto trackId = csv.getInteger<std::uint64_t>(cTrack);
      const auto track = indexById.find(trackId);
      if (track == indexById.end()) {
        csv.fail("track_id " + std::to_string(trackId) +
                 " is not in the tracks file");
      }
      const auto hitId = csv.getInteger<std::uint64_t>(cHit);
      const auto hit = hitIndex.find(hitId);
      if (hit == hitIndex.end()) {
        csv.fail("hit_id " + std::to_string(hitId) +
                 " is not a hit of the event");
      }
      // (track index, hit index) packed into one key.
      const std::uint64_t key =
          (static_cast<std::uint64_t>(track->second) << 32) | hit->second;
      if (!seen.insert(key).second) {
        csv.fail("hit_id " + std::to_string(hitId) +
                 " appears twice on track " + std::to_string(trackId));
      }
      Track& t = tracks[track->second];
      t.hits.push_back(hit->second);
      t.outlier.push_back(cOutlier ? hitUse(csv, *cOutlier)
                                   : std::uint8_t{kFittedHit});
    }
  }
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    const Declared& d = declared[i];
    if (tracks[i].hits.size() != d.hits) {
      throw InputError(
          location(tracksSource, d.line),
          "n_hits is " + std::to_string(d.hits) + " but " +
              std::filesystem::path(trackHitsSource).filename().string() +
              " has " + std::to_string(tracks[i].hits.size()) +
              " rows for this track");
    }
    if (tracks[i].numOutliers() != d.outliers) {
      throw InputError(
          location(tracksSource, d.line),
          "n_outliers is " + std::to_string(d.outliers) + " but " +
              std::filesystem::path(trackHitsSource).filename().string() +
              " flags " + std::to_string(tracks[i].numOutliers()) +
              " hits of this track as outliers");
    }
  }
  return tracks;
}

std::vector<Track> readTrackFiles(const std::filesystem::path& tracksFile,
                                  const std::filesystem::path& trackHitsFile,
                                  std::span<const Hit> hits) {
  return parseTrackFiles(readTextFile(tracksFile), tracksFile.string(),
                         readTextFile(trackHitsFile), trackHitsFile.string(),
                         hits);
}

std::vector<Track> readTracks(const std::filesystem::path& dir,
                              std::uint64_t eventNumber,
                              std::span<const Hit> hits) {
  const std::filesystem::path tracks =
      locate(dir, eventNumber, TrackFileKind::eTracks);
  const std::filesystem::path trackHits =
      locate(dir, eventNumber, TrackFileKind::eTrackHits);
  return readTrackFiles(tracks, trackHits, hits);
}

}  // namespace conftrack
