#include "conftrack/io/TrackmlWriter.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/TextFile.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/io/CsvWriter.hpp"
#include "conftrack/io/EventFiles.hpp"
#include "conftrack/io/TrackmlFormat.hpp"
#include "conftrack/io/TrackmlIds.hpp"

#include <algorithm>
#include <stdexcept>

namespace conftrack {

namespace {

std::string describe(const DetectorId& id) {
  return "(subdetector " + std::to_string(id.subdetector) + ", side " +
         std::to_string(static_cast<int>(id.side)) + ", layer " +
         std::to_string(id.layer) + ")";
}

}  // namespace

void writeHits(const std::filesystem::path& file, const std::vector<Hit>& hits,
               const TrackmlLayerMap* layers, int gzipLevel) {
  namespace c = trackml::hits;
  // Resolutions all 0 mean "unknown" (e.g. Kaggle hits read without a
  // detector): leave the columns out, so that a later read with a detector
  // takes the layer resolutions instead of zeros.
  const bool withSigmas = std::any_of(
      hits.begin(), hits.end(),
      [](const Hit& h) { return h.sigmaU != 0.0 || h.sigmaV != 0.0; });
  std::vector<std::string_view> columns = {
      c::kHitId, c::kX, c::kY, c::kZ, c::kVolumeId, c::kLayerId, c::kModuleId};
  if (withSigmas) {
    columns.push_back(c::kSigmaU);
    columns.push_back(c::kSigmaV);
  }
  CsvWriter csv(file.string(), columns, hits.size());
  // Consecutive hits are mostly on one layer: remember the last mapping.
  DetectorId lastLayer;
  std::optional<TrackmlId> last;
  for (const Hit& hit : hits) {
    if (!last || !hit.detId.sameLayer(lastLayer)) {
      last = toTrackml(hit.detId, layers);
      lastLayer = hit.detId;
      if (!last) {
        csv.fail("hit_id " + std::to_string(hit.id) + ": detector id " +
                 describe(hit.detId) +
                 (layers != nullptr
                      ? " is not a layer of detector '" +
                            layers->detectorName() + "'"
                      : std::string(" is not on the barrel side: without a "
                                    "detector only raw barrel ids can be "
                                    "written")));
      }
    }
    csv.add(hit.id);
    csv.add(hit.position.x() / units::mm);
    csv.add(hit.position.y() / units::mm);
    csv.add(hit.position.z() / units::mm);
    csv.add(last->volume);
    csv.add(last->layer);
    csv.add(hit.detId.module);
    if (withSigmas) {
      csv.add(hit.sigmaU / units::mm);
      csv.add(hit.sigmaV / units::mm);
    }
    csv.endRow();
  }
  csv.write(file, hasGzipExtension(file), gzipLevel);
}

void writeTruth(const std::filesystem::path& file, const std::vector<Hit>& hits,
                const std::vector<HitTruth>& truth, int gzipLevel) {
  if (truth.size() != hits.size()) {
    throw std::invalid_argument(
        "writeTruth: " + std::to_string(truth.size()) + " truth entries for " +
        std::to_string(hits.size()) + " hits (must be parallel)");
  }
  namespace c = trackml::truth;
  CsvWriter csv(file.string(),
                {c::kHitId, c::kParticleId, c::kTx, c::kTy, c::kTz, c::kTpx,
                 c::kTpy, c::kTpz, c::kWeight, c::kTime},
                hits.size());
  for (std::size_t i = 0; i < hits.size(); ++i) {
    const HitTruth& t = truth[i];
    csv.add(hits[i].id);
    csv.add(t.particleId);
    csv.add(t.position.x() / units::mm);
    csv.add(t.position.y() / units::mm);
    csv.add(t.position.z() / units::mm);
    csv.add(t.momentum.x() / units::GeV);
    csv.add(t.momentum.y() / units::GeV);
    csv.add(t.momentum.z() / units::GeV);
    csv.add(t.weight);
    csv.add(t.time / units::ns);
    csv.endRow();
  }
  csv.write(file, hasGzipExtension(file), gzipLevel);
}

void writeParticles(const std::filesystem::path& file,
                    const std::vector<Particle>& particles, int gzipLevel) {
  namespace c = trackml::particles;
  CsvWriter csv(file.string(),
                {c::kParticleId, c::kParticleType, c::kVx, c::kVy, c::kVz,
                 c::kPx, c::kPy, c::kPz, c::kQ, c::kNHits, c::kVt, c::kStatus,
                 c::kParentId, c::kBackground},
                particles.size());
  for (const Particle& p : particles) {
    csv.add(p.id);
    csv.add(p.pdg);
    csv.add(p.vertex.x() / units::mm);
    csv.add(p.vertex.y() / units::mm);
    csv.add(p.vertex.z() / units::mm);
    csv.add(p.momentum.x() / units::GeV);
    csv.add(p.momentum.y() / units::GeV);
    csv.add(p.momentum.z() / units::GeV);
    csv.add(p.charge);
    csv.add(p.nHits);
    csv.add(p.time / units::ns);
    csv.add(p.status);
    csv.add(p.parentId);
    csv.add(p.isBackground() ? 1 : 0);
    csv.endRow();
  }
  csv.write(file, hasGzipExtension(file), gzipLevel);
}

void writeEvent(const std::filesystem::path& dir, const Event& event,
                const TrackmlLayerMap* layers, const WriteOptions& options) {
  if (event.hasTruth() && event.truth.size() != event.hits.size()) {
    throw std::invalid_argument("writeEvent: truth not parallel to hits");
  }
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    throw InputError(location(dir.string()),
                     "cannot create folder: " + ec.message());
  }
  auto path = [&](EventFileKind kind, bool gzip) {
    return dir / eventFileName(event.number, kind, gzip);
  };
  bool gz = options.gzip;
  auto write = [&](EventFileKind kind, const auto& writer) {
    std::filesystem::path target = path(kind, gz);
    // Write with the wanted compression, then drop the other variant.
    writer(target);
    removeIfExists(path(kind, !gz));
  };
  write(EventFileKind::eHits, [&](const std::filesystem::path& f) {
    writeHits(f, event.hits, layers, options.gzipLevel);
  });
  if (event.hasTruth()) {
    write(EventFileKind::eTruth, [&](const std::filesystem::path& f) {
      writeTruth(f, event.hits, event.truth, options.gzipLevel);
    });
  } else {
    removeIfExists(path(EventFileKind::eTruth, false));
    removeIfExists(path(EventFileKind::eTruth, true));
  }
  write(EventFileKind::eParticles, [&](const std::filesystem::path& f) {
    writeParticles(f, event.particles, options.gzipLevel);
  });
}

}  // namespace conftrack
