#pragma once

/// @file LuminousRegion.hpp
/// Where the interactions of a collider take place: the luminous region, a
/// Gaussian in (x, y, z, t), with named presets per machine. The presets,
/// their sources and which numbers are unverified: docs/luminous-region.md.

#include "conftrack/core/Random.hpp"
#include "conftrack/core/Types.hpp"

#include <optional>
#include <random>
#include <span>
#include <string>
#include <string_view>

namespace conftrack {

/// The distribution of the primary interaction points of a machine.
///
/// Each coordinate is an independent Gaussian around the mean position and
/// time (no tilt, no x-z correlation from a crossing angle). A generator
/// draws one vertex per interaction: all primary particles of that
/// interaction share it, and every pile-up or overlay interaction draws its
/// own.
///
/// Random numbers: sample() draws the standard normals in the order z, x,
/// y, t and draws none for an axis of zero width. A region with only a
/// length (preset clic3tev) therefore takes exactly one normal number per
/// vertex, as conftrack's generators did before the region existed, so
/// that their events did not change.
class LuminousRegion {
 public:
  /// Mean and widths; all widths 0 is a point.
  struct Config {
    /// Mean interaction point [mm].
    Vector3 position = Vector3::Zero();
    /// Mean interaction time [ns].
    double time = 0.0;
    /// Gaussian sigma of x [mm].
    double sigmaX = 0.0;
    /// Gaussian sigma of y [mm].
    double sigmaY = 0.0;
    /// Gaussian sigma of z [mm] (the length of the luminous region).
    double sigmaZ = 0.0;
    /// Gaussian sigma of the interaction time [ns].
    double sigmaT = 0.0;
  };

  /// A drawn interaction point.
  struct Vertex {
    /// Position [mm].
    Vector3 position = Vector3::Zero();
    /// Time [ns].
    double time = 0.0;
  };

  /// A named region of one machine.
  struct Preset {
    /// Name used in files and on the command line, e.g. "clic3tev".
    std::string_view name;
    /// The machine and its running point, e.g. "CLIC, 3 TeV".
    std::string_view machine;
    /// The region.
    Config config;
    /// Short reference of the numbers (details in docs/luminous-region.md).
    std::string_view source;
  };

  /// Largest accepted |mean position| per axis and width [mm].
  static constexpr double kMaxLength = 1000.0;
  /// Largest accepted |mean time| and time width [ns].
  static constexpr double kMaxTime = 1e6;

  /// Validates the configuration: every field finite, widths >= 0, means
  /// and widths below kMaxLength (kMaxTime for times). Throws InputError
  /// "LuminousRegion: config field 'sigmaZ': ..." naming the bad field.
  explicit LuminousRegion(const Config& config);

  /// The configuration.
  const Config& config() const { return m_cfg; }

  /// Draws one interaction point from `rng` (see the class comment for the
  /// order of the draws).
  /// @param rng the event's random engine
  /// @return position and time of the interaction
  Vertex sample(RandomEngine& rng) const;

  /// As sample(rng), with the standard normals taken from `normal`, so that
  /// a caller can share one distribution object (and the second number of
  /// each pair it caches) between its own draws and the vertices.
  /// @param rng the event's random engine
  /// @param normal a standard normal distribution (mean 0, sigma 1)
  /// @return position and time of the interaction
  Vertex sample(RandomEngine& rng,
                std::normal_distribution<double>& normal) const;

  /// All presets, in the order of the documentation table.
  static std::span<const Preset> presets();
  /// The preset called `name`, or nullptr.
  static const Preset* findPreset(std::string_view name);
  /// The preset names separated by ", " (for messages and --help).
  static std::string presetNames();

  /// The region of the CLIC generators (ttbar3tev, bb500, the gamma gamma
  /// overlay) when none is configured: preset "clic3tev".
  static Config clic3TeV();
  /// A point at the origin (preset "point"): the particle gun's default.
  static Config point() { return Config{}; }

 private:
  Config m_cfg;
};

/// What is wrong with a LuminousRegion::Config.
struct LuminousRegionProblem {
  /// The field, e.g. "sigmaZ" or "position.x".
  std::string field;
  /// The problem, e.g. "must lie in [0, 1000] mm (got -1)".
  std::string problem;
};

/// The first problem of `config` in the order of its fields, if any: the
/// checks of the LuminousRegion constructor.
std::optional<LuminousRegionProblem> findLuminousRegionProblem(
    const LuminousRegion::Config& config);

/// Validates `config` as the field `field` of the configuration of
/// `owner` (a generator holding a region): throws InputError
/// "<owner>: config field '<field>.<region field>': <problem>".
/// @return `config`, for use in member initialisers
const LuminousRegion::Config& requireValidRegion(
    std::string_view owner, std::string_view field,
    const LuminousRegion::Config& config);

}  // namespace conftrack
