#pragma once

/// @file GeneratorTestUtils.hpp
/// Helpers shared by the event-generator tests (GeneratorTests.cpp,
/// TtbarGeneratorTests.cpp): random streams, four-momenta, the
/// generator-level reconstructable selection, particle comparison and the
/// output and input-error contracts of the generators.

#include "conftrack/core/Error.hpp"
#include "conftrack/core/Particle.hpp"
#include "conftrack/core/PdgTable.hpp"
#include "conftrack/core/Random.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/simulation/generators/Kinematics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace conftrack::test {

using namespace conftrack::units;

inline RandomEngine engine(std::uint64_t event, std::uint64_t seed = 42) {
  return makeEngine(seed, event, RandomStream::eSignalGenerator);
}

inline FourMomentum fourMomentum(const Particle& p) {
  return FourMomentum::fromMass(p.momentum, pdg::massOf(p.pdg));
}

inline double cosTheta(const Particle& p) {
  return p.momentum.z() / p.momentum.norm();
}

/// Generator-level "reconstructable": stable, charged, pT > 0.1 GeV,
/// |cos theta| < 0.99 (evaluation.md A1 without the hit requirement).
inline bool reconstructableAtGeneratorLevel(const Particle& p) {
  return p.isStable() && p.charge != 0.0 && p.pt() > 0.1 * GeV &&
         std::abs(cosTheta(p)) < 0.99;
}

inline bool identical(const Particle& a, const Particle& b) {
  return a.id == b.id && a.pdg == b.pdg && a.status == b.status &&
         a.charge == b.charge && a.vertex == b.vertex && a.time == b.time &&
         a.momentum == b.momentum && a.parentId == b.parentId &&
         a.origin == b.origin && a.nHits == b.nHits;
}

inline bool identical(const std::vector<Particle>& a,
                      const std::vector<Particle>& b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(),
                    [](const Particle& x, const Particle& y) {
                      return identical(x, y);
                    });
}

/// The output contract of EventGenerator: ids 1..n, parents earlier.
inline void expectWellFormed(const std::vector<Particle>& particles) {
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Particle& p = particles[i];
    ASSERT_EQ(p.id, i + 1);
    ASSERT_LT(p.parentId, p.id);
    if (p.parentId != 0) {
      ASSERT_EQ(particles[p.parentId - 1].status, 2);
    }
    ASSERT_TRUE(p.vertex.allFinite());
    ASSERT_TRUE(p.momentum.allFinite());
    ASSERT_TRUE(std::isfinite(p.time));
    ASSERT_EQ(p.charge, pdg::charge(p.pdg)) << "pdg " << p.pdg;
  }
}

template <typename Generator>
void expectInputError(const typename Generator::Config& cfg,
                      const std::string& field) {
  try {
    Generator gen(cfg);
    FAIL() << "expected InputError for " << field;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'" + field + "'"), std::string::npos)
        << e.what();
  }
}

}  // namespace conftrack::test
