#include "conftrack/evaluation/PerformanceCollector.hpp"

#include "conftrack/evaluation/ResourceUsage.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace conftrack {

namespace {

// Binnings of the distributions (native units). pT: 10 bins per decade
// from 0.1 GeV to 10^2.7 = 501 GeV ("0.1-500 GeV").
VariableAxis ptAxis() {
  return logAxis(37, 0.1 * units::GeV, std::pow(10.0, 2.7) * units::GeV);
}
VariableAxis thetaAxis() { return uniformAxis(90, 0.0, std::numbers::pi); }
VariableAxis phiAxis() {
  return uniformAxis(36, -std::numbers::pi, std::numbers::pi);
}
VariableAxis vertexRadiusAxis() {
  return uniformAxis(60, 0.0, 600.0 * units::mm);
}
// Proximity Delta R: 8 bins per decade from 1e-3 to 10.
VariableAxis proximityAxis() { return logAxis(32, 1e-3, 10.0); }
// Reconstruction time per event: 5 bins per decade from 0.01 ms to 1e6 ms.
VariableAxis timeAxis() { return logAxis(40, 1e-2, 1e6); }
VariableAxis pullAxis() { return uniformAxis(50, -5.0, 5.0); }

double polarAngle(const Vector3& p) {
  return std::atan2(p.head<2>().norm(), p.z());
}

/// The best of several matched tracks of one particle (ACTS rule: more
/// measurements, then smaller chi2/ndf, then the earlier track).
bool betterTrack(const Track& a, std::size_t ia, const Track& b,
                 std::size_t ib) {
  if (a.numMeasurements() != b.numMeasurements()) {
    return a.numMeasurements() > b.numMeasurements();
  }
  const double ca = a.ndf > 0 ? a.chi2 / a.ndf : 0.0;
  const double cb = b.ndf > 0 ? b.chi2 / b.ndf : 0.0;
  if (ca != cb) {
    return ca < cb;
  }
  return ia < ib;
}

}  // namespace

std::vector<double> PerformanceConfig::defaultResolutionPtEdges() {
  std::vector<double> edges;
  for (int k = -5; k <= 12; ++k) {
    edges.push_back(std::pow(10.0, (k + 0.5) / 4.0) * units::GeV);
  }
  return edges;
}

PerformanceConfig PerformanceConfig::singleParticleSample() {
  PerformanceConfig c;
  c.minTrackHits = 3;
  c.singleParticle = true;
  c.plotSelection.minPt = 0.0;
  c.plotSelection.minTheta = 0.0;
  c.plotSelection.maxTheta = std::numbers::pi;
  return c;
}

EfficiencyRatios& EfficiencyRatios::operator+=(const EfficiencyRatios& other) {
  all += other.all;
  ptAbove1GeV += other.ptAbove1GeV;
  ptBelow1GeV += other.ptBelow1GeV;
  return *this;
}

PerformanceData::PerformanceData()
    : efficiencyVsPt(ptAxis()),
      efficiencyVsPtAll(ptAxis()),
      efficiencyVsTheta(thetaAxis()),
      efficiencyVsPhi(phiAxis()),
      efficiencyVsVertexRadius(vertexRadiusAxis()),
      efficiencyVsProximity(proximityAxis()),
      fakeRateVsPt(ptAxis()),
      fakeRateVsTheta(thetaAxis()),
      duplicateRateVsPt(ptAxis()),
      duplicateRateVsTheta(thetaAxis()),
      reconstructionMsPerEvent(makeCountHistogram(timeAxis())) {}

void PerformanceData::merge(const PerformanceData& other) {
  events += other.events;
  eventsWithoutTruth += other.eventsWithoutTruth;
  if (other.events > 0) {
    bz = other.bz;
  }
  reconstructableParticles += other.reconstructableParticles;
  tracks += other.tracks;
  fittedTracks += other.fittedTracks;
  selectedTracks += other.selectedTracks;
  efficiency += other.efficiency;
  signalEfficiency += other.signalEfficiency;
  backgroundEfficiency += other.backgroundEfficiency;
  efficiencyThetaPlotCuts += other.efficiencyThetaPlotCuts;
  efficiencyPtPlotCuts += other.efficiencyPtPlotCuts;
  efficiencyAllPlotCuts += other.efficiencyAllPlotCuts;
  fakes += other.fakes;
  duplicates += other.duplicates;
  selectedFakes += other.selectedFakes;
  selectedDuplicates += other.selectedDuplicates;
  actsEfficiency += other.actsEfficiency;
  actsFakes += other.actsFakes;
  actsDuplicates += other.actsDuplicates;
  efficiencyVsPt += other.efficiencyVsPt;
  efficiencyVsPtAll += other.efficiencyVsPtAll;
  efficiencyVsTheta += other.efficiencyVsTheta;
  efficiencyVsPhi += other.efficiencyVsPhi;
  efficiencyVsVertexRadius += other.efficiencyVsVertexRadius;
  efficiencyVsProximity += other.efficiencyVsProximity;
  fakeRateVsPt += other.fakeRateVsPt;
  fakeRateVsTheta += other.fakeRateVsTheta;
  duplicateRateVsPt += other.duplicateRateVsPt;
  duplicateRateVsTheta += other.duplicateRateVsTheta;
  residuals.insert(residuals.end(), other.residuals.begin(),
                   other.residuals.end());
  // Floating-point sums: the caller merges in event order, so the rounding
  // is the same for any thread count.
  simulationMs += other.simulationMs;
  findingMs += other.findingMs;
  fittingMs += other.fittingMs;
  for (const StepStats& step : other.steps) {
    auto it = std::find_if(steps.begin(), steps.end(), [&](const StepStats& s) {
      return s.name == step.name;
    });
    if (it == steps.end()) {
      steps.push_back(step);
    } else {
      *it += step;
    }
  }
  reconstructionMsPerEvent += other.reconstructionMsPerEvent;
}

double PerformanceSummary::simulationMsPerEvent() const {
  return data.events > 0 ? data.simulationMs / double(data.events) : 0.0;
}
double PerformanceSummary::findingMsPerEvent() const {
  return data.events > 0 ? data.findingMs / double(data.events) : 0.0;
}
double PerformanceSummary::fittingMsPerEvent() const {
  return data.events > 0 ? data.fittingMs / double(data.events) : 0.0;
}
double PerformanceSummary::reconstructionMsPerEvent() const {
  return findingMsPerEvent() + fittingMsPerEvent();
}

PerformanceSummary summarizePerformance(const PerformanceConfig& config,
                                        const PerformanceData& data) {
  PerformanceSummary s;
  s.config = config;
  s.data = data;
  s.peakRssMb = peakRssMb();
  const std::vector<TrackResidual>& res = data.residuals;
  if (res.empty()) {
    return s;
  }

  std::vector<double> values;
  // Resolution curves: per nominal theta (folded into [0, 90 deg], the
  // detector being symmetric in z) and generated-pT bin.
  const auto& edges = config.resolutionPtEdges;
  for (double nominal : config.resolutionThetas) {
    for (std::size_t b = 0; b + 1 < edges.size(); ++b) {
      std::vector<const TrackResidual*> entries;
      double ptSum = 0.0;
      for (const TrackResidual& r : res) {
        const double folded =
            std::min(r.trueTheta, std::numbers::pi - r.trueTheta);
        if (std::abs(folded - nominal) <= config.resolutionThetaWindow &&
            r.truePt >= edges[b] && r.truePt < edges[b + 1]) {
          entries.push_back(&r);
          ptSum += r.truePt;
        }
      }
      if (entries.size() < std::max<std::size_t>(config.minFitEntries, 1)) {
        continue;
      }
      for (int q = 0; q < eNumResidualQuantities; ++q) {
        values.clear();
        for (const TrackResidual* r : entries) {
          values.push_back(r->residuals[q]);
        }
        ResolutionPoint p;
        p.quantity = static_cast<ResidualQuantity>(q);
        p.theta = nominal;
        p.ptLow = edges[b];
        p.ptHigh = edges[b + 1];
        p.ptMean = ptSum / double(entries.size());
        p.fit = fitGaussianCore(values, 2.0, config.minFitEntries);
        s.resolutions.push_back(p);
      }
    }
  }
  // Pulls over all entries.
  for (int q = 0; q < eNumPullQuantities; ++q) {
    PullResult p;
    p.quantity = static_cast<PullQuantity>(q);
    p.histogram = makeCountHistogram(pullAxis());
    values.clear();
    for (const TrackResidual& r : res) {
      if (std::isfinite(r.pulls[q])) {
        values.push_back(r.pulls[q]);
        p.histogram(r.pulls[q]);
      }
    }
    p.fit = fitGaussianCore(values, 2.0, config.minFitEntries);
    s.pulls.push_back(std::move(p));
  }
  return s;
}

PerformanceCollector::PerformanceCollector(Config config,
                                           std::size_t firstIndex)
    : m_config(std::move(config)), m_nextIndex(firstIndex) {
  if (!(m_config.matching.purity > 0.0 && m_config.matching.purity <= 1.0)) {
    throw std::invalid_argument("PerformanceCollector: purity not in (0, 1]");
  }
  if (!std::is_sorted(m_config.resolutionPtEdges.begin(),
                      m_config.resolutionPtEdges.end())) {
    throw std::invalid_argument(
        "PerformanceCollector: resolutionPtEdges not sorted");
  }
}

PerformanceData PerformanceCollector::analyseEvent(
    const Event& event, std::span<const Track> tracks, double bz,
    std::span<const StepStats> steps, const EventTimes& times) const {
  PerformanceData d;
  d.events = 1;
  d.bz = bz;
  d.simulationMs = times.simulation;
  d.findingMs = times.finding;
  d.fittingMs = times.fitting;
  d.reconstructionMsPerEvent(times.finding + times.fitting);
  for (const StepStats& step : steps) {
    auto it =
        std::find_if(d.steps.begin(), d.steps.end(),
                     [&](const StepStats& s) { return s.name == step.name; });
    if (it == d.steps.end()) {
      d.steps.push_back(step);
    } else {
      *it += step;
    }
  }
  d.tracks = tracks.size();
  for (const Track& t : tracks) {
    d.fittedTracks += t.fitted ? 1u : 0u;
    d.selectedTracks += t.hits.size() >= m_config.minTrackHits ? 1u : 0u;
  }
  if (!event.hasTruth()) {
    d.eventsWithoutTruth = 1;
    return d;
  }

  std::vector<std::vector<HitIndex>> hitLists;
  hitLists.reserve(tracks.size());
  for (const Track& t : tracks) {
    hitLists.push_back(t.hits);
  }
  const EventMatching matching =
      matchTracks(event, hitLists, m_config.particles, m_config.matching);

  const std::size_t nParticles = event.particles.size();
  // Per particle: tracks whose majority particle it is (all tracks and
  // selected tracks), ACTS-matched tracks, and the best matched track.
  std::vector<std::uint32_t> majorityAll(nParticles, 0);
  std::vector<std::uint32_t> majoritySelected(nParticles, 0);
  std::vector<std::uint32_t> actsMatched(nParticles, 0);
  std::vector<std::size_t> bestTrack(nParticles, tracks.size());
  std::vector<bool> isActsMatched(tracks.size(), false);
  const double ratio = m_config.actsMatchingRatio;
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    const TrackMatch& m = matching.tracks[i];
    if (m.particle == kInvalidIndex) {
      continue;
    }
    ++majorityAll[m.particle];
    if (tracks[i].hits.size() >= m_config.minTrackHits) {
      ++majoritySelected[m.particle];
    }
    const std::uint32_t particleHits = matching.particles[m.particle].nHits;
    isActsMatched[i] = m.purity >= ratio && particleHits > 0 &&
                       double(m.nMajority) / particleHits >= ratio;
    actsMatched[m.particle] += isActsMatched[i] ? 1u : 0u;
    if (m.matched && (bestTrack[m.particle] == tracks.size() ||
                      betterTrack(tracks[i], i, tracks[bestTrack[m.particle]],
                                  bestTrack[m.particle]))) {
      bestTrack[m.particle] = i;
    }
  }

  // Particle side: efficiencies.
  const PlotSelection& cut = m_config.plotSelection;
  for (std::size_t p = 0; p < nParticles; ++p) {
    const ParticleTruth& truth = matching.particles[p];
    if (!truth.reconstructable) {
      continue;
    }
    const Particle& particle = event.particles[p];
    const bool found = truth.nMatchedTracks > 0;
    const double pt = particle.pt();
    const double theta = polarAngle(particle.momentum);
    const double phi = std::atan2(particle.momentum.y(), particle.momentum.x());
    const double radius = particle.vertex.head<2>().norm();
    const double proximity = truth.proximity;

    EfficiencyRatios& origin =
        particle.isBackground() ? d.backgroundEfficiency : d.signalEfficiency;
    origin.all.add(found);
    (pt > 1.0 * units::GeV ? origin.ptAbove1GeV : origin.ptBelow1GeV)
        .add(found);
    // Headline efficiencies and their distributions are those of the
    // physics event's particles (paper section 5); overlay particles count
    // only in backgroundEfficiency (and, through their tracks, in the fake
    // and duplicate rates) unless includeBackground.
    if (particle.isBackground() && !m_config.includeBackground) {
      continue;
    }
    ++d.reconstructableParticles;
    d.efficiency.all.add(found);
    (pt > 1.0 * units::GeV ? d.efficiency.ptAbove1GeV
                           : d.efficiency.ptBelow1GeV)
        .add(found);
    d.actsEfficiency.add(actsMatched[p] > 0);

    const bool ptCut = pt > cut.minPt;
    const bool thetaCut = theta > cut.minTheta && theta < cut.maxTheta;
    const bool radiusCut = radius < cut.maxVertexRadius;
    const bool proximityCut = proximity > cut.minProximity;
    if (ptCut && radiusCut && proximityCut) {
      d.efficiencyThetaPlotCuts.add(found);
      d.efficiencyVsTheta.fill(theta, found);
    }
    if (thetaCut && radiusCut && proximityCut) {
      d.efficiencyPtPlotCuts.add(found);
      d.efficiencyVsPt.fill(pt, found);
    }
    if (ptCut && thetaCut && radiusCut && proximityCut) {
      d.efficiencyAllPlotCuts.add(found);
      d.efficiencyVsPhi.fill(phi, found);
    }
    if (ptCut && thetaCut && proximityCut) {
      d.efficiencyVsVertexRadius.fill(radius, found);
    }
    if (ptCut && thetaCut && radiusCut) {
      d.efficiencyVsProximity.fill(proximity, found);
    }
    d.efficiencyVsPtAll.fill(pt, found);

    if (m_config.singleParticle && bestTrack[p] < tracks.size() &&
        tracks[bestTrack[p]].fitted) {
      d.residuals.push_back(
          computeTrackResidual(tracks[bestTrack[p]], particle, bz));
    }
  }

  // Track side: fake and duplicate rates.
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    const TrackMatch& m = matching.tracks[i];
    const bool fake = !m.matched;
    const bool hasParticle = m.particle != kInvalidIndex;
    d.fakes.add(fake);
    d.duplicates.add(hasParticle && majorityAll[m.particle] > 1);
    d.actsFakes.add(!isActsMatched[i]);
    if (tracks[i].hits.size() < m_config.minTrackHits) {
      continue;
    }
    const bool duplicate = hasParticle && majoritySelected[m.particle] > 1;
    d.selectedFakes.add(fake);
    d.selectedDuplicates.add(duplicate);
    const TrackKinematics k = trackKinematics(tracks[i], event, bz);
    if (k.theta > cut.minTheta && k.theta < cut.maxTheta) {
      d.fakeRateVsPt.fill(k.pt, fake);
      d.duplicateRateVsPt.fill(k.pt, duplicate);
    }
    if (k.pt > cut.minPt) {
      d.fakeRateVsTheta.fill(k.theta, fake);
      d.duplicateRateVsTheta.fill(k.theta, duplicate);
    }
  }
  // ACTS duplicates: the matched tracks of a particle beyond the first.
  std::uint64_t extra = 0;
  for (std::uint32_t n : actsMatched) {
    extra += n > 1 ? n - 1 : 0;
  }
  d.actsDuplicates.passed = extra;
  d.actsDuplicates.total = tracks.size();
  return d;
}

void PerformanceCollector::add(std::size_t index, PerformanceData data) {
  std::lock_guard<std::mutex> lock(m_mutex);
  if (index < m_nextIndex || m_pending.count(index) > 0) {
    throw std::invalid_argument("PerformanceCollector: event index " +
                                std::to_string(index) + " given twice");
  }
  m_pending.emplace(index, std::move(data));
  // Merge the contiguous run of indices that is now complete.
  while (!m_pending.empty() && m_pending.begin()->first == m_nextIndex) {
    m_merged.merge(m_pending.begin()->second);
    m_pending.erase(m_pending.begin());
    ++m_nextIndex;
  }
}

void PerformanceCollector::addEvent(std::size_t index, const Event& event,
                                    std::span<const Track> tracks, double bz,
                                    std::span<const StepStats> steps,
                                    const EventTimes& times) {
  // The analysis runs outside the lock; only the merge is serialised.
  add(index, analyseEvent(event, tracks, bz, steps, times));
}

PerformanceSummary PerformanceCollector::summary() const {
  PerformanceData total;
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    total = m_merged;
    for (const auto& [index, data] : m_pending) {
      total.merge(data);
    }
  }
  return summarizePerformance(m_config, total);
}

}  // namespace conftrack
