/// @file TrackFilesTests.cpp
/// Track files: exact write/read round trips (plain and gzip) and a
/// one-line "file:line: problem" InputError for every kind of bad input.

#include "conftrack/core/Error.hpp"
#include "conftrack/io/TrackFiles.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <unistd.h>

#include "TempDir.hpp"

namespace conftrack {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::StartsWith;

/// Hits with non-contiguous ids (so that ids and indices differ).
std::vector<Hit> makeHits() {
  std::vector<Hit> hits(40);
  for (std::size_t i = 0; i < hits.size(); ++i) {
    hits[i].id = 7 * i + 3;
  }
  return hits;
}

/// Tracks with awkward numbers: full-precision doubles, a random positive
/// definite covariance, outliers, a further-turn hit, an unfitted track
/// and an empty one.
std::vector<Track> makeTracks() {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  std::vector<Track> tracks(4);
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    Track& t = tracks[i];
    for (int k = 0; k < 5; ++k) {
      t.atIp.parameters[k] = normal(rng) * std::pow(10.0, -k);
    }
    TrackCovariance a;
    for (int r = 0; r < 5; ++r) {
      for (int c = 0; c < 5; ++c) {
        a(r, c) = normal(rng) * 1e-3;
      }
    }
    // Exactly symmetric (only the lower triangle is written).
    t.atIp.covariance = a * a.transpose();
    t.atIp.covariance =
        t.atIp.covariance.triangularView<Eigen::Lower>().toDenseMatrix();
    t.atIp.covariance.triangularView<Eigen::StrictlyUpper>() =
        t.atIp.covariance.transpose();
    t.chi2 = 12.345678901234567 * static_cast<double>(i + 1);
    t.ndf = static_cast<int>(2 * i + 1);
    t.findingStep = static_cast<std::uint16_t>(i);
    t.ptEstimate = 0.1 + static_cast<double>(i) / 3.0;
    t.fitted = i != 2;
    // Perigees about a beam line off the axis (full-precision doubles).
    if (t.fitted) {
      t.atIp.reference = Vector3(normal(rng), normal(rng), 0.0);
    }
    for (HitIndex h = 0; h < 3 + i; ++h) {
      t.hits.push_back(static_cast<HitIndex>(37 - 5 * i - h));
      // Track 1: an outlier; track 2: a looper's further-turn hit last.
      t.outlier.push_back(h == 1 && i == 1       ? kOutlierHit
                          : h == 2 + i && i == 2 ? kTurnHit
                                                 : kFittedHit);
    }
  }
  tracks[3].hits.clear();
  tracks[3].outlier.clear();
  return tracks;
}

class TrackFiles : public ::testing::Test {
 protected:
  fs::path write(const std::string& name, const std::string& text) {
    return test::writeText(m_dir / name, text);
  }

  /// Reads the two tables and returns the error, expected at `file:line`
  /// (line 0: no line) as a one-line message.
  std::string errorOf(const std::string& tracksText,
                      const std::string& hitsText, const std::string& where,
                      std::size_t line) {
    const fs::path tracks = write("t-tracks.csv", tracksText);
    const fs::path trackHits = write("t-track-hits.csv", hitsText);
    const auto hits = makeHits();
    const fs::path file = where == "tracks" ? tracks : trackHits;
    try {
      readTrackFiles(tracks, trackHits, hits);
    } catch (const InputError& e) {
      std::string message = e.what();
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      EXPECT_THAT(message, StartsWith(location(file.string(), line) + ": "));
      return message;
    }
    ADD_FAILURE() << "no InputError thrown";
    return "";
  }

  test::TempDir m_tmp;
  const fs::path& m_dir = m_tmp.path();
};

void expectSame(const std::vector<Track>& read,
                const std::vector<Track>& written) {
  ASSERT_EQ(read.size(), written.size());
  for (std::size_t i = 0; i < read.size(); ++i) {
    const Track& a = read[i];
    const Track& b = written[i];
    EXPECT_EQ(a.atIp.parameters, b.atIp.parameters) << i;
    EXPECT_EQ(a.atIp.covariance, b.atIp.covariance) << i;
    EXPECT_EQ(a.atIp.reference, b.atIp.reference) << i;
    EXPECT_EQ(a.chi2, b.chi2);
    EXPECT_EQ(a.ndf, b.ndf);
    EXPECT_EQ(a.hits, b.hits);
    EXPECT_EQ(a.outlier, b.outlier);
    EXPECT_EQ(a.findingStep, b.findingStep);
    EXPECT_EQ(a.ptEstimate, b.ptEstimate);
    EXPECT_EQ(a.fitted, b.fitted);
  }
}

TEST_F(TrackFiles, FileNames) {
  EXPECT_EQ(trackFileName(1001, TrackFileKind::eTracks, false),
            "event000001001-tracks.csv");
  EXPECT_EQ(trackFileName(7, TrackFileKind::eTrackHits, true),
            "event000000007-track-hits.csv.gz");
}

TEST_F(TrackFiles, RoundTripIsExact) {
  const auto hits = makeHits();
  const auto tracks = makeTracks();
  for (bool gzip : {false, true}) {
    WriteOptions options;
    options.gzip = gzip;
    writeTracks(m_dir, 42, hits, tracks, options);
    EXPECT_TRUE(
        fs::exists(m_dir / trackFileName(42, TrackFileKind::eTracks, gzip)));
    // The other variant is gone, so the read is unambiguous.
    EXPECT_FALSE(fs::exists(
        m_dir / trackFileName(42, TrackFileKind::eTrackHits, !gzip)));
    expectSame(readTracks(m_dir, 42, hits), tracks);
  }
}

TEST_F(TrackFiles, HeaderAndHitIds) {
  const auto hits = makeHits();
  std::vector<Track> tracks(1);
  tracks[0].hits = {2, 0, 1};
  tracks[0].outlier = {kFittedHit, kOutlierHit, kTurnHit};
  writeTracks(m_dir, 1, hits, tracks);
  std::ifstream in(m_dir / trackFileName(1, TrackFileKind::eTrackHits, false));
  std::string text((std::istreambuf_iterator<char>(in)),
                   std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "track_id,hit_id,outlier\n0,17,0\n0,3,1\n0,10,2\n");
  std::ifstream tin(m_dir / trackFileName(1, TrackFileKind::eTracks, false));
  std::string header;
  std::getline(tin, header);
  EXPECT_THAT(header,
              StartsWith("track_id,d0,phi0,omega,z0,tan_lambda,cov_d0_d0,"
                         "cov_phi0_d0,cov_phi0_phi0,cov_omega_d0,"));
  EXPECT_THAT(header, HasSubstr("cov_tan_lambda_tan_lambda,chi2,ndf,n_hits,"
                                "n_outliers,step,pt_estimate,fitted,ref_x,"
                                "ref_y"));
}

TEST_F(TrackFiles, WriterRejectsBadTracks) {
  const auto hits = makeHits();
  std::vector<Track> tracks(1);
  tracks[0].hits = {99};
  EXPECT_THROW(writeTracks(m_dir, 1, hits, tracks), std::out_of_range);
  tracks[0].hits = {1, 2};
  tracks[0].outlier = {0};
  EXPECT_THROW(writeTracks(m_dir, 1, hits, tracks), std::invalid_argument);
  tracks[0].outlier = {0, 0};
  tracks[0].chi2 = std::nan("");
  EXPECT_THROW(writeTracks(m_dir, 1, hits, tracks), InputError);
}

// ------------------------------------------------------------------ errors

const std::string kHeader =
    "track_id,d0,phi0,omega,z0,tan_lambda,cov_d0_d0,cov_phi0_d0,"
    "cov_phi0_phi0,cov_omega_d0,cov_omega_phi0,cov_omega_omega,cov_z0_d0,"
    "cov_z0_phi0,cov_z0_omega,cov_z0_z0,cov_tan_lambda_d0,"
    "cov_tan_lambda_phi0,cov_tan_lambda_omega,cov_tan_lambda_z0,"
    "cov_tan_lambda_tan_lambda,chi2,ndf,n_hits,n_outliers,step,pt_estimate,"
    "fitted\n";

/// A valid row: track `id` with 3 hits, `outliers` of them outliers.
std::string row(int id, const std::string& nHits = "3",
                const std::string& nOutliers = "0",
                const std::string& fitted = "1",
                const std::string& covD0 = "1e-6") {
  return std::to_string(id) + ",0.01,1.2,0.001,-0.5,0.3," + covD0 +
         ",0,1e-8,0,0,1e-12,0,0,0,1e-4,0,0,0,0,1e-6,2.5,1," + nHits + "," +
         nOutliers + ",0,1.5," + fitted + "\n";
}

const std::string kHitsHeader = "track_id,hit_id,outlier\n";
/// Hit rows of track `id` (hit ids 3, 10, 17 exist).
std::string hitRows(int id) {
  const std::string t = std::to_string(id);
  return t + ",3,0\n" + t + ",10,0\n" + t + ",17,0\n";
}

TEST_F(TrackFiles, ValidTablesRead) {
  const auto hits = makeHits();
  const fs::path tracks = write("t-tracks.csv", kHeader + row(5) + row(2));
  const fs::path trackHits =
      write("t-track-hits.csv", kHitsHeader + hitRows(2) + hitRows(5));
  const auto read = readTrackFiles(tracks, trackHits, hits);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].hits, (std::vector<HitIndex>{0, 1, 2}));
  EXPECT_DOUBLE_EQ(read[0].atIp.covariance(eTanLambda, eTanLambda), 1e-6);
  EXPECT_DOUBLE_EQ(read[0].atIp.parameters[eOmega], 0.001);
  // Files without the reference columns (written before them): the
  // perigee about the origin.
  EXPECT_EQ(read[0].atIp.reference, Vector3::Zero());
}

TEST_F(TrackFiles, PerigeeReferenceColumns) {
  const auto hits = makeHits();
  std::string header = kHeader;
  header.insert(header.size() - 1, ",ref_x,ref_y");
  std::string line = row(5);
  line.insert(line.size() - 1, ",0.7,-0.5");
  const fs::path tracks = write("t-tracks.csv", header + line);
  const fs::path trackHits =
      write("t-track-hits.csv", kHitsHeader + hitRows(5));
  const auto read = readTrackFiles(tracks, trackHits, hits);
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(read[0].atIp.reference, Vector3(0.7, -0.5, 0.0));
  // One without the other, and a reference that is not a number.
  std::string half = kHeader;
  half.insert(half.size() - 1, ",ref_y");
  std::string halfRow = row(5);
  halfRow.insert(halfRow.size() - 1, ",-0.5");
  EXPECT_THAT(errorOf(half + halfRow, kHitsHeader + hitRows(5), "tracks", 1),
              HasSubstr("column 'ref_y' without 'ref_x'"));
  std::string nan = row(5);
  nan.insert(nan.size() - 1, ",nan,-0.5");
  EXPECT_THAT(errorOf(header + nan, kHitsHeader + hitRows(5), "tracks", 2),
              HasSubstr("ref_x"));
}

TEST_F(TrackFiles, MissingColumn) {
  std::string header = kHeader;
  header.replace(header.find(",chi2"), 5, "");
  EXPECT_THAT(errorOf(header, kHitsHeader, "tracks", 1),
              HasSubstr("missing required column 'chi2'"));
  EXPECT_THAT(
      errorOf(kHeader + row(0), "track_id,outlier\n0,0\n", "track-hits", 1),
      HasSubstr("missing required column 'hit_id'"));
}

TEST_F(TrackFiles, BadNumbers) {
  std::string bad = row(0);
  bad.replace(bad.find("0.01"), 4, "abc");
  EXPECT_THAT(errorOf(kHeader + bad, kHitsHeader + hitRows(0), "tracks", 2),
              HasSubstr("column 'd0': 'abc' is not a number"));
  EXPECT_THAT(errorOf(kHeader + row(0, "-3"), kHitsHeader, "tracks", 2),
              HasSubstr("column 'n_hits': '-3' is not an integer"));
  EXPECT_THAT(
      errorOf(kHeader + row(0, "3", "0", "1", "nan"), kHitsHeader, "tracks", 2),
      HasSubstr("is not finite"));
}

TEST_F(TrackFiles, InconsistentTrackRows) {
  EXPECT_THAT(errorOf(kHeader + row(4) + row(4), kHitsHeader, "tracks", 3),
              HasSubstr("duplicate track_id 4"));
  EXPECT_THAT(errorOf(kHeader + row(0, "3", "4"), kHitsHeader, "tracks", 2),
              HasSubstr("column 'n_outliers': '4' exceeds n_hits 3"));
  EXPECT_THAT(
      errorOf(kHeader + row(0, "3", "0", "2"), kHitsHeader, "tracks", 2),
      HasSubstr("column 'fitted': '2' is not 0 or 1"));
  EXPECT_THAT(errorOf(kHeader + row(0, "3", "0", "1", "-1e-6"), kHitsHeader,
                      "tracks", 2),
              HasSubstr("column 'cov_d0_d0': '-1e-6' is negative"));
}

TEST_F(TrackFiles, FittedStraightTrackAndNegativePtEstimate) {
  // Omega = 0 on a fitted track: infinite pT, no place in the evaluation's
  // pT bins (it wrote NaN rates before it was refused).
  std::string straight = row(0);
  straight.replace(straight.find(",0.001,"), 7, ",0,");
  EXPECT_THAT(
      errorOf(kHeader + straight, kHitsHeader + hitRows(0), "tracks", 2),
      HasSubstr("column 'omega': '0' is 0 on a fitted track"));
  // Unfitted tracks carry zero parameters: valid.
  std::string unfitted = row(0, "3", "0", "0");
  unfitted.replace(unfitted.find(",0.001,"), 7, ",0,");
  const auto hits = makeHits();
  const auto read =
      readTrackFiles(write("u-tracks.csv", kHeader + unfitted),
                     write("u-track-hits.csv", kHitsHeader + hitRows(0)), hits);
  ASSERT_EQ(read.size(), 1u);
  EXPECT_FALSE(read[0].fitted);
  std::string negative = row(0);
  negative.replace(negative.find(",1.5,"), 5, ",-1.5,");
  EXPECT_THAT(
      errorOf(kHeader + negative, kHitsHeader + hitRows(0), "tracks", 2),
      HasSubstr("column 'pt_estimate': '-1.5' is negative"));
}

TEST_F(TrackFiles, BadTrackHitRows) {
  EXPECT_THAT(
      errorOf(kHeader + row(0), kHitsHeader + "1,3,0\n", "track-hits", 2),
      HasSubstr("track_id 1 is not in the tracks file"));
  EXPECT_THAT(
      errorOf(kHeader + row(0), kHitsHeader + "0,4,0\n", "track-hits", 2),
      HasSubstr("hit_id 4 is not a hit of the event"));
  EXPECT_THAT(errorOf(kHeader + row(0), kHitsHeader + "0,3,0\n0,3,0\n",
                      "track-hits", 3),
              HasSubstr("hit_id 3 appears twice on track 0"));
  EXPECT_THAT(
      errorOf(kHeader + row(0), kHitsHeader + "0,3,5\n", "track-hits", 2),
      HasSubstr("column 'outlier': '5' is not 0, 1 or 2"));
  EXPECT_THAT(errorOf(kHeader + row(0), kHitsHeader + "0,3\n", "track-hits", 2),
              HasSubstr("expected 3 fields as in the header, found 2"));
}

TEST_F(TrackFiles, CountsMustMatchTheHitRows) {
  EXPECT_THAT(errorOf(kHeader + row(0) + row(1),
                      kHitsHeader + hitRows(0) + "1,3,0\n", "tracks", 3),
              HasSubstr("n_hits is 3 but t-track-hits.csv has 1 rows"));
  EXPECT_THAT(errorOf(kHeader + row(0, "3", "1"), kHitsHeader + hitRows(0),
                      "tracks", 2),
              HasSubstr("n_outliers is 1 but t-track-hits.csv flags 0"));
  // Without the outlier column no hit is an outlier.
  EXPECT_THAT(errorOf(kHeader + row(0, "1", "1"), "track_id,hit_id\n0,3\n",
                      "tracks", 2),
              HasSubstr("n_outliers is 1"));
}

TEST_F(TrackFiles, MissingOrAmbiguousFiles) {
  const auto hits = makeHits();
  const fs::path tracks =
      m_dir / trackFileName(9, TrackFileKind::eTracks, false);
  try {
    readTracks(m_dir, 9, hits);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              tracks.string() + ": no such file (nor with .gz)");
  }
  writeTracks(m_dir, 9, hits, makeTracks());
  write(trackFileName(9, TrackFileKind::eTracks, true), "x");
  try {
    readTracks(m_dir, 9, hits);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("exist: remove one of them"));
  }
}

}  // namespace
}  // namespace conftrack
