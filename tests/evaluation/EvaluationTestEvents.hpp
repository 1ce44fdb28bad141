#pragma once

// Hand-made events and tracks for the evaluation tests (no simulation).

#include "conftrack/core/Event.hpp"
#include "conftrack/core/Track.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/evaluation/PerformanceCollector.hpp"
#include "conftrack/evaluation/TrackResiduals.hpp"
#include "conftrack/reconstruction/finding/TrackCandidate.hpp"

#include <cmath>
#include <random>
#include <vector>

namespace conftrack::test {

inline Particle makeParticle(std::uint64_t id, const Vector3& momentum,
                             double charge = -1.0,
                             ParticleOrigin origin = ParticleOrigin::eSignal,
                             const Vector3& vertex = Vector3::Zero()) {
  Particle p;
  p.id = id;
  p.pdg = charge < 0 ? 13 : -13;
  p.charge = charge;
  p.momentum = momentum;
  p.vertex = vertex;
  p.origin = origin;
  return p;
}

/// Adds `particle` and `nLayers` hits on distinct layers along its
/// direction (straight line, transverse radius 30 + 40 l mm); returns the
/// hit indices. Particles must be added in increasing id.
inline std::vector<HitIndex> addParticle(Event& event, const Particle& particle,
                                         int nLayers) {
  event.particles.push_back(particle);
  std::vector<HitIndex> hits;
  const Vector3 dir = particle.momentum.normalized();
  const double sinTheta = std::max(dir.head<2>().norm(), 1e-3);
  for (int l = 0; l < nLayers; ++l) {
    Hit h;
    h.id = event.hits.size() + 1;
    h.position = particle.vertex + dir * ((30.0 + 40.0 * l) / sinTheta);
    h.detId.subdetector = 0;
    h.detId.layer = static_cast<std::uint16_t>(l);
    HitTruth t;
    t.particleId = particle.id;
    t.position = h.position;
    t.momentum = particle.momentum;
    hits.push_back(static_cast<HitIndex>(event.hits.size()));
    event.hits.push_back(h);
    event.truth.push_back(t);
  }
  return hits;
}

/// Adds `n` noise hits (particle id 0) at radius 500 mm.
inline std::vector<HitIndex> addNoise(Event& event, int n) {
  std::vector<HitIndex> hits;
  for (int i = 0; i < n; ++i) {
    Hit h;
    h.id = event.hits.size() + 1;
    h.position =
        Vector3(500.0 * std::cos(0.3 * i), 500.0 * std::sin(0.3 * i), 10.0 * i);
    h.detId.subdetector = 1;
    h.detId.layer = static_cast<std::uint16_t>(i);
    hits.push_back(static_cast<HitIndex>(event.hits.size()));
    event.hits.push_back(h);
    event.truth.push_back(HitTruth{});
  }
  return hits;
}

/// An unfitted track of these hits with a finder pT estimate.
inline Track makeTrack(std::vector<HitIndex> hits, double ptEstimate) {
  Track t;
  t.hits = std::move(hits);
  t.outlier.assign(t.hits.size(), 0);
  t.ptEstimate = ptEstimate;
  return t;
}

/// Concatenates the first n of a and the first m of b.
inline std::vector<HitIndex> take(const std::vector<HitIndex>& a, std::size_t n,
                                  const std::vector<HitIndex>& b = {},
                                  std::size_t m = 0) {
  std::vector<HitIndex> out(a.begin(), a.begin() + n);
  out.insert(out.end(), b.begin(), b.begin() + m);
  return out;
}

struct EventWithTracks {
  Event event;
  std::vector<Track> tracks;
};

/// The reference event of the counting tests:
///  P1 signal pT 5 GeV, theta 90 deg, 6 layers      reconstructable
///  P2 signal pT 0.5 GeV, 5 layers                  reconstructable
///  P3 background pT 2 GeV, R_vtx = 100 mm, 5 layers reconstructable
///  P4 signal pT 0.05 GeV, 4 layers                 too soft
///  P5 signal pT 3 GeV, 3 layers                    too few layers
///  P6 neutral, no hits
///  4 noise hits.
/// Tracks:
///  T0 = P1 x6              pure (1.0)
///  T1 = P1 x4 + P2 x1      pure (0.8), duplicate of T0
///  T2 = P2 x3 + P3 x1      pure (0.75, the boundary)
///  T3 = P3 x2 + noise x2   fake (0.5)
///  T4 = noise x3           fake, 3 hits (below minTrackHits = 4)
inline EventWithTracks referenceEvent() {
  EventWithTracks out;
  Event& e = out.event;
  e.number = 7;
  auto p1 = addParticle(e, makeParticle(1, Vector3(5.0, 0.0, 0.0)), 6);
  auto p2 = addParticle(e, makeParticle(2, Vector3(0.0, 0.5, 0.1), 1.0), 5);
  auto p3 = addParticle(
      e,
      makeParticle(3, Vector3(-2.0, 0.0, 1.0), -1.0,
                   ParticleOrigin::eBackground, Vector3(-100.0, 0.0, 0.0)),
      5);
  addParticle(e, makeParticle(4, Vector3(0.03, 0.04, 0.0)), 4);
  addParticle(e, makeParticle(5, Vector3(0.0, -3.0, 0.0)), 3);
  Particle neutral = makeParticle(6, Vector3(1.0, 1.0, 0.0), 0.0);
  neutral.pdg = 22;
  e.particles.push_back(neutral);
  auto noise = addNoise(e, 4);
  e.sortParticles();

  out.tracks.push_back(makeTrack(p1, 5.1));
  out.tracks.push_back(makeTrack(take(p1, 4, p2, 1), 4.9));
  out.tracks.push_back(makeTrack(take(p2, 3, p3, 1), 0.5));
  out.tracks.push_back(makeTrack(take(p3, 2, noise, 2), 2.0));
  out.tracks.push_back(makeTrack(take(noise, 3), 0.3));
  return out;
}

/// Resolutions assumed for the synthetic fitted muon tracks, per LCIO
/// parameter.
inline TrackVector muonSigmas(double ptGeV) {
  TrackVector s;
  const double ms = 1.0 + 2.0 / ptGeV;  // a multiple-scattering-like term
  s[eD0] = 5e-3 * ms;
  s[ePhi0] = 1e-4 * ms;
  s[eOmega] = 2e-8 * ms;
  s[eZ0] = 8e-3 * ms;
  s[eTanLambda] = 2e-4 * ms;
  return s;
}

/// One muon at (thetaDeg, ptGeV) from the origin with a fitted track whose
/// parameters are the truth smeared by muonSigmas() and whose covariance is
/// diag(muonSigmas()^2): pulls are N(0, 1).
inline EventWithTracks muonEvent(std::uint64_t number, double thetaDeg,
                                 double ptGeV, double bz, std::mt19937_64& rng,
                                 std::uint16_t findingStep = 0) {
  EventWithTracks out;
  Event& e = out.event;
  e.number = number;
  std::uniform_real_distribution<double> flat(-3.14, 3.14);
  const double phi = flat(rng);
  const double theta = thetaDeg * units::degree;
  const Vector3 p(ptGeV * std::cos(phi), ptGeV * std::sin(phi),
                  ptGeV / std::tan(theta));
  const Particle muon = makeParticle(1, p, -1.0);
  auto hits = addParticle(e, muon, 6);
  Track t = makeTrack(hits, ptGeV);
  t.findingStep = findingStep;
  t.fitted = true;
  t.chi2 = 5.0;
  t.ndf = 7;
  const TrackVector truth = trueTrackParameters(muon, bz);
  const TrackVector sigma = muonSigmas(ptGeV);
  std::normal_distribution<double> gauss(0.0, 1.0);
  t.atIp.parameters = truth;
  for (int i = 0; i < 5; ++i) {
    t.atIp.parameters[i] += sigma[i] * gauss(rng);
    t.atIp.covariance(i, i) = sigma[i] * sigma[i];
  }
  out.tracks.push_back(t);
  return out;
}

inline std::vector<StepStats> twoSteps(double ms0, double ms1) {
  StepStats a;
  a.name = "vertex_barrel";
  a.seeds = 10;
  a.accepted = 2;
  a.milliseconds = ms0;
  StepStats b;
  b.name = "displaced";
  b.seeds = 3;
  b.accepted = 1;
  b.milliseconds = ms1;
  return {a, b};
}

/// A mixed run: reference events, muon events and random times whose
/// floating-point sums depend on the order of addition.
inline std::vector<PerformanceData> mixedRun(
    const PerformanceCollector& collector, std::size_t n) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> ms(0.1, 1000.0);
  std::vector<PerformanceData> out;
  for (std::size_t i = 0; i < n; ++i) {
    EventWithTracks e =
        i % 3 == 0 ? referenceEvent() : muonEvent(i, 30.0, 10.0, 4.0, rng);
    const auto steps = twoSteps(ms(rng), ms(rng));
    out.push_back(collector.analyseEvent(
        e.event, e.tracks, 4.0, steps, EventTimes{ms(rng), ms(rng), ms(rng)}));
  }
  return out;
}

}  // namespace conftrack::test
