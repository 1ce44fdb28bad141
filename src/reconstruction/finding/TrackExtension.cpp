// Outward per-layer extension (detail/TrackExtension.hpp).

#include "conftrack/reconstruction/finding/detail/TrackExtension.hpp"

namespace conftrack::detail {

TrackExtension::Config TrackExtension::Config::fromStep(
    const FindingStep& step, const FinderConfig& finder) {
  Config c;
  c.cuts = ExtensionCuts::fromStep(step, finder);
  c.scatteringAllowance = finder.scatteringAllowance;
  return c;
}

TrackExtension::TrackExtension(const Config& config) : m_config(config) {
  m_config.cuts.validate("TrackExtension");
  m_rules.direction = Direction::eOutward;
  m_rules.branches = Branches::eOutgoing;
  m_rules.angleFactor = 1.0;
  m_rules.sameZSide = false;
  m_rules.radiusOrdered = true;
  m_rules.scatteringAllowance = m_config.scatteringAllowance;
}

void TrackExtension::run(FinderState& state, const HitPool& pool,
                         StepStats& stats, std::uint32_t t) const {
  followTrack(state, pool, stats, t, m_config.cuts, m_rules, m_work);
}

}  // namespace conftrack::detail
