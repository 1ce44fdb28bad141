/// @file HepMCCanonicalTextTests.cpp
/// The HepMC3 3.1.2 readers are given the validator's re-printing of a file
/// (TextSummary::canonical), never the file itself: it must carry
/// everything conftrack reads (the stable particles' PDG codes, momenta and
/// production positions, the units) and nothing of the auxiliary records
/// where the fuzzers found the readers' crashes (weights, names,
/// attributes, tool, cross-section, heavy-ion and PDF lines).

#include "conftrack/simulation/generators/HepMCText.hpp"

#include <HepMC3/GenEvent.h>
#include <HepMC3/GenParticle.h>
#include <HepMC3/GenVertex.h>
#include <HepMC3/ReaderAscii.h>
#include <HepMC3/ReaderAsciiHepMC2.h>
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace conftrack {
namespace {

const std::filesystem::path kHepMCDir =
    std::filesystem::path(CONFTRACK_TEST_DATA_DIR) / "hepmc";

/// What conftrack takes from a stable particle, as the library gives it.
struct StableParticle {
  int pdg = 0;
  std::array<double, 4> momentum{};
  std::array<double, 4> production{};
  bool operator==(const StableParticle&) const = default;
};

/// The first `count` events of `text` as the HepMC3 reader of `format`
/// reads them: units and stable particles (fewer if a read fails; as
/// readHepMCEvents, never a read past the last event).
std::vector<std::pair<std::string, std::vector<StableParticle>>> readDirectly(
    const std::string& text, hepmc::Format format, std::size_t count) {
  std::istringstream in(text);
  std::unique_ptr<HepMC3::Reader> reader;
  if (format == hepmc::Format::eAsciiV3) {
    reader = std::make_unique<HepMC3::ReaderAscii>(in);
  } else {
    reader = std::make_unique<HepMC3::ReaderAsciiHepMC2>(in);
  }
  std::vector<std::pair<std::string, std::vector<StableParticle>>> events;
  for (std::size_t i = 0; i < count; ++i) {
    HepMC3::GenEvent event;
    if (!reader->read_event(event) || event.particles().empty()) {
      break;
    }
    std::string units = HepMC3::Units::name(event.momentum_unit()) + " " +
                        HepMC3::Units::name(event.length_unit());
    std::vector<StableParticle> stable;
    for (const auto& p : event.particles()) {
      if (p->status() != 1) {
        continue;
      }
      StableParticle s;
      s.pdg = p->pid();
      const HepMC3::FourVector& m = p->momentum();
      s.momentum = {m.px(), m.py(), m.pz(), m.e()};
      if (auto v = p->production_vertex()) {
        const HepMC3::FourVector x = v->position();
        s.production = {x.x(), x.y(), x.z(), x.t()};
      }
      stable.push_back(s);
    }
    events.emplace_back(std::move(units), std::move(stable));
  }
  return events;
}

TEST(HepMCCanonicalText, ReaderGetsTheSameParticlesAsFromTheFile) {
  for (const char* name :
       {"g4pythia.hepmc.gz", "inputConvert1.hepmc.gz", "inputIO6.hepmc.gz",
        "sk_example_HS.hepmc.gz", "sk_example_PU.hepmc.gz"}) {
    SCOPED_TRACE(name);
    const std::string text = hepmc::loadFile(kHepMCDir / name);
    const hepmc::TextSummary summary = hepmc::validate(text, name);
    const auto original = readDirectly(text, summary.format, summary.numEvents);
    const auto canonical =
        readDirectly(summary.canonical, summary.format, summary.numEvents);
    ASSERT_EQ(original.size(), summary.numEvents);
    ASSERT_EQ(canonical.size(), original.size());
    std::size_t stable = 0;
    for (std::size_t e = 0; e < original.size(); ++e) {
      EXPECT_EQ(canonical[e].first, original[e].first) << "event " << e;
      EXPECT_TRUE(canonical[e].second == original[e].second) << "event " << e;
      stable += original[e].second.size();
    }
    EXPECT_GT(stable, 0U);
    // The canonical text is the smaller one: it drops records.
    EXPECT_LT(summary.canonical.size(), text.size());
  }
}

TEST(HepMCCanonicalText, AuxiliaryRecordsAreDroppedAndNumbersReprinted) {
  const std::string ioGenEvent =
      "HepMC::Version 2.06.09\r\n"
      "HepMC::IO_GenEvent-START_EVENT_LISTING\r\n"
      "E 7 3 91.2 0.118 0.0078 11 -3 2 1 2 2 123 456 2 0.5 2.5\r\n"
      "N 2 \"a b\" \"c\"\r\n"
      "U MEV CM\r\n"
      "C 1.5 0.1\r\n"
      "V -1 5 0 0 0 0 2 1 1 0.25\r\n"
      "P 1 11 0 0 1000 1000 0.511 4 0.1 0.2 -1 1 1 501\r\n"
      "P 2 -11 0 0 -1000 1000 0.511 4 0 0 -1 0\r\n"
      "P 3 23 0 0 0 2000.000000000000000001 2000 2 0 0 -2 0\r\n"
      "V -2 0 1e0 2 3 30 0 2 0\r\n"
      "P 4 13 500 0 0 510 105.7 1 0 0 0 0\r\n"
      "P 5 -13 -500 0 0 510 105.7 1 0 0 0 0\r\n"
      "HepMC::IO_GenEvent-END_EVENT_LISTING\r\n";
  EXPECT_EQ(hepmc::validate(ioGenEvent, "a.hepmc").canonical,
            "HepMC::Version 3.1.2\n"
            "HepMC::IO_GenEvent-START_EVENT_LISTING\n"
            "E 7 -1 0 0 0 0 0 2 0 0 0 0\n"
            "U MEV CM\n"
            "V -1 5 0 0 0 0 2 1 0\n"
            "P 1 11 0 0 1000 1000 0.511 4 0 0 -1 0\n"
            "P 2 -11 0 0 -1000 1000 0.511 4 0 0 -1 0\n"
            "P 3 23 0 0 0 2000 2000 2 0 0 -2 0\n"
            "V -2 0 1 2 3 30 0 2 0\n"
            "P 4 13 500 0 0 510 105.7 1 0 0 0 0\n"
            "P 5 -13 -500 0 0 510 105.7 1 0 0 0 0\n"
            "HepMC::IO_GenEvent-END_EVENT_LISTING\n");

  const std::string asciiV3 =
      "HepMC::Version 3.02.01\n"
      "HepMC::Asciiv3-START_EVENT_LISTING\n"
      "W Weight Other\n"
      "T Pythia\\|8.3\\|generator\n"
      "A 0 GenCrossSection 1.0 0.1 -1 -1\n"
      "E 3 2 4 @ 0 0 1.50 0\n"
      "U GEV MM\n"
      "W 1.0 2.0\n"
      "A 0 signal_process_id 11\n"
      "P 1 0 2212 0 0 7000 7000 0.938 4\n"
      "P 2 0 2212 0 0 -7000 7000 0.938 4\n"
      "V -1 0 [1,2] @ 0.1 0.2 0.3 0.4\n"
      "P 3 -1 211 1.0 0 0 1.0096 0.1396 1\n"
      "V -2 0 [3]\n"
      "P 4 -2 -211 0 2 0 2.005 0.1396 1\n"
      "HepMC::Asciiv3-END_EVENT_LISTING\n";
  EXPECT_EQ(hepmc::validate(asciiV3, "b.hepmc").canonical,
            "HepMC::Version 3.1.2\n"
            "HepMC::Asciiv3-START_EVENT_LISTING\n"
            "E 3 2 4 @ 0 0 1.5 0\n"
            "U GEV MM\n"
            "P 1 0 2212 0 0 7000 7000 0.938 4\n"
            "P 2 0 2212 0 0 -7000 7000 0.938 4\n"
            "V -1 0 [1,2] @ 0.1 0.2 0.3 0.4\n"
            "P 3 -1 211 1 0 0 1.0096 0.1396 1\n"
            "V -2 0 [3]\n"
            "P 4 -2 -211 0 2 0 2.005 0.1396 1\n"
            "HepMC::Asciiv3-END_EVENT_LISTING\n");
}

}  // namespace
}  // namespace conftrack
