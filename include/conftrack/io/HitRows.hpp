#pragma once

/// @file HitRows.hpp
/// The rows of a TrackML hits table turned into Hits, with the checks of
/// readHits (TrackmlReader.hpp): shared by the CSV reader and by callers
/// that hold the columns in memory (the Python module).

#include "conftrack/core/Hit.hpp"
#include "conftrack/core/TrackmlLayerMap.hpp"
#include "conftrack/io/TrackmlIds.hpp"

#include <cstdint>
#include <optional>
#include <string_view>
#include <unordered_set>

namespace conftrack {

/// The fields of one hits row, in TrackML units (mm).
struct HitRow {
  std::uint64_t id = 0;
  Vector3 position = Vector3::Zero();
  TrackmlId trackml;
  /// sigma_u and sigma_v if the table has them [mm].
  std::optional<double> sigmaU;
  std::optional<double> sigmaV;
};

/// Where a row's problems go: both calls must throw (InputError), naming
/// the row; `failField` also names the column and its value.
class HitRowErrors {
 public:
  virtual ~HitRowErrors() = default;
  [[noreturn]] virtual void fail(std::string_view what) const = 0;
  [[noreturn]] virtual void failField(std::string_view column,
                                      std::string_view what) const = 0;
};

/// Builds the hits of one table row by row (readHits documents the checks
/// and what the layer map supplies). Rows must come in table order: the
/// duplicate-id check spans the rows given so far.
class HitRowBuilder {
 public:
  /// `layers` may be null (raw ids); it must outlive the builder.
  explicit HitRowBuilder(const TrackmlLayerMap* layers);

  /// The hit of `row`; problems go to `errors`.
  Hit build(const HitRow& row, const HitRowErrors& errors);

 private:
  const TrackmlLayer* findLayer(std::uint32_t volume, std::uint32_t layer);

  const TrackmlLayerMap* m_layers;
  /// The last layer found: hits come grouped by module.
  const TrackmlLayer* m_layer = nullptr;
  std::uint32_t m_volume = 0;
  std::uint32_t m_layerId = 0;
  /// Rows so far; while ids run 1, 2, 3, ... they cannot repeat, and the
  /// set of seen ids is built only once a row leaves that pattern.
  std::uint64_t m_rows = 0;
  bool m_contiguous = true;
  std::unordered_set<std::uint64_t> m_seen;
};

}  // namespace conftrack
