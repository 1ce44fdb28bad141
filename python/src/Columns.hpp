#pragma once

/// @file Columns.hpp
/// Tables between C++ and Python: dicts of numpy arrays with the TrackML
/// column names (the Python layer makes pandas DataFrames of them) and the
/// hits of such a table turned into Hits with the checks of the hits-file
/// reader. All functions need the GIL.

#include "conftrack/core/Event.hpp"
#include "conftrack/geometry/Detector.hpp"

#include <cstddef>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <span>
#include <string>
#include <vector>

namespace conftrack::python {

namespace py = pybind11;

/// A numpy array of n values f(0), ..., f(n - 1).
template <class T, class F>
py::array_t<T> column(std::size_t n, F&& f) {
  py::array_t<T> array(static_cast<py::ssize_t>(n));
  T* data = array.mutable_data();
  for (std::size_t i = 0; i < n; ++i) {
    data[i] = static_cast<T>(f(i));
  }
  return array;
}

/// The hits as TrackML hit columns (hit_id, x, y, z [mm], volume_id,
/// layer_id, module_id; sigma_u, sigma_v [mm] if some hit has a non-zero
/// one, as the hits-file writer does). `detector` maps the ids as
/// TrackmlIds.hpp (null: raw ids). InputError for ids it cannot map.
py::dict hitColumns(std::span<const Hit> hits, const Detector* detector);

/// The truth as TrackML truth columns (hit_id, particle_id, tx, ty, tz
/// [mm], tpx, tpy, tpz [GeV], weight, time [ns]).
py::dict truthColumns(const std::vector<Hit>& hits,
                      const std::vector<HitTruth>& truth);

/// The particles as TrackML particle columns (particle_id, particle_type,
/// vx, vy, vz [mm], px, py, pz [GeV], q, nhits, vt [ns], status,
/// parent_id, background).
py::dict particleColumns(const std::vector<Particle>& particles);

/// The hits of `columns` (a mapping of TrackML hit column names to 1-D
/// arrays, as hitColumns writes): hit_id, x, y, z, volume_id, layer_id and
/// module_id required, sigma_u and sigma_v optional, other names ignored.
/// The checks and what `detector` supplies are those of readHits
/// (io/TrackmlReader.hpp); problems are InputErrors "hits row N: ...".
std::vector<Hit> hitsFromColumns(const py::handle& columns,
                                 const Detector* detector);

/// The truth parallel to `hits` from TrackML truth columns (hit_id and
/// particle_id required; tx, ty, tz, tpx, tpy, tpz, weight, time optional,
/// 0 when absent). Every hit needs exactly one row, as in readTruth.
std::vector<HitTruth> truthFromColumns(const py::handle& columns,
                                       const std::vector<Hit>& hits);

/// Particles from TrackML particle columns (particle_id required, the rest
/// optional with the defaults of readParticles), sorted by id.
std::vector<Particle> particlesFromColumns(const py::handle& columns);

/// Hits with only the ids of column hit_id of `columns` (table `table`):
/// enough for the TrackML score.
std::vector<Hit> hitIdsFromColumns(const py::handle& columns,
                                   const std::string& table);

/// The track ids of a TrackML submission (hit_id, track_id) parallel to
/// `hits`: every hit exactly once, as readSubmission.
std::vector<std::uint64_t> labelsFromColumns(const py::handle& submission,
                                             const std::vector<Hit>& hits);

}  // namespace conftrack::python
