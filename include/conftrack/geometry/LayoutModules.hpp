#pragma once

/// @file LayoutModules.hpp
/// The flat sensors of CLICdet and CLD, built from their layout JSON files
/// (data/layouts/*_layout.json.gz), as a ModuleLayout for a module-level
/// simulation of those detectors.

#include "conftrack/geometry/Detector.hpp"
#include "conftrack/geometry/ModuleLayout.hpp"

#include <string>
#include <string_view>

namespace conftrack {

/// Largest distance between a layer's nominal radius or disk z in the
/// layout file and the navigation surface of the detector layer it is
/// matched to [mm]: farther, the file is taken to describe another detector.
inline constexpr double kMaxLayoutLayerDistance = 10.0;

/// Builds the sensors that the layout JSON `jsonText` (the text of
/// clicdet_layout.json or cld_layout.json; `source` names it in errors)
/// describes, on the layers of `detector` (detectors/clicdet.toml or
/// cld.toml). Each entry of "barrel_layers" and "endcap_disks" is matched
/// to the detector layer with the same subdetector name and layer number
/// (endcap entries to both sides: +z as given, -z mirrored). The model,
/// per kind of entry (keys in the file's units, multiplied by
/// core/Units.hpp on input):
/// - vertex barrel (`n_staves`): flat staves of `stave_width_mm` at
///   perpendicular distance `r_mm`, |z| < `half_z_mm`, stave j at azimuth
///   2 pi j / n and shifted by `stave_offset_mm` along +phi (ZPlanarTracker);
///   module number j;
/// - tracker barrel (`n_phi_modules`): `n_phi_modules` x `n_z_modules`
///   modules of `module_size_mm` (r-phi, z), module i at azimuth 2 pi i / n
///   and perpendicular distance `r_mm` (i even) or `r_alt_mm` (i odd), the
///   z rows evenly spread over |z| < `half_z_mm`; module number
///   i + n_phi * (z row);
/// - tracker disk (`rings`): per ring `n_modules` rectangles of
///   `module_width_mm` (tangential) by the ring's radial extent, module k
///   at azimuth 2 pi k / n, inner edge at `r_min_mm`, the sensor at
///   |z| = `z_mm` + `module_z_offsets_mm`[k % 2] +
///   `sensor_z_offset_in_module_mm`; module numbers count on over the rings
///   from the innermost;
/// - vertex disk (`n_petals`): trapezoidal petals that tile their 2 pi / n
///   sector exactly (edges on the sector's radial boundary lines, no
///   overlap, no gap), inner and outer edges at perpendicular distances
///   `r_min_mm` and `r_max_mm`, petal k at `z_petals_mm`[k] (else `z_mm`)
///   and azimuth `petal_phi_center_rad`[k] (else pi + pi/n + 2 pi k / n,
///   the VertexEndcap driver's placement); on -z, petal k sits at
///   -`z_petals_mm`[n - 1 - k] (the spiral mirrored); module number k.
/// u is r-phi (barrels) or tangential (disks), v is z or radial; the
/// resolutions are `resolution_rphi_um` (u) and `resolution_z_um` or
/// `resolution_r_um` (v); the thickness `sensor_thickness_um`. Material:
/// `module_X0` per sensor and `support_X0` as the layer's support where
/// given; where only `thickness_X0` is given (vertex staves and petals,
/// whose support is glued under the sensor and has its extent), all of it
/// is the sensor's and the layer has no separate support.
///
/// Throws InputError "source: key 'barrel_layers[6].module_size_mm':
/// problem" for invalid JSON, a missing or wrongly typed key, a
/// non-positive size, count or resolution, a negative material, a
/// subdetector or layer the detector lacks (or of the other kind), a layer
/// given twice, or a nominal radius / z more than kMaxLayoutLayerDistance
/// from the detector layer's.
ModuleLayout buildLayoutModules(std::string_view jsonText,
                                const Detector& detector,
                                const std::string& source);

}  // namespace conftrack
