// Catch-all extension (detail/CatchAllExtension.hpp).

#include "conftrack/reconstruction/finding/detail/CatchAllExtension.hpp"

namespace conftrack::detail {

CatchAllExtension::Config CatchAllExtension::Config::fromStep(
    const FindingStep& step, const FinderConfig& finder) {
  Config c;
  c.cuts = ExtensionCuts::fromStep(step, finder);
  return c;
}

CatchAllExtension::CatchAllExtension(const Config& config) : m_config(config) {
  m_config.cuts.validate("CatchAllExtension");
  m_rules.direction = Direction::eOutward;
  m_rules.branches = Branches::eWholeTurn;
  m_rules.angleFactor = 3.0;
  m_rules.sameZSide = true;
  m_rules.radiusOrdered = false;
  m_rules.scatteringAllowance = false;
}

void CatchAllExtension::run(FinderState& state, const HitPool& pool,
                            StepStats& stats, std::uint32_t t) const {
  followTrack(state, pool, stats, t, m_config.cuts, m_rules, m_work);
}

}  // namespace conftrack::detail
