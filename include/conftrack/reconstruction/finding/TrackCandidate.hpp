#pragma once

/// @file TrackCandidate.hpp
/// A track candidate of the conformal finder, and the per-step counters.

#include "conftrack/reconstruction/finding/ConformalFit.hpp"

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

  /// chi2_uv/ndf + chi2_sz/ndf (algorithm.md 7.4, linear sum).
  double quality() const { return uv.chi2PerNdf() + sz.chi2PerNdf(); }
};

/// Counters and time of one finding step (instrumentation).
struct StepStats {
  std::string name;
  std::uint64_t seeds = 0;          ///< seed hits processed
  std::uint64_t cells = 0;          ///< cells created
  std::uint64_t paths = 0;          ///< paths enumerated
  std::uint64_t candidates = 0;     ///< candidates passing the chi2 cuts
  std::uint64_t accepted = 0;       ///< tracks added (net of clones)
  std::uint64_t extendedHits = 0;   ///< hits added by extensions
  std::uint64_t hitsUsed = 0;       ///< hits marked used at the end of step
  std::uint64_t pathOverflows = 0;  ///< seeds hitting maxPathsPerSeed
  std::uint64_t cellOverflows = 0;  ///< seeds hitting maxCellsPerSeed
  std::uint64_t recovered = 0;      ///< candidates saved by the recovery
  double milliseconds = 0.0;

  StepStats& operator+=(const StepStats& o);
};

}  // namespace conftrack
