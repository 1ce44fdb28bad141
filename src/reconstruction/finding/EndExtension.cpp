// The final extension of every track's end (detail/EndExtension.hpp).

#include "conftrack/reconstruction/finding/detail/EndExtension.hpp"

#include <cmath>
#include <vector>

namespace conftrack::detail {

EndExtension::Config EndExtension::Config::fromStep(
    const FindingStep& step, const FinderConfig& finder) {
  Config c;
  c.cuts = ExtensionCuts::fromStep(step, finder);
  c.cuts.phiWindow = finder.finalExtensionPhiWindow;
  c.angleFactor = finder.finalExtensionAngleFactor;
  return c;
}

EndExtension::EndExtension(const Config& config) : m_config(config) {
  // The window is the final extension's own key; the rest are the step's
  // and the finder's.
  m_config.cuts.validate("EndExtension", "final_extension_phi_window");
  if (m_config.minHits < 3) {
    throwBadKey("EndExtension", "minHits", "must be at least 3",
                static_cast<double>(m_config.minHits));
  }
  if (!(std::isfinite(m_config.angleFactor) && m_config.angleFactor >= 1.0)) {
    throwBadKey("EndExtension", "final_extension_angle_factor",
                "must be finite and at least 1", m_config.angleFactor);
  }
  m_rules.direction = Direction::eOutward;
  m_rules.branches = Branches::eOutgoing;
  m_rules.angleFactor = m_config.angleFactor;
  m_rules.sameZSide = false;
  m_rules.radiusOrdered = true;
  // Where the steps' cuts failed, the track's direction at its last hit is
  // what scattering changed: allow for it in the chi2 of the nearest
  // crossing (five TrackML events: +0.0002 at both lengths).
  m_rules.scatteringAllowance = true;
}

void EndExtension::run(FinderState& state, const HitPool& pool,
                       StepStats& stats, std::uint32_t t) const {
  if (state.tracks[t].hits.size() < m_config.minHits) {
    return;
  }
  followTrack(state, pool, stats, t, m_config.cuts, m_rules, m_work);
}

void extendTrackEnds(FinderState& state, const HitPool& pool,
                     StepStats& stats) {
  // One unit per step: each track is extended with the cuts of the step
  // that built it.
  std::vector<EndExtension> units;
  units.reserve(state.config.steps.size());
  for (const FindingStep& step : state.config.steps) {
    units.emplace_back(EndExtension::Config::fromStep(step, state.config));
  }
  for (std::uint32_t t = 0; t < state.tracks.size(); ++t) {
    if (state.tracks[t].alive) {
      units[state.tracks[t].step].run(state, pool, stats, t);
    }
  }
}

}  // namespace conftrack::detail
