#include "conftrack/evaluation/SimulationValidation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace conftrack {

namespace {

/// Sums two layer lists sorted by id into one.
std::vector<LayerHitCount> mergeLayers(const std::vector<LayerHitCount>& x,
                                       const std::vector<LayerHitCount>& y) {
  std::vector<LayerHitCount> merged;
  merged.reserve(x.size() + y.size());
  auto a = x.begin();
  auto b = y.begin();
  while (a != x.end() || b != y.end()) {
    if (b == y.end() || (a != x.end() && a->id < b->id)) {
      merged.push_back(*a++);
    } else if (a == x.end() || b->id < a->id) {
      merged.push_back(*b++);
    } else {
      LayerHitCount sum = *a++;
      sum.real += b->real;
      sum.simulated += b->simulated;
      ++b;
      merged.push_back(sum);
    }
  }
  return merged;
}

/// Hits per (volume, layer), sorted by id; `simulated` says which count
/// they go to.
std::vector<LayerHitCount> countLayers(std::span<const VolumeLayer> hits,
                                       bool simulated) {
  std::vector<VolumeLayer> ids(hits.begin(), hits.end());
  std::sort(ids.begin(), ids.end());
  std::vector<LayerHitCount> counts;
  for (const VolumeLayer& id : ids) {
    if (counts.empty() || counts.back().id != id) {
      counts.push_back({id, 0, 0});
    }
    ++(simulated ? counts.back().simulated : counts.back().real);
  }
  return counts;
}

}  // namespace

double HitCountBin::realMean() const {
  return particles > 0 ? realHits / static_cast<double>(particles) : 0.0;
}

double HitCountBin::simulatedMean() const {
  return particles > 0 ? simulatedHits / static_cast<double>(particles) : 0.0;
}

double HitCountBin::deviation() const {
  return realHits > 0.0 ? simulatedHits / realHits - 1.0
                        : std::numeric_limits<double>::quiet_NaN();
}

double LayerHitCount::deviation() const {
  return real > 0
             ? static_cast<double>(simulated) / static_cast<double>(real) - 1.0
             : std::numeric_limits<double>::quiet_NaN();
}

void SimulationValidationTables::merge(
    const SimulationValidationTables& other) {
  if (other.bins.size() != bins.size()) {
    throw std::invalid_argument(
        "SimulationValidationTables::merge: different binnings");
  }
  for (std::size_t i = 0; i < bins.size(); ++i) {
    HitCountBin& b = bins[i];
    const HitCountBin& o = other.bins[i];
    if (b.ptMin != o.ptMin || b.ptMax != o.ptMax ||
        b.absEtaMin != o.absEtaMin || b.absEtaMax != o.absEtaMax ||
        b.displaced != o.displaced) {
      throw std::invalid_argument(
          "SimulationValidationTables::merge: different binnings");
    }
    b.particles += o.particles;
    b.realHits += o.realHits;
    b.simulatedHits += o.simulatedHits;
  }
  layers = mergeLayers(layers, other.layers);
  events += other.events;
  particles += other.particles;
  outsideBins += other.outsideBins;
  unmatched += other.unmatched;
}

SimulationValidationTables SimulationValidationTables::averageRepeats(
    std::span<const SimulationValidationTables> repeats) {
  if (repeats.empty()) {
    throw std::invalid_argument(
        "SimulationValidationTables::averageRepeats: no tables");
  }
  SimulationValidationTables total = repeats.front();
  for (const SimulationValidationTables& r : repeats.subspan(1)) {
    if (r.bins.size() != total.bins.size() || r.events != total.events ||
        r.particles != total.particles) {
      throw std::invalid_argument(
          "SimulationValidationTables::averageRepeats: not the same events");
    }
    for (std::size_t i = 0; i < total.bins.size(); ++i) {
      if (r.bins[i].particles != total.bins[i].particles ||
          r.bins[i].realHits != total.bins[i].realHits) {
        throw std::invalid_argument(
            "SimulationValidationTables::averageRepeats: not the same events");
      }
      total.bins[i].simulatedHits += r.bins[i].simulatedHits;
    }
    total.layers = mergeLayers(total.layers, r.layers);
  }
  const auto n = static_cast<double>(repeats.size());
  for (HitCountBin& b : total.bins) {
    b.simulatedHits /= n;
  }
  for (LayerHitCount& l : total.layers) {
    // mergeLayers summed the real counts too: every repeat has the same.
    l.real /= repeats.size();
    l.simulated = static_cast<std::size_t>(
        std::llround(static_cast<double>(l.simulated) / n));
  }
  return total;
}

BinAgreement binAgreement(const SimulationValidationTables& tables,
                          std::size_t minParticles, double tolerance) {
  BinAgreement result;
  for (const HitCountBin& bin : tables.bins) {
    if (bin.particles < minParticles || bin.particles == 0) {
      continue;
    }
    ++result.bins;
    // A bin without real hits but with simulated ones is off by any
    // measure; with neither it agrees.
    double d = bin.realHits > 0.0 ? bin.deviation()
               : bin.simulatedHits > 0.0
                   ? std::numeric_limits<double>::infinity()
                   : 0.0;
    if (std::abs(d) <= tolerance) {
      ++result.within;
    }
    if (std::abs(d) > std::abs(result.worst)) {
      result.worst = d;
    }
  }
  return result;
}

SimulationValidation::SimulationValidation(Config config)
    : m_config(std::move(config)) {
  const std::vector<double>& e = m_config.ptEdges;
  if (e.size() < 2 || !(e.front() >= 0.0)) {
    throw std::invalid_argument(
        "SimulationValidation: ptEdges needs at least two edges from >= 0");
  }
  for (std::size_t i = 1; i < e.size(); ++i) {
    if (!(e[i] > e[i - 1]) || std::isnan(e[i]) ||
        (std::isinf(e[i]) && i + 1 != e.size())) {
      throw std::invalid_argument(
          "SimulationValidation: ptEdges must increase strictly (only the "
          "last may be infinite)");
    }
  }
  if (!(m_config.etaBinWidth > 0.0) || !std::isfinite(m_config.etaBinWidth) ||
      !(m_config.maxAbsEta > 0.0) || !std::isfinite(m_config.maxAbsEta)) {
    throw std::invalid_argument(
        "SimulationValidation: etaBinWidth and maxAbsEta must be positive");
  }
  const double n = m_config.maxAbsEta / m_config.etaBinWidth;
  if (std::abs(n - std::round(n)) > 1e-9 * n || std::round(n) > 100.0) {
    throw std::invalid_argument(
        "SimulationValidation: maxAbsEta must be a multiple of etaBinWidth "
        "(at most 100 bins)");
  }
  m_etaBins = static_cast<std::size_t>(std::round(n));
  if (!(m_config.displacedRadius > 0.0) ||
      !std::isfinite(m_config.displacedRadius)) {
    throw std::invalid_argument(
        "SimulationValidation: displacedRadius must be positive");
  }
}

SimulationValidationTables SimulationValidation::empty() const {
  SimulationValidationTables t;
  const std::vector<double>& e = m_config.ptEdges;
  for (std::size_t p = 0; p + 1 < e.size(); ++p) {
    for (std::size_t k = 0; k < m_etaBins; ++k) {
      for (bool displaced : {false, true}) {
        HitCountBin bin;
        bin.ptMin = e[p];
        bin.ptMax = e[p + 1];
        bin.absEtaMin = static_cast<double>(k) * m_config.etaBinWidth;
        bin.absEtaMax = static_cast<double>(k + 1) * m_config.etaBinWidth;
        bin.displaced = displaced;
        t.bins.push_back(bin);
      }
    }
  }
  return t;
}

SimulationValidationTables SimulationValidation::run(
    const SimulationValidationEvent& event) const {
  SimulationValidationTables t = empty();
  t.events = 1;

  // Simulated counts by particle id.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> simulated;
  simulated.reserve(event.simulated.size());
  for (const Particle& p : event.simulated) {
    simulated.emplace_back(p.id, p.nHits);
  }
  std::sort(simulated.begin(), simulated.end());

  const std::vector<double>& edges = m_config.ptEdges;
  for (const Particle& p : event.real) {
    auto it = std::lower_bound(
        simulated.begin(), simulated.end(), p.id,
        [](const auto& entry, std::uint64_t id) { return entry.first < id; });
    if (it == simulated.end() || it->first != p.id) {
      ++t.unmatched;
      continue;
    }
    const double pt = p.pt();
    const double absEta = pt > 0.0 ? std::abs(std::asinh(p.momentum.z() / pt))
                                   : std::numeric_limits<double>::infinity();
    auto edge = std::upper_bound(edges.begin(), edges.end(), pt);
    if (!(pt > 0.0) || edge == edges.begin() || edge == edges.end() ||
        !(absEta < m_config.maxAbsEta)) {
      ++t.outsideBins;
      continue;
    }
    const auto ptBin = static_cast<std::size_t>(edge - edges.begin()) - 1;
    const auto etaBin = std::min(
        m_etaBins - 1, static_cast<std::size_t>(absEta / m_config.etaBinWidth));
    const bool displaced =
        p.vertex.head<2>().norm() >= m_config.displacedRadius;
    HitCountBin& bin =
        t.bins[(ptBin * m_etaBins + etaBin) * 2 + (displaced ? 1 : 0)];
    ++bin.particles;
    bin.realHits += p.nHits;
    bin.simulatedHits += it->second;
    ++t.particles;
  }

  t.layers = mergeLayers(countLayers(event.realHits, false),
                         countLayers(event.simulatedHits, true));
  return t;
}

}  // namespace conftrack
