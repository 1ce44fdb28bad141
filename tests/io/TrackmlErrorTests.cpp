/// @file TrackmlErrorTests.cpp
/// Every kind of bad TrackML input gives a one-line InputError
/// "file:line: problem", never a crash or silently wrong data.

#include "conftrack/core/Error.hpp"
#include "conftrack/core/TextFile.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/io/EventFiles.hpp"
#include "conftrack/io/TrackmlReader.hpp"
#include "conftrack/io/TrackmlWriter.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <unistd.h>

#include "TempDir.hpp"

namespace conftrack {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::StartsWith;

const std::string kHitsHeader = "hit_id,x,y,z,volume_id,layer_id,module_id\n";
const std::string kTruthHeader =
    "hit_id,particle_id,tx,ty,tz,tpx,tpy,tpz,weight\n";
const std::string kParticlesHeader =
    "particle_id,particle_type,vx,vy,vz,px,py,pz,q,nhits\n";

const Detector& clicdet() {
  static const Detector detector = loadDetector("clicdet");
  return detector;
}

/// Writes bad files into a fresh folder and checks the error they give.
class TrackmlErrors : public ::testing::Test {
 protected:
  /// Writes `text` to a file in the test folder; returns its path.
  fs::path write(const std::string& name, const std::string& text) {
    return test::writeText(m_dir / name, text);
  }

  /// Runs `f`, expects an InputError and returns its message, checking
  /// that it is one line starting with "file:line: " (line 0 = no line).
  static std::string errorOf(const std::function<void()>& f,
                             const fs::path& file, std::size_t line) {
    try {
      f();
    } catch (const InputError& e) {
      std::string message = e.what();
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      EXPECT_THAT(message, StartsWith(location(file.string(), line) + ": "));
      return message;
    }
    ADD_FAILURE() << "no InputError thrown";
    return "";
  }

  /// Reads a hits file and returns the error, expected at `line`.
  std::string hitsError(const std::string& text, std::size_t line,
                        const Detector* detector = nullptr) {
    fs::path file = write("hits.csv", text);
    return errorOf([&] { readHits(file, trackmlLayerMapOf(detector)); }, file,
                   line);
  }

  test::TempDir m_tmp;
  const fs::path& m_dir = m_tmp.path();
};

TEST_F(TrackmlErrors, MissingFile) {
  fs::path file = m_dir / "nothing-hits.csv";
  EXPECT_THAT(errorOf([&] { readHits(file, nullptr); }, file, 0),
              HasSubstr("cannot open"));
}

TEST_F(TrackmlErrors, MissingEvent) {
  fs::path file = m_dir / "event000000042-hits.csv";
  EXPECT_THAT(errorOf([&] { readEvent(m_dir, 42, nullptr); }, file, 0),
              HasSubstr("no such file"));
}

TEST_F(TrackmlErrors, MissingFolderForListEvents) {
  fs::path dir = m_dir / "nope";
  EXPECT_THAT(errorOf([&] { listEvents(dir); }, dir, 0),
              HasSubstr("not a folder"));
}

TEST_F(TrackmlErrors, MissingRequiredHitsColumn) {
  EXPECT_THAT(hitsError("hit_id,x,y,volume_id,layer_id,module_id\n"
                        "1,1,1,1,1,1\n",
                        1),
              HasSubstr("missing required column 'z'"));
}

TEST_F(TrackmlErrors, RenamedRequiredHitsColumn) {
  EXPECT_THAT(hitsError("hit_id,x,y,z,volume,layer_id,module_id\n"
                        "1,1,1,1,1,1,1\n",
                        1),
              HasSubstr("missing required column 'volume_id'"));
}

TEST_F(TrackmlErrors, MissingRequiredTruthColumn) {
  fs::path hitsFile = write("hits.csv", kHitsHeader + "1,1,1,1,1,1,1\n");
  auto hits = readHits(hitsFile, nullptr);
  fs::path file = write("truth.csv",
                        "hit_id,particle,tx,ty,tz,tpx,tpy,tpz\n"
                        "1,0,1,1,1,1,1,1\n");
  EXPECT_THAT(errorOf([&] { readTruth(file, hits); }, file, 1),
              HasSubstr("missing required column 'particle_id'"));
}

TEST_F(TrackmlErrors, MissingRequiredParticlesColumn) {
  fs::path file = write("particles.csv",
                        "particle_id,vx,vy,vz,px,py,pz,nhits\n"
                        "1,0,0,0,1,1,1,3\n");
  EXPECT_THAT(errorOf([&] { readParticles(file); }, file, 1),
              HasSubstr("missing required column 'q'"));
}

TEST_F(TrackmlErrors, DuplicateColumn) {
  EXPECT_THAT(hitsError("hit_id,x,y,z,x,volume_id,layer_id,module_id\n", 1),
              HasSubstr("duplicate column 'x'"));
}

TEST_F(TrackmlErrors, NonNumericField) {
  std::string message =
      hitsError(kHitsHeader + "1,1,1,1,1,1,1\n2,1,abc,1,1,1,1\n", 3);
  EXPECT_THAT(message, HasSubstr("column 'y': 'abc' is not a number"));
}

TEST_F(TrackmlErrors, TrailingCharactersInNumber) {
  EXPECT_THAT(hitsError(kHitsHeader + "1,1.5x,1,1,1,1,1\n", 2),
              HasSubstr("column 'x': '1.5x' is not a number"));
}

TEST_F(TrackmlErrors, EmptyField) {
  EXPECT_THAT(hitsError(kHitsHeader + "1,1,1,,1,1,1\n", 2),
              HasSubstr("column 'z': '' is not a number"));
}

TEST_F(TrackmlErrors, NonIntegerId) {
  EXPECT_THAT(hitsError(kHitsHeader + "1.5,1,1,1,1,1,1\n", 2),
              HasSubstr("column 'hit_id': '1.5' is not an integer"));
}

TEST_F(TrackmlErrors, NegativeUnsignedField) {
  EXPECT_THAT(hitsError(kHitsHeader + "1,1,1,1,1,1,-3\n", 2),
              HasSubstr("column 'module_id': '-3' is not an integer"));
}

TEST_F(TrackmlErrors, NaN) {
  EXPECT_THAT(hitsError(kHitsHeader + "1,nan,1,1,1,1,1\n", 2),
              HasSubstr("column 'x': 'nan' is not finite"));
}

TEST_F(TrackmlErrors, Infinity) {
  EXPECT_THAT(hitsError(kHitsHeader + "1,1,-inf,1,1,1,1\n", 2),
              HasSubstr("column 'y': '-inf' is not finite"));
  EXPECT_THAT(hitsError(kHitsHeader + "1,1,1,1e999,1,1,1\n", 2),
              HasSubstr("column 'z': '1e999' is out of the range"));
}

TEST_F(TrackmlErrors, NaNInTruthAndParticles) {
  fs::path hitsFile = write("hits.csv", kHitsHeader + "1,1,1,1,1,1,1\n");
  auto hits = readHits(hitsFile, nullptr);
  fs::path truth = write("truth.csv", kTruthHeader + "1,0,1,1,1,1,NaN,1,0\n");
  EXPECT_THAT(errorOf([&] { readTruth(truth, hits); }, truth, 2),
              HasSubstr("column 'tpy': 'NaN' is not finite"));
  fs::path particles =
      write("particles.csv", kParticlesHeader + "1,11,0,0,0,1,1,inf,-1,1\n");
  EXPECT_THAT(errorOf([&] { readParticles(particles); }, particles, 2),
              HasSubstr("column 'pz': 'inf' is not finite"));
}

TEST_F(TrackmlErrors, TooFewFields) {
  EXPECT_THAT(hitsError(kHitsHeader + "1,1,1,1,1,1,1\n2,1,1,1,1,1\n", 3),
              HasSubstr("expected 7 fields as in the header, found 6"));
}

TEST_F(TrackmlErrors, TooManyFields) {
  EXPECT_THAT(hitsError(kHitsHeader + "1,1,1,1,1,1,1,1\n", 2),
              HasSubstr("expected 7 fields as in the header, found 8"));
}

TEST_F(TrackmlErrors, TruncatedGzip) {
  std::string text = kHitsHeader;
  for (int i = 1; i <= 2000; ++i) {
    text += std::to_string(i) + ",1.25,2.5," + std::to_string(i) + ",1,2,3\n";
  }
  fs::path good = m_dir / "good-hits.csv.gz";
  writeTextFile(good, text, true);
  EXPECT_EQ(readHits(good, nullptr).size(), 2000u);

  std::ifstream in(good, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  for (std::size_t keep : {bytes.size() - 1, bytes.size() - 8, bytes.size() / 2,
                           std::size_t{10}, std::size_t{2}}) {
    SCOPED_TRACE("kept bytes: " + std::to_string(keep));
    fs::path file = write("cut-hits.csv.gz", bytes.substr(0, keep));
    EXPECT_THAT(errorOf([&] { readHits(file, nullptr); }, file, 0),
                HasSubstr("unexpected end of file"));
  }
}

TEST_F(TrackmlErrors, CorruptGzip) {
  std::string text = kHitsHeader + "1,1,1,1,1,1,1\n";
  fs::path good = m_dir / "good.csv.gz";
  writeTextFile(good, text, true);
  std::ifstream in(good, std::ios::binary);
  const std::string original((std::istreambuf_iterator<char>(in)), {});
  // Flipping bits in the trailer (CRC) must be detected.
  std::string bytes = original;
  bytes[bytes.size() - 6] = static_cast<char>(bytes[bytes.size() - 6] ^ 0x55);
  fs::path file = write("bad.csv.gz", bytes);
  EXPECT_THAT(errorOf([&] { readHits(file, nullptr); }, file, 0),
              HasSubstr("corrupt gzip data"));
  fs::path trailing = write("trailing.csv.gz", original + "garbage");
  EXPECT_THAT(errorOf([&] { readHits(trailing, nullptr); }, trailing, 0),
              HasSubstr("trailing garbage"));
}

TEST_F(TrackmlErrors, DuplicateHitIds) {
  EXPECT_THAT(
      hitsError(kHitsHeader + "1,1,1,1,1,1,1\n2,1,1,1,1,1,1\n2,1,1,1,1,1,1\n",
                4),
      HasSubstr("duplicate hit_id 2"));
  // Not in the 1..N pattern: found through the hash set.
  EXPECT_THAT(
      hitsError(kHitsHeader + "50,1,1,1,1,1,1\n9,1,1,1,1,1,1\n50,1,1,1,1,1,1\n",
                4),
      HasSubstr("duplicate hit_id 50"));
}

TEST_F(TrackmlErrors, HitOnBeamLine) {
  EXPECT_THAT(hitsError(kHitsHeader + "1,1,1,1,1,1,1\n2,0,-0,250,1,1,1\n", 3),
              HasSubstr("hit_id 2 lies on the beam line"));
  // x^2 + y^2 underflows to 0: the conformal mapping would give inf.
  EXPECT_THAT(hitsError(kHitsHeader + "1,1e-200,1e-200,250,1,1,1\n", 2),
              HasSubstr("hit_id 1 lies on the beam line"));
  EXPECT_THAT(hitsError(kHitsHeader + "1,0,0,250,1,2,0\n", 2, &clicdet()),
              HasSubstr("hit_id 1 lies on the beam line"));
}

TEST_F(TrackmlErrors, HitOutsideTheTracker) {
  // CLICdet VertexBarrel layer 0 is (volume 1, layer 2) at r = 31.165 mm.
  EXPECT_EQ(readHits(write("ok.csv", kHitsHeader + "1,31.165,0,10,1,2,0\n"),
                     &clicdet().trackmlLayerMap())
                .size(),
            1u);
  EXPECT_THAT(
      hitsError(kHitsHeader + "1,1e308,1e308,1e308,1,2,0\n", 2, &clicdet()),
      HasSubstr("hit_id 1 at r = 1.41421e+308 mm, z = 1e+308 mm lies outside "
                "the tracker of detector 'CLICdet' (r <= 1500 mm, |z| <= "
                "2306 mm)"));
  EXPECT_THAT(
      hitsError(kHitsHeader + "1,31.165,0,-3000,1,2,0\n", 2, &clicdet()),
      HasSubstr("lies outside the tracker"));
}

TEST_F(TrackmlErrors, HitAwayFromItsLayer) {
  // Inside the tracker, but 470 mm from the layer it names.
  EXPECT_THAT(
      hitsError(kHitsHeader + "1,500,0,10,1,2,0\n", 2, &clicdet()),
      HasSubstr("hit_id 1 at r = 500 mm, z = 10 mm is not on the layer its "
                "volume_id/layer_id name (VXD_B_L0: r = 31.165 mm"));
  // Beyond the end of the barrel layer (|z| <= 130 mm) by more than 25 mm.
  EXPECT_THAT(hitsError(kHitsHeader + "1,31.165,0,200,1,2,0\n", 2, &clicdet()),
              HasSubstr("is not on the layer"));
}

TEST_F(TrackmlErrors, NegativeTruthWeight) {
  fs::path hitsFile = write("hits.csv", kHitsHeader + "1,1,1,1,1,1,1\n");
  auto hits = readHits(hitsFile, nullptr);
  fs::path truth = write("truth.csv", kTruthHeader + "1,0,1,1,1,1,1,1,-0.5\n");
  EXPECT_THAT(errorOf([&] { readTruth(truth, hits); }, truth, 2),
              HasSubstr("column 'weight': '-0.5' is negative"));
}

TEST_F(TrackmlErrors, CrOnlyLineEnds) {
  // Not "duplicate column '1'" from one long line.
  EXPECT_THAT(hitsError("hit_id,x,y,z,volume_id,layer_id,module_id\r"
                        "1,1,1,1,1,1,1\r2,1,1,1,1,1,1\r",
                        1),
              HasSubstr("line ends are CR only"));
}

TEST_F(TrackmlErrors, CrLfReadsLikeLf) {
  const std::string rows = "1,31.165,0,10,1,2,0\n2,33.1,0.5,-4,1,4,0\n";
  std::string crlf = kHitsHeader + rows;
  for (std::size_t i = 0; (i = crlf.find('\n', i)) != std::string::npos;
       i += 2) {
    crlf.insert(i, "\r");
  }
  auto lf = readHits(write("lf.csv", kHitsHeader + rows),
                     &clicdet().trackmlLayerMap());
  auto dos = readHits(write("crlf.csv", crlf), &clicdet().trackmlLayerMap());
  ASSERT_EQ(lf.size(), 2u);
  ASSERT_EQ(dos.size(), 2u);
  for (std::size_t i = 0; i < lf.size(); ++i) {
    EXPECT_EQ(lf[i].id, dos[i].id);
    EXPECT_EQ(lf[i].position, dos[i].position);
    EXPECT_TRUE(lf[i].detId.sameSensor(dos[i].detId));
  }
}

TEST_F(TrackmlErrors, NonUtf8BytesAreMaskedInMessages) {
  EXPECT_THAT(hitsError(kHitsHeader + "1,\xff\xfe"
                                      "1,1,1,1,1,1\n",
                        2),
              HasSubstr("column 'x': '??1' is not a number"));
  // Valid UTF-8 is shown as it is.
  EXPECT_THAT(hitsError(kHitsHeader + "1,1\xc2\xb5m,1,1,1,1,1\n", 2),
              HasSubstr("column 'x': '1\xc2\xb5m' is not a number"));
}

TEST_F(TrackmlErrors, HeaderOnlyHitsFileIsAnEmptyEvent) {
  EXPECT_TRUE(
      readHits(write("hits.csv", kHitsHeader), &clicdet().trackmlLayerMap())
          .empty());
}

TEST_F(TrackmlErrors, EmptyFile) {
  EXPECT_THAT(hitsError("", 1), HasSubstr("no header line"));
  fs::path gz = m_dir / "empty-hits.csv.gz";
  writeTextFile(gz, "", true);
  EXPECT_THAT(errorOf([&] { readHits(gz, nullptr); }, gz, 1),
              HasSubstr("no header line"));
}

TEST_F(TrackmlErrors, EmptyFirstLine) {
  EXPECT_THAT(hitsError("\n" + kHitsHeader + "1,1,1,1,1,1,1\n", 1),
              HasSubstr("no header line"));
}

TEST_F(TrackmlErrors, BinaryFile) {
  EXPECT_THAT(hitsError(std::string("hit_id\0x", 8), 0),
              HasSubstr("binary data"));
}

TEST_F(TrackmlErrors, NegativeSigma) {
  EXPECT_THAT(
      hitsError("hit_id,x,y,z,volume_id,layer_id,module_id,sigma_u,sigma_v\n"
                "1,1,1,1,1,1,1,0.01,-0.02\n",
                2),
      HasSubstr("column 'sigma_v': '-0.02' is negative"));
}

TEST_F(TrackmlErrors, UnknownLayerWithDetector) {
  // CLICdet has no TrackML volume 77.
  EXPECT_THAT(hitsError(kHitsHeader + "1,31.165,0,0,1,2,0\n"
                                      "2,31.165,0,0,77,2,0\n",
                        3, &clicdet()),
              HasSubstr("(volume_id, layer_id) = (77, 2) is not a layer of "
                        "detector 'CLICdet'"));
}

TEST_F(TrackmlErrors, ModuleOutOfRangeWithDetector) {
  EXPECT_THAT(
      hitsError(kHitsHeader + "1,31.165,0,0,1,2,100000\n", 2, &clicdet()),
      HasSubstr("column 'module_id': '100000' exceeds"));
}

TEST_F(TrackmlErrors, IdTooLargeWithoutDetector) {
  EXPECT_THAT(hitsError(kHitsHeader + "1,1,1,1,70000,1,1\n", 2),
              HasSubstr("do not fit 16 bits"));
}

TEST_F(TrackmlErrors, TruthForUnknownHit) {
  fs::path hitsFile =
      write("hits.csv", kHitsHeader + "1,1,1,1,1,1,1\n2,1,1,1,1,1,1\n");
  auto hits = readHits(hitsFile, nullptr);
  fs::path file = write("truth.csv", kTruthHeader +
                                         "1,0,1,1,1,1,1,1,0\n"
                                         "3,0,1,1,1,1,1,1,0\n");
  EXPECT_THAT(errorOf([&] { readTruth(file, hits); }, file, 3),
              HasSubstr("truth for hit_id 3, which is not in the hits file"));
}

TEST_F(TrackmlErrors, TruthRowMissing) {
  fs::path hitsFile =
      write("hits.csv", kHitsHeader + "1,1,1,1,1,1,1\n2,1,1,1,1,1,1\n");
  auto hits = readHits(hitsFile, nullptr);
  fs::path file = write("truth.csv", kTruthHeader + "2,0,1,1,1,1,1,1,0\n");
  EXPECT_THAT(errorOf([&] { readTruth(file, hits); }, file, 0),
              HasSubstr("no truth row for hit_id 1"));
}

TEST_F(TrackmlErrors, TruthRowDuplicate) {
  fs::path hitsFile =
      write("hits.csv", kHitsHeader + "1,1,1,1,1,1,1\n2,1,1,1,1,1,1\n");
  auto hits = readHits(hitsFile, nullptr);
  fs::path file = write("truth.csv", kTruthHeader +
                                         "2,0,1,1,1,1,1,1,0\n"
                                         "1,0,1,1,1,1,1,1,0\n"
                                         "2,0,1,1,1,1,1,1,0\n");
  EXPECT_THAT(errorOf([&] { readTruth(file, hits); }, file, 4),
              HasSubstr("second truth row for hit_id 2"));
}

TEST_F(TrackmlErrors, ParticleIdZero) {
  fs::path file = write("particles.csv", kParticlesHeader +
                                             "4,11,0,0,0,1,1,1,-1,1\n"
                                             "0,11,0,0,0,1,1,1,-1,1\n");
  EXPECT_THAT(errorOf([&] { readParticles(file); }, file, 3),
              HasSubstr("particle_id 0 is reserved"));
}

TEST_F(TrackmlErrors, DuplicateParticleIds) {
  fs::path file = write("particles.csv", kParticlesHeader +
                                             "4,11,0,0,0,1,1,1,-1,1\n"
                                             "5,11,0,0,0,1,1,1,-1,1\n"
                                             "4,13,0,0,0,1,1,1,-1,1\n");
  EXPECT_THAT(errorOf([&] { readParticles(file); }, file, 4),
              HasSubstr("duplicate particle_id 4"));
}

TEST_F(TrackmlErrors, BadBackgroundFlag) {
  fs::path file = write("particles.csv",
                        "particle_id,vx,vy,vz,px,py,pz,q,nhits,background\n"
                        "4,0,0,0,1,1,1,-1,1,2\n");
  EXPECT_THAT(errorOf([&] { readParticles(file); }, file, 2),
              HasSubstr("column 'background': '2' is not 0"));
}

TEST_F(TrackmlErrors, PlainAndGzipBothPresent) {
  write("event000000001-hits.csv", kHitsHeader);
  write("event000000001-hits.csv.gz", kHitsHeader);
  fs::path file = m_dir / "event000000001-hits.csv";
  EXPECT_THAT(errorOf([&] { readEvent(m_dir, 1, nullptr); }, file, 0),
              HasSubstr("exist: remove one of them"));
}

TEST_F(TrackmlErrors, WriterRefusesNonFiniteValues) {
  std::vector<Hit> hits(1);
  hits[0].id = 1;
  hits[0].position = Vector3(1.0, std::nan(""), 0.0);
  fs::path file = m_dir / "hits.csv";
  EXPECT_THAT(errorOf([&] { writeHits(file, hits, nullptr); }, file, 2),
              HasSubstr("column 'y': refusing to write"));
  EXPECT_FALSE(fs::exists(file));
}

TEST_F(TrackmlErrors, WriterRefusesIdsItCannotMap) {
  std::vector<Hit> hits(1);
  hits[0].id = 1;
  hits[0].position = Vector3(1.0, 1.0, 0.0);
  hits[0].detId = DetectorId{1, Side::ePositive, 0, 0};
  fs::path file = m_dir / "hits.csv";
  EXPECT_THAT(errorOf([&] { writeHits(file, hits, nullptr); }, file, 2),
              HasSubstr("not on the barrel side"));
  hits[0].detId = DetectorId{999, Side::eBarrel, 0, 0};
  EXPECT_THAT(
      errorOf([&] { writeHits(file, hits, &clicdet().trackmlLayerMap()); },
              file, 2),
      HasSubstr("is not a layer of detector 'CLICdet'"));
}

}  // namespace
}  // namespace conftrack
