#pragma once

/// @file ClicdetParticles.hpp
/// Single particles through CLICdet for the tests of the stages after the
/// fit (SplitTrackMerger, HitReassigner): a pion, the event of a few
/// particles and each particle's hits in path order.

#include "conftrack/core/Random.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/fitting/KalmanFitter.hpp"
#include "conftrack/simulation/Simulator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace conftrack::test {

inline const Detector& clicdetDetector() {
  static const Detector detector = loadDetector("clicdet");
  return detector;
}

/// The Kalman fitter of CLICdet with its defaults.
inline const KalmanFitter& clicdetFitter() {
  static const KalmanFitter fitter(clicdetDetector());
  return fitter;
}

/// A pion of charge `charge` and transverse momentum `pt` [GeV] at
/// azimuth `phi` and polar angle `theta` from `vertex` [mm].
inline Particle pion(std::uint64_t id, double pt, double phi, double theta,
                     const Vector3& vertex = Vector3::Zero(),
                     double charge = 1.0) {
  Particle p;
  p.id = id;
  p.pdg = charge > 0.0 ? 211 : -211;
  p.charge = charge;
  p.vertex = vertex;
  p.momentum =
      Vector3(pt * std::cos(phi), pt * std::sin(phi), pt / std::tan(theta));
  return p;
}

/// The CLICdet event of `particles` (simulation stream of `seed`) and each
/// particle's hit indices in the order of their times (the path order).
struct SimulatedParticles {
  Event event;
  std::vector<std::vector<HitIndex>> byParticle;
};

inline SimulatedParticles simulateInClicdet(
    const std::vector<Particle>& particles, std::uint64_t seed) {
  SimulatedParticles s;
  RandomEngine rng = makeEngine(seed, 0, RandomStream::eSimulation);
  Simulator(clicdetDetector()).simulate(particles, rng, s.event);
  s.byParticle.resize(particles.size());
  for (std::size_t p = 0; p < particles.size(); ++p) {
    for (HitIndex h = 0; h < s.event.hits.size(); ++h) {
      if (s.event.truth[h].particleId == particles[p].id) {
        s.byParticle[p].push_back(h);
      }
    }
    std::sort(s.byParticle[p].begin(), s.byParticle[p].end(),
              [&](HitIndex a, HitIndex b) {
                return s.event.truth[a].time < s.event.truth[b].time;
              });
  }
  return s;
}

}  // namespace conftrack::test
