#pragma once

/// @file TrackmlFormat.hpp
/// Column names of conftrack's event files: the TrackML CSV format plus
/// conftrack's extra columns (docs/formats.md).
///
/// Per event `NNN` (zero-padded to 9 digits) a folder holds
/// `eventNNN-hits.csv`, `eventNNN-truth.csv` and `eventNNN-particles.csv`,
/// each plain or gzip-compressed with the suffix `.gz`. Units are the
/// TrackML ones, which are conftrack's native units: mm, GeV, ns, charge in
/// units of e.
///
/// hits (one row per measured hit):
///   hit_id,x,y,z,volume_id,layer_id,module_id   TrackML standard [mm]
///   sigma_u,sigma_v                             conftrack extra  [mm]
///     resolution along the local u (r-phi) and v (z on barrels, r on
///     disks) axes. Missing: the detector layer's resolution if a detector
///     is given, else 0. Written only if some hit has a non-zero one.
/// truth (one row per hit, hit_id in any order):
///   hit_id,particle_id (0 = noise),tx,ty,tz [mm],tpx,tpy,tpz [GeV],weight
///   time                                        conftrack extra  [ns]
///     time of the crossing relative to the physics bunch crossing.
///     Missing: 0. (`weight` is also optional when reading: 0.)
/// particles (one row per particle):
///   particle_id,particle_type (PDG code),vx,vy,vz [mm],px,py,pz [GeV],
///   q [e],nhits                                 TrackML standard
///     (particle_type is optional when reading: the Kaggle files lack it;
///     missing: 0)
///   vt [ns],status,parent_id,background         conftrack extra
///     production time (missing: 0); HepMC status, 1 = stable, 2 = decayed
///     (missing: 1); id of the parent particle, 0 = primary (missing: 0);
///     0 = physics event, 1 = overlaid background (missing: 0).
///
/// Detector ids: volume_id and layer_id are the layer's TrackML volume and
/// layer (TrackmlLayerMap::findTrackml), module_id is
/// DetectorId::module. Without a detector the ids are taken raw:
/// subdetector = volume_id, side = barrel, layer = layer_id.
///
/// Readers find columns by header name in any order and ignore unknown
/// columns; writers put the extra columns after the standard ones, so TrackML
/// tools read conftrack files unchanged.

#include <string_view>

namespace conftrack::trackml {

/// Hits file columns.
namespace hits {
inline constexpr std::string_view kHitId = "hit_id";
inline constexpr std::string_view kX = "x";
inline constexpr std::string_view kY = "y";
inline constexpr std::string_view kZ = "z";
inline constexpr std::string_view kVolumeId = "volume_id";
inline constexpr std::string_view kLayerId = "layer_id";
inline constexpr std::string_view kModuleId = "module_id";
inline constexpr std::string_view kSigmaU = "sigma_u";
inline constexpr std::string_view kSigmaV = "sigma_v";
}  // namespace hits

/// Truth file columns.
namespace truth {
inline constexpr std::string_view kHitId = "hit_id";
inline constexpr std::string_view kParticleId = "particle_id";
inline constexpr std::string_view kTx = "tx";
inline constexpr std::string_view kTy = "ty";
inline constexpr std::string_view kTz = "tz";
inline constexpr std::string_view kTpx = "tpx";
inline constexpr std::string_view kTpy = "tpy";
inline constexpr std::string_view kTpz = "tpz";
inline constexpr std::string_view kWeight = "weight";
inline constexpr std::string_view kTime = "time";
}  // namespace truth

/// Particles file columns.
namespace particles {
inline constexpr std::string_view kParticleId = "particle_id";
inline constexpr std::string_view kParticleType = "particle_type";
inline constexpr std::string_view kVx = "vx";
inline constexpr std::string_view kVy = "vy";
inline constexpr std::string_view kVz = "vz";
inline constexpr std::string_view kPx = "px";
inline constexpr std::string_view kPy = "py";
inline constexpr std::string_view kPz = "pz";
inline constexpr std::string_view kQ = "q";
inline constexpr std::string_view kNHits = "nhits";
inline constexpr std::string_view kVt = "vt";
inline constexpr std::string_view kStatus = "status";
inline constexpr std::string_view kParentId = "parent_id";
inline constexpr std::string_view kBackground = "background";
}  // namespace particles

}  // namespace conftrack::trackml
