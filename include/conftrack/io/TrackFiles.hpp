#pragma once

/// @file TrackFiles.hpp
/// Per-event files of reconstructed tracks (docs/formats.md "Track
/// files"): `eventNNNNNNNNN-tracks.csv`, one row per track with the LCIO
/// parameters at the IP, their covariance, the fit quality and the finder
/// information, and `eventNNNNNNNNN-track-hits.csv`, one row per hit of a
/// track (track_id, hit_id = Hit::id, outlier flag), in track order and,
/// within a track, along the path. Either may be gzip-compressed (`.gz`).
///
/// Units are the native ones: mm, rad, 1/mm, GeV. Doubles are written in
/// their shortest exact form, so a write/read round trip is exact. Reading
/// is strict: every problem is a one-line InputError "file:line: problem".

#include "conftrack/core/Hit.hpp"
#include "conftrack/core/TextFile.hpp"
#include "conftrack/core/Track.hpp"
#include "conftrack/io/TrackmlWriter.hpp"

#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace conftrack {

/// Column names of the track files.
namespace trackfiles {
inline constexpr std::string_view kTrackId = "track_id";
inline constexpr std::string_view kD0 = "d0";
inline constexpr std::string_view kPhi0 = "phi0";
inline constexpr std::string_view kOmega = "omega";
inline constexpr std::string_view kZ0 = "z0";
inline constexpr std::string_view kTanLambda = "tan_lambda";
/// The 15 lower-triangle covariance elements in LCIO order: (row, column)
/// = (0,0), (1,0), (1,1), (2,0), ... with rows/columns eD0 ... eTanLambda.
inline constexpr std::array<std::string_view, 15> kCovariance = {
    "cov_d0_d0",
    "cov_phi0_d0",
    "cov_phi0_phi0",
    "cov_omega_d0",
    "cov_omega_phi0",
    "cov_omega_omega",
    "cov_z0_d0",
    "cov_z0_phi0",
    "cov_z0_omega",
    "cov_z0_z0",
    "cov_tan_lambda_d0",
    "cov_tan_lambda_phi0",
    "cov_tan_lambda_omega",
    "cov_tan_lambda_z0",
    "cov_tan_lambda_tan_lambda"};
inline constexpr std::string_view kChi2 = "chi2";
inline constexpr std::string_view kNdf = "ndf";
inline constexpr std::string_view kNHits = "n_hits";
inline constexpr std::string_view kNOutliers = "n_outliers";
inline constexpr std::string_view kStep = "step";
inline constexpr std::string_view kPtEstimate = "pt_estimate";
inline constexpr std::string_view kFitted = "fitted";
/// The perigee's reference point, the beam line at z = 0 (TrackState::
/// reference of Track::atIp): x and y [mm]. Optional when reading (files
/// written before them: the origin).
inline constexpr std::string_view kRefX = "ref_x";
inline constexpr std::string_view kRefY = "ref_y";
inline constexpr std::string_view kHitId = "hit_id";
inline constexpr std::string_view kOutlier = "outlier";
}  // namespace trackfiles

/// The two files of an event's tracks.
enum class TrackFileKind : std::uint8_t { eTracks, eTrackHits };

/// File name, e.g. "event000001001-tracks.csv.gz" (event number zero-padded
/// to 9 digits, as eventFileName).
std::string trackFileName(std::uint64_t eventNumber, TrackFileKind kind,
                          bool gzip);

/// Writes the tracks table: one row per track, track_id = its position in
/// `tracks`, the parameters and covariance of Track::atIp. Compressed if
/// the name ends in ".gz". Throws InputError for non-finite values.
void writeTrackTable(const std::filesystem::path& file,
                     const std::vector<Track>& tracks,
                     int gzipLevel = kDefaultGzipLevel);

/// Writes the track-hits table: for each track (track_id as above) its
/// hits in order with their Hit::id (the tracks' hit indices point into
/// `hits`) and outlier flag. Throws std::out_of_range for a hit index
/// outside `hits`, std::invalid_argument for outlier flags that are
/// neither empty nor parallel to the hits.
void writeTrackHitTable(const std::filesystem::path& file,
                        std::span<const Hit> hits,
                        const std::vector<Track>& tracks,
                        int gzipLevel = kDefaultGzipLevel);

/// Writes both files of event `eventNumber` into `dir` (created if
/// needed), with `.gz` if options.gzip, removing the other compression
/// variant of each so that readTracks returns what was written.
void writeTracks(const std::filesystem::path& dir, std::uint64_t eventNumber,
                 std::span<const Hit> hits, const std::vector<Track>& tracks,
                 const WriteOptions& options = {});

/// Reads a tracks table and its track-hits table; hit ids are mapped to
/// indices into `hits` (the event's hits). Returns the tracks in the order
/// of the tracks table with hits, outlier flags, atIp (reference origin),
/// chi2, ndf, findingStep, ptEstimate and fitted filled.
///
/// Errors: missing columns, bad numbers, duplicate track ids, n_outliers >
/// n_hits, flags other than 0/1, negative variances, a negative
/// pt_estimate, omega = 0 on a fitted track; track-hits rows for
/// unknown track ids or hit ids not in `hits`, a hit twice on one track;
/// a track whose n_hits or n_outliers disagree with its track-hits rows.
std::vector<Track> readTrackFiles(const std::filesystem::path& tracksFile,
                                  const std::filesystem::path& trackHitsFile,
                                  std::span<const Hit> hits);

/// readTrackFiles on the two files' texts already in memory (plain, see
/// decompressIfGzip); the sources name them in error messages.
std::vector<Track> parseTrackFiles(std::string tracksText,
                                   const std::string& tracksSource,
                                   std::string trackHitsText,
                                   const std::string& trackHitsSource,
                                   std::span<const Hit> hits);

/// Reads the track files of event `eventNumber` from `dir` (plain or .gz;
/// both present or none is an error).
std::vector<Track> readTracks(const std::filesystem::path& dir,
                              std::uint64_t eventNumber,
                              std::span<const Hit> hits);

}  // namespace conftrack
