/// @file TrackmlCsvTests.cpp
/// Round trips of the TrackML CSV reader/writer and reading of the shipped
/// Kaggle TrackML events.

#include "conftrack/core/Event.hpp"
#include "conftrack/core/TextFile.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/io/EventFiles.hpp"
#include "conftrack/io/TrackmlIds.hpp"
#include "conftrack/io/TrackmlReader.hpp"
#include "conftrack/io/TrackmlWriter.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>
#include <string>
#include <unistd.h>

#include "TempDir.hpp"

namespace conftrack {
namespace {

namespace fs = std::filesystem;

const fs::path kTrackmlDir =
    fs::path(CONFTRACK_TEST_DATA_DIR) / "trackml/train_100_events_no_truth";

using test::TempDir;
using test::writeText;

const Detector& clicdet() {
  static const Detector detector = loadDetector("clicdet");
  return detector;
}

/// A made-up event on CLICdet with full-precision random doubles: hits on
/// every layer, truth for each hit, particles with all fields set.
/// `contiguousIds` false gives hit ids that are not 1..N in file order.
Event makeEvent(const Detector& detector, std::uint64_t number,
                bool contiguousIds = true) {
  std::mt19937_64 rng(number);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> sym(-1.0, 1.0);
  Event event;
  event.number = number;

  const int pdgs[] = {11, -11, 13, -13, 211, -211, 321, 2212, 22, 310};
  for (std::uint64_t i = 0; i < 40; ++i) {
    Particle p;
    // TrackML-like 64-bit ids, not in order.
    p.id = ((40 - i) << 52) | (rng() & 0xFFFFFFFFFFull);
    p.pdg = pdgs[i % 10];
    p.status = (i % 7 == 3) ? 2 : 1;
    p.charge = (p.pdg == 22 || p.pdg == 310) ? 0.0 : (p.pdg > 0 ? -1.0 : 1.0);
    p.vertex =
        Vector3(sym(rng) * 0.01, sym(rng) * 0.01, sym(rng) * 50.0) * units::mm;
    p.time = sym(rng) * 0.1 * units::ns;
    p.momentum = Vector3(sym(rng), sym(rng), sym(rng)) * 20.0 * units::GeV;
    p.parentId = (i % 5 == 4) ? event.particles.front().id : 0;
    p.origin =
        (i % 3 == 2) ? ParticleOrigin::eBackground : ParticleOrigin::eSignal;
    p.nHits = static_cast<std::uint32_t>(rng() % 30);
    event.particles.push_back(p);
  }
  event.sortParticles();

  for (const SensitiveLayer& layer : detector.layers()) {
    for (int k = 0; k < 6; ++k) {
      Hit hit;
      double phi = sym(rng) * std::numbers::pi;
      double r = layer.isDisk()
                     ? layer.rMin + unit(rng) * (layer.rMax - layer.rMin)
                     : layer.r;
      double z = layer.isDisk()
                     ? layer.z()
                     : layer.zMin + unit(rng) * (layer.zMax - layer.zMin);
      hit.position = Vector3(r * std::cos(phi), r * std::sin(phi), z);
      hit.detId = layer.id;
      hit.detId.module = layer.moduleAt(hit.position);
      layer.localAxes(hit.position, hit.uAxis, hit.vAxis);
      // Not the layer value, so that the sigma columns are really used.
      hit.sigmaU = layer.sigmaU * (1.0 + unit(rng));
      hit.sigmaV = layer.sigmaV * (1.0 + unit(rng));
      event.hits.push_back(hit);

      HitTruth truth;
      truth.particleId =
          (k == 5) ? 0 : event.particles[rng() % event.particles.size()].id;
      truth.position =
          hit.position + Vector3(sym(rng), sym(rng), sym(rng)) * units::um;
      truth.momentum = Vector3(sym(rng), sym(rng), sym(rng)) * units::GeV;
      truth.time = unit(rng) * 10.0 * units::ns;
      truth.weight = unit(rng) * 1e-5;
      event.truth.push_back(truth);
    }
  }
  for (std::size_t i = 0; i < event.hits.size(); ++i) {
    event.hits[i].id = i + 1;
  }
  if (!contiguousIds) {
    std::vector<std::uint64_t> ids(event.hits.size());
    std::iota(ids.begin(), ids.end(), 1000);
    std::shuffle(ids.begin(), ids.end(), rng);
    for (std::size_t i = 0; i < ids.size(); ++i) {
      event.hits[i].id = ids[i] * 7;
    }
  }
  // Values that are hard to round-trip: extremes and negative zero.
  event.truth[0].weight = 5e-324;  // smallest subnormal
  event.truth[1].time = 1.7976931348623157e308;
  event.truth[2].momentum.x() = -0.0;
  event.particles[0].time = 0.1 + 0.2;  // 0.30000000000000004
  return event;
}

/// Bit-exact equality of doubles (also tells -0.0 from 0.0).
bool same(double a, double b) {
  return std::memcmp(&a, &b, sizeof(double)) == 0;
}
bool same(const Vector3& a, const Vector3& b) {
  return same(a.x(), b.x()) && same(a.y(), b.y()) && same(a.z(), b.z());
}

void expectSameHits(const std::vector<Hit>& a, const std::vector<Hit>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    SCOPED_TRACE("hit " + std::to_string(i));
    EXPECT_EQ(a[i].id, b[i].id);
    EXPECT_TRUE(same(a[i].position, b[i].position));
    EXPECT_EQ(a[i].detId, b[i].detId);
    EXPECT_TRUE(same(a[i].uAxis, b[i].uAxis));
    EXPECT_TRUE(same(a[i].vAxis, b[i].vAxis));
    EXPECT_TRUE(same(a[i].sigmaU, b[i].sigmaU));
    EXPECT_TRUE(same(a[i].sigmaV, b[i].sigmaV));
  }
}

void expectSameEvent(const Event& a, const Event& b) {
  EXPECT_EQ(a.number, b.number);
  expectSameHits(a.hits, b.hits);
  ASSERT_EQ(a.truth.size(), b.truth.size());
  for (std::size_t i = 0; i < a.truth.size(); ++i) {
    SCOPED_TRACE("truth " + std::to_string(i));
    EXPECT_EQ(a.truth[i].particleId, b.truth[i].particleId);
    EXPECT_TRUE(same(a.truth[i].position, b.truth[i].position));
    EXPECT_TRUE(same(a.truth[i].momentum, b.truth[i].momentum));
    EXPECT_TRUE(same(a.truth[i].time, b.truth[i].time));
    EXPECT_TRUE(same(a.truth[i].weight, b.truth[i].weight));
  }
  ASSERT_EQ(a.particles.size(), b.particles.size());
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    SCOPED_TRACE("particle " + std::to_string(i));
    const Particle& p = a.particles[i];
    const Particle& q = b.particles[i];
    EXPECT_EQ(p.id, q.id);
    EXPECT_EQ(p.pdg, q.pdg);
    EXPECT_EQ(p.status, q.status);
    EXPECT_TRUE(same(p.charge, q.charge));
    EXPECT_TRUE(same(p.vertex, q.vertex));
    EXPECT_TRUE(same(p.time, q.time));
    EXPECT_TRUE(same(p.momentum, q.momentum));
    EXPECT_EQ(p.parentId, q.parentId);
    EXPECT_EQ(p.origin, q.origin);
    EXPECT_EQ(p.nHits, q.nHits);
  }
}

class RoundTrip : public ::testing::TestWithParam<bool> {};

TEST_P(RoundTrip, WriteThenReadIsBitIdentical) {
  const bool gzip = GetParam();
  TempDir dir;
  Event event = makeEvent(clicdet(), 123);
  writeEvent(dir.path(), event, &clicdet().trackmlLayerMap(),
             WriteOptions{gzip});

  for (auto kind : {EventFileKind::eHits, EventFileKind::eTruth,
                    EventFileKind::eParticles}) {
    EXPECT_TRUE(fs::exists(dir.path() / eventFileName(123, kind, gzip)));
    EXPECT_FALSE(fs::exists(dir.path() / eventFileName(123, kind, !gzip)));
  }
  Event back = readEvent(dir.path(), 123, &clicdet().trackmlLayerMap());
  expectSameEvent(event, back);
}

INSTANTIATE_TEST_SUITE_P(PlainAndGzip, RoundTrip, ::testing::Bool(),
                         [](const auto& info) {
                           return info.param ? "Gzip" : "Plain";
                         });

TEST(TrackmlCsv, RoundTripWithUnorderedHitIds) {
  TempDir dir;
  Event event = makeEvent(clicdet(), 7, false);
  writeEvent(dir.path(), event, &clicdet().trackmlLayerMap());
  expectSameEvent(event,
                  readEvent(dir.path(), 7, &clicdet().trackmlLayerMap()));
}

TEST(TrackmlCsv, FileNames) {
  EXPECT_EQ(eventFileName(1001, EventFileKind::eHits, true),
            "event000001001-hits.csv.gz");
  EXPECT_EQ(eventFileName(0, EventFileKind::eTruth, false),
            "event000000000-truth.csv");
  EXPECT_EQ(eventFileName(1234567890, EventFileKind::eParticles, false),
            "event1234567890-particles.csv");
}

TEST(TrackmlCsv, ListEvents) {
  TempDir dir;
  writeEvent(dir.path(), makeEvent(clicdet(), 12), &clicdet().trackmlLayerMap(),
             WriteOptions{true});
  writeEvent(dir.path(), makeEvent(clicdet(), 3), &clicdet().trackmlLayerMap());
  writeText(dir.path() / "event000000099-particles.csv", "");  // no hits
  writeText(dir.path() / "eventX-hits.csv", "");
  writeText(dir.path() / "notes.txt", "");
  EXPECT_EQ(listEvents(dir.path()), (std::vector<std::uint64_t>{3, 12}));
  EXPECT_EQ(listEvents(kTrackmlDir),
            (std::vector<std::uint64_t>{1001, 1003, 1005, 1009, 1010}));
}

TEST(TrackmlCsv, RewriteReplacesOtherCompressionAndStaleTruth) {
  TempDir dir;
  Event event = makeEvent(clicdet(), 5);
  writeEvent(dir.path(), event, &clicdet().trackmlLayerMap(),
             WriteOptions{true});
  event.truth.clear();
  writeEvent(dir.path(), event, &clicdet().trackmlLayerMap(),
             WriteOptions{false});
  EventFiles files = EventFiles::locate(dir.path(), 5);
  ASSERT_TRUE(files.hits);
  EXPECT_EQ(files.hits->filename(), "event000000005-hits.csv");
  EXPECT_FALSE(files.truth);
  Event back = readEvent(dir.path(), 5, &clicdet().trackmlLayerMap());
  EXPECT_FALSE(back.hasTruth());
  expectSameEvent(event, back);
}

TEST(TrackmlCsv, ReadOptionsSkipTruthAndParticles) {
  TempDir dir;
  writeEvent(dir.path(), makeEvent(clicdet(), 5), &clicdet().trackmlLayerMap());
  Event back = readEvent(dir.path(), 5, &clicdet().trackmlLayerMap(),
                         ReadOptions{false, false});
  EXPECT_FALSE(back.hits.empty());
  EXPECT_TRUE(back.truth.empty());
  EXPECT_TRUE(back.particles.empty());
}

TEST(TrackmlCsv, ColumnsByNameAnyOrderUnknownIgnored) {
  TempDir dir;
  // VertexBarrel layer 0 of CLICdet is TrackML (volume 1, layer 2).
  writeText(dir.path() / "hits.csv",
            "module_id,comment,z,layer_id,y,x,volume_id,hit_id\r\n"
            "3,7,12.5,2,0,31.165,1,42\r\n"
            "\r\n");
  auto hits = readHits(dir.path() / "hits.csv", &clicdet().trackmlLayerMap());
  ASSERT_EQ(hits.size(), 1u);
  const SensitiveLayer& layer = clicdet().layers()[0];
  EXPECT_EQ(hits[0].id, 42u);
  EXPECT_EQ(hits[0].position, Vector3(31.165, 0.0, 12.5));
  EXPECT_EQ(hits[0].detId.subdetector, layer.id.subdetector);
  EXPECT_EQ(hits[0].detId.layer, layer.id.layer);
  EXPECT_EQ(hits[0].detId.side, Side::eBarrel);
  EXPECT_EQ(hits[0].detId.module, 3u);
  // Without sigma columns the resolutions come from the layer.
  EXPECT_EQ(hits[0].sigmaU, layer.sigmaU);
  EXPECT_EQ(hits[0].sigmaV, layer.sigmaV);
  EXPECT_EQ(hits[0].uAxis, Vector3(0.0, 1.0, 0.0));
  EXPECT_EQ(hits[0].vAxis, Vector3(0.0, 0.0, 1.0));
}

TEST(TrackmlCsv, RawIdsWithoutDetector) {
  TempDir dir;
  writeText(dir.path() / "hits.csv",
            "hit_id,x,y,z,volume_id,layer_id,module_id\n"
            "1,-69.2717,-0.812497,-1502.5,7,2,1\n"
            "2,1,2,3,18,12,1000\n");
  auto hits = readHits(dir.path() / "hits.csv", nullptr);
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_EQ(hits[1].detId, (DetectorId{18, Side::eBarrel, 12, 1000}));
  EXPECT_EQ(hits[0].sigmaU, 0.0);
  EXPECT_EQ(hits[0].sigmaV, 0.0);
  EXPECT_EQ(hits[0].uAxis, Vector3::UnitX());

  EXPECT_EQ(toTrackml(hits[1].detId, nullptr), (TrackmlId{18, 12, 1000}));
  writeHits(dir.path() / "out.csv.gz", hits, nullptr);
  expectSameHits(hits, readHits(dir.path() / "out.csv.gz", nullptr));
  // Unknown (zero) resolutions are not written: the file stays pure TrackML.
  std::string text = readTextFile(dir.path() / "out.csv.gz");
  EXPECT_EQ(text.substr(0, text.find('\n')),
            "hit_id,x,y,z,volume_id,layer_id,module_id");
}

TEST(TrackmlCsv, TrackmlIdMappingWithDetector) {
  for (const SensitiveLayer& layer : clicdet().layers()) {
    DetectorId id = layer.id;
    id.module = layer.nPhiModules * layer.nZModules - 1;
    auto tid = toTrackml(id, &clicdet().trackmlLayerMap());
    ASSERT_TRUE(tid);
    EXPECT_EQ(tid->volume, layer.trackmlVolume);
    EXPECT_EQ(tid->layer, layer.trackmlLayer);
    EXPECT_EQ(tid->module, id.module);
    EXPECT_EQ(fromTrackml(*tid, &clicdet().trackmlLayerMap()), id);
    ++tid->module;
    EXPECT_FALSE(fromTrackml(*tid, &clicdet().trackmlLayerMap()));
  }
}

TEST(TrackmlCsv, OptionalColumnsDefaults) {
  TempDir dir;
  writeText(dir.path() / "hits.csv",
            "hit_id,x,y,z,volume_id,layer_id,module_id\n1,1,0,0,1,2,0\n");
  writeText(dir.path() / "truth.csv",
            "hit_id,particle_id,tx,ty,tz,tpx,tpy,tpz\n1,5,1,0,0,1,2,3\n");
  writeText(dir.path() / "particles.csv",
            "particle_id,vx,vy,vz,px,py,pz,q,nhits\n5,0,0,0,1,2,3,-1,1\n");
  auto hits = readHits(dir.path() / "hits.csv", nullptr);
  auto truth = readTruth(dir.path() / "truth.csv", hits);
  ASSERT_EQ(truth.size(), 1u);
  EXPECT_EQ(truth[0].particleId, 5u);
  EXPECT_EQ(truth[0].weight, 0.0);
  EXPECT_EQ(truth[0].time, 0.0);
  auto particles = readParticles(dir.path() / "particles.csv");
  ASSERT_EQ(particles.size(), 1u);
  EXPECT_EQ(particles[0].pdg, 0);
  EXPECT_EQ(particles[0].status, 1);
  EXPECT_EQ(particles[0].parentId, 0u);
  EXPECT_EQ(particles[0].time, 0.0);
  EXPECT_EQ(particles[0].charge, -1.0);
  EXPECT_FALSE(particles[0].isBackground());
}

TEST(TrackmlCsv, HeaderOnlyFilesAreEmptyEvents) {
  TempDir dir;
  writeText(dir.path() / "event000000001-hits.csv",
            "hit_id,x,y,z,volume_id,layer_id,module_id\n");
  Event event = readEvent(dir.path(), 1, nullptr);
  EXPECT_TRUE(event.hits.empty());
}

TEST(TrackmlCsv, GzipWithSeveralMembers) {
  TempDir dir;
  // `cat a.gz b.gz` is a valid gzip file that zcat reads as a + b.
  writeTextFile(dir.path() / "a.gz",
                "hit_id,x,y,z,volume_id,layer_id,module_id\n1,1,1,1,1,1,1\n",
                true);
  writeTextFile(dir.path() / "b.gz", "2,2,2,2,1,1,1\n", true);
  std::string both = readTextFile(dir.path() / "a.gz");
  std::ifstream a(dir.path() / "a.gz", std::ios::binary);
  std::ifstream b(dir.path() / "b.gz", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(a)), {});
  bytes.append(std::istreambuf_iterator<char>(b), {});
  writeText(dir.path() / "hits.csv.gz", bytes);
  EXPECT_EQ(readHits(dir.path() / "hits.csv.gz", nullptr).size(), 2u);
}

struct RealEvent {
  std::uint64_t number;
  std::size_t hits;
  std::size_t particles;
  std::uint64_t sumNHits;
};

class RealTrackmlEvent : public ::testing::TestWithParam<RealEvent> {};

TEST_P(RealTrackmlEvent, ReadsWithTheRightCounts) {
  const RealEvent& expected = GetParam();
  Event event = readEvent(kTrackmlDir, expected.number, nullptr);
  EXPECT_EQ(event.hits.size(), expected.hits);
  EXPECT_EQ(event.particles.size(), expected.particles);
  EXPECT_FALSE(event.hasTruth());
  std::uint64_t sum = 0;
  for (const Particle& p : event.particles) {
    sum += p.nHits;
  }
  EXPECT_EQ(sum, expected.sumNHits);
  EXPECT_TRUE(std::is_sorted(
      event.particles.begin(), event.particles.end(),
      [](const Particle& a, const Particle& b) { return a.id < b.id; }));
  // TrackML hit ids run 1..N; the TrackML volumes are 7..18.
  EXPECT_EQ(event.hits.front().id, 1u);
  EXPECT_EQ(event.hits.back().id, expected.hits);
  for (const Hit& hit : event.hits) {
    ASSERT_GE(hit.detId.subdetector, 7);
    ASSERT_LE(hit.detId.subdetector, 18);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Kaggle, RealTrackmlEvent,
    ::testing::Values(RealEvent{1001, 93680, 8915, 76210},
                      RealEvent{1003, 104451, 10261, 86931},
                      RealEvent{1005, 110023, 10945, 92218},
                      RealEvent{1009, 108769, 10724, 91065},
                      RealEvent{1010, 104084, 10150, 86310}),
    [](const auto& info) { return std::to_string(info.param.number); });

TEST(TrackmlCsv, RealEventFirstHitValues) {
  auto hits = readHits(kTrackmlDir / "event000001001-hits.csv.gz", nullptr);
  ASSERT_FALSE(hits.empty());
  EXPECT_EQ(hits[0].position, Vector3(-69.2717, -0.812497, -1502.5));
  EXPECT_EQ(hits[0].detId, (DetectorId{7, Side::eBarrel, 2, 1}));
}

TEST(TrackmlCsv, RealEventRawRoundTrip) {
  TempDir dir;
  Event event = readEvent(kTrackmlDir, 1001, nullptr);
  writeEvent(dir.path(), event, nullptr, WriteOptions{true, 1});
  expectSameEvent(event, readEvent(dir.path(), 1001, nullptr));
}

}  // namespace
}  // namespace conftrack
