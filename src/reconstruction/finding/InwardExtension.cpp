// Inward extension of newly built tracks (detail/InwardExtension.hpp).

#include "conftrack/reconstruction/finding/detail/InwardExtension.hpp"

namespace conftrack::detail {

InwardExtension::Config InwardExtension::Config::fromStep(
    const FindingStep& step, const FinderConfig& finder) {
  Config c;
  c.cuts = ExtensionCuts::fromStep(step, finder);
  c.scatteringAllowance = finder.inwardScatteringAllowance;
  return c;
}

InwardExtension::InwardExtension(const Config& config) : m_config(config) {
  m_config.cuts.validate("InwardExtension");
  m_rules.direction = Direction::eInward;
  m_rules.branches = Branches::eOutgoing;
  m_rules.angleFactor = 3.0;
  m_rules.sameZSide = false;
  m_rules.radiusOrdered = true;
  m_rules.scatteringAllowance = m_config.scatteringAllowance;
}

void InwardExtension::run(FinderState& state, const HitPool& pool,
                          StepStats& stats, std::uint32_t t) const {
  followTrack(state, pool, stats, t, m_config.cuts, m_rules, m_work);
}

}  // namespace conftrack::detail
