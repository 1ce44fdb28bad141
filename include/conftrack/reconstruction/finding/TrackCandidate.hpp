#pragma once

/// @file TrackCandidate.hpp
/// A track candidate of the conformal finder.

#include "conftrack/reconstruction/finding/ConformalFit.hpp"
#include "conftrack/reconstruction/finding/StepStats.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace conftrack {

/// A candidate during finding: hits in conformal-hit indices, along the
/// particle's path (innermost first for prompt tracks).
struct TrackCandidate {
  std::vector<ConfIndex> hits;
  ConformalFitResult uv;
  SzFitResult sz;
  double pt = 0.0;
  /// Step that created it.
  std::uint16_t step = 0;
  bool fitBackward = false;
  /// Built by a helix step: its hits need not lie on a line or parabola in
  /// the conformal plane, so the conformal extensions leave it alone.
  bool helix = false;
  /// False once removed by the clone treatment.
  bool alive = true;
  /// Hits of the particle's further half-turns (a looper found once per
  /// half-turn; TrackMerger::dropTurns), joined to this track but in none
  /// of its fits.
  std::vector<ConfIndex> turnHits;

  /// The candidate as its build step made it, before the completion of the
  /// accepted track (inward extension, hole filling, overlap hits) added
  /// hits: its number of hits and quality(). Set while its step runs, 0
  /// after it; the clone treatment compares a new candidate of the step
  /// with these (detail::CloneIndex::offer).
  std::size_t builtHits = 0;
  double builtQuality = 0.0;

  /// chi2_uv/ndf + chi2_sz/ndf (upstream.md 7.4, linear sum).
  double quality() const { return uv.chi2PerNdf() + sz.chi2PerNdf(); }
};

}  // namespace conftrack
