#pragma once

// One synthetic event for the tests of the extension units and the hole
// filling: the hits, their conformal representation, a finder state and a
// pool of all hits, with helpers to make a track of chosen hits.

#include "conftrack/reconstruction/finding/ConformalHits.hpp"
#include "conftrack/reconstruction/finding/HitPool.hpp"
#include "conftrack/reconstruction/finding/detail/FinderState.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "SyntheticHits.hpp"

namespace conftrack::test {

/// A point of the helix of helixHits (through the origin, charge q) at
/// transverse arc length s.
inline Vector3 helixPoint(double rho, double phi0, int q, double tanL,
                          double s) {
  const double omega = q / rho;
  return Vector3((std::sin(phi0) - std::sin(phi0 - omega * s)) / omega,
                 -(std::cos(phi0) - std::cos(phi0 - omega * s)) / omega,
                 s * tanL);
}

/// Where that helix crosses radius r in its first (outgoing) half turn or,
/// with `returning`, in its second (a looper on its way back in).
inline Vector3 helixAtRadius(double rho, double phi0, int q, double tanL,
                             double r, bool returning = false) {
  const double half = M_PI * rho;
  double lo = returning ? half : 0.0;
  double hi = returning ? 2.0 * half : half;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    const bool inside =
        helixPoint(rho, phi0, q, tanL, mid).head<2>().norm() < r;
    // Outgoing the radius grows with s, returning it shrinks.
    (inside != returning ? lo : hi) = mid;
  }
  return helixPoint(rho, phi0, q, tanL, 0.5 * (lo + hi));
}

/// The event: all hits are in the pool; tracks are added by addTrack.
struct Event {
  Detector det;
  std::vector<Hit> hits;
  FinderConfig cfg;
  ConformalHits conf;
  detail::FinderState state;
  HitPool pool;
  StepStats stats;

  Event(Detector d, std::vector<Hit> h, FinderConfig c)
      : det(std::move(d)),
        hits(std::move(h)),
        cfg(std::move(c)),
        conf(makeConformalHits(hits, det)),
        state(conf, det, cfg, det.bz()),
        pool(conf, allHits(conf)) {}

  static std::vector<ConfIndex> allHits(const ConformalHits& conf) {
    std::vector<ConfIndex> all(conf.size());
    std::iota(all.begin(), all.end(), ConfIndex{0});
    return all;
  }

  /// The conformal index of the hit with this id.
  ConfIndex index(std::uint64_t id) const {
    const auto at = std::find(conf.id.begin(), conf.id.end(), id);
    EXPECT_NE(at, conf.id.end()) << "no hit " << id;
    return static_cast<ConfIndex>(at - conf.id.begin());
  }

  /// Adds a track of the hits with these ids (in this order) fitted as a
  /// candidate of step 0, its hits claimed as a build claims them; returns
  /// its index in state.tracks.
  std::uint32_t addTrack(const std::vector<std::uint64_t>& ids) {
    std::vector<ConfIndex> idx;
    for (std::uint64_t id : ids) {
      idx.push_back(index(id));
    }
    TrackCandidate track;
    EXPECT_TRUE(detail::fitCandidate(state, cfg.steps[0], idx, track));
    const auto t = static_cast<std::uint32_t>(state.tracks.size());
    for (ConfIndex h : idx) {
      state.used[h] = 1;
      state.clones.addHit(h, t);
    }
    state.tracks.push_back(std::move(track));
    return t;
  }

  /// The ids of track t's hits, in track order.
  std::vector<std::uint64_t> ids(std::uint32_t t) const {
    std::vector<std::uint64_t> out;
    for (ConfIndex h : state.tracks[t].hits) {
      out.push_back(conf.id[h]);
    }
    return out;
  }

  /// True if track t holds the hit with this id.
  bool holds(std::uint32_t t, std::uint64_t id) const {
    const std::vector<std::uint64_t> v = ids(t);
    return std::find(v.begin(), v.end(), id) != v.end();
  }
};

/// A hit of barrel layer `layer` at p moved by `offset` mm along its
/// sensor's u axis (across the track), on the sensor of p.
inline Hit shiftedHit(const Detector& det, std::uint16_t layer,
                      const Vector3& p, double offset, std::uint64_t id) {
  Hit h = barrelHit(det, layer, p.x(), p.y(), p.z(), id);
  h.position += offset * h.uAxis;
  return h;
}

}  // namespace conftrack::test
