#pragma once

/// @file HepMC3Generator.hpp
/// Events replayed from a HepMC text file (Asciiv3 or IO_GenEvent, plain or
/// gzip-compressed), read with the HepMC3 library.

#include "conftrack/simulation/LuminousRegion.hpp"
#include "conftrack/simulation/generators/EventGenerator.hpp"
#include "conftrack/simulation/generators/HepMCText.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace conftrack {

/// Replays the events of a HepMC file.
///
/// All events are read at construction (the files are small), so that
/// generate() is a pure lookup: event number n gives file event
/// n % numEvents(), independent of thread scheduling. The random engine is
/// used only with a luminous region (below). Reading: the file is loaded into
/// memory (gzip detected by its magic bytes and inflated with zlib), the format
/// is taken from its START_EVENT_LISTING line, the text is validated by
/// hepmc::validate() (which rejects everything known to crash the HepMC3 3.1.2
/// readers), and then parsed by HepMC3::ReaderAscii or ReaderAsciiHepMC2 from
/// an std::istringstream. read_event() is called exactly once per event found
/// by the validator and each event's particle count is checked, so the last
/// event of a file without END_EVENT_LISTING is kept (the reader returns it
/// complete even though it then reports end of input): sk_example_HS gives
/// 25 events, sk_example_PU 100.
///
/// Particles: every status-1 particle (neutral ones too) with its
/// production vertex (the nearest ancestor vertex with a position, as
/// HepMC3 defines it) converted from the file's units (GeV/MeV, mm/cm) to
/// GeV and mm, time = c t / c in ns, charge from the PDG code
/// (pdg::charge), ids 1..n in file order, parentId 0, origin eSignal.
///
/// Luminous region: unset (the default), the file's vertices are kept. Set,
/// every event is moved by one interaction point drawn from the region
/// (added to all its particles' positions and times, as the vertex
/// smearing of ddsim), after the maxProductionRadius cut on the file's
/// positions. A file event holding several interactions moves as a whole.
class HepMC3Generator final : public EventGenerator {
 public:
  /// Configuration.
  struct Config {
    /// The HepMC file.
    std::string path;
    /// Particles produced at a larger transverse radius [mm] are dropped
    /// (e.g. decay products of long-lived particles beyond the tracker);
    /// infinite by default (keep all).
    double maxProductionRadius = std::numeric_limits<double>::infinity();
    /// If set, events are moved by a vertex drawn from this region.
    std::optional<LuminousRegion::Config> luminousRegion = std::nullopt;
  };

  /// Reads and validates the whole file; throws InputError with a one-line
  /// message if it is missing, empty, truncated, of unknown format or
  /// malformed.
  explicit HepMC3Generator(const Config& config);

  /// "HepMC3(<path>)".
  std::string name() const override;
  /// The configuration.
  const Config& config() const { return m_cfg; }
  /// The file's format.
  hepmc::Format format() const { return m_format; }
  /// Number of events in the file (>= 1).
  std::size_t numEvents() const { return m_events.size(); }
  /// Event i (0-based, i < numEvents()).
  const std::vector<Particle>& eventAt(std::size_t i) const {
    return m_events.at(i);
  }

 private:
  std::vector<Particle> doGenerate(RandomEngine& rng,
                                   std::uint64_t eventNumber) const override;

  Config m_cfg;
  std::optional<LuminousRegion> m_region;
  hepmc::Format m_format = hepmc::Format::eUnknown;
  std::vector<std::vector<Particle>> m_events;
};

/// Reads all events of HepMC text already in memory (validation, then the
/// HepMC3 reader). `source` names the input in error messages. Used by
/// HepMC3Generator and by tests with hand-made records.
std::vector<std::vector<Particle>> readHepMCEvents(
    std::string_view text, const std::string& source,
    double maxProductionRadius = std::numeric_limits<double>::infinity());

}  // namespace conftrack
