#include "conftrack/geometry/SurfaceNavigator.hpp"

#include "conftrack/geometry/MaterialInteractions.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace conftrack {

Vector3 NavigationSurface::normal(const Vector3& position) const {
  if (shape == SurfaceShape::eDisk) {
    return Vector3::UnitZ();
  }
  const double r = position.head<2>().norm();
  const double c = r > 0.0 ? position.x() / r : 1.0;
  const double s = r > 0.0 ? position.y() / r : 0.0;
  if (shape == SurfaceShape::eCylinder) {
    return {c, s, 0.0};
  }
  const double norm = 1.0 / std::sqrt(1.0 + coneSlope * coneSlope);
  return {c * norm, s * norm, -coneSlope * norm};
}

double NavigationSurface::xOverX0(const Vector3& position,
                                  const Vector3& direction,
                                  double minCosIncidence) const {
  // The chord cap bounds the path across the shell's curvature: in the
  // plane perpendicular to the generator line (z for a cylinder, the
  // cone's slope line for a cone). A track moving along the generator
  // covers that path over 1/|d_perp| more length (a forward track crossing
  // a cylinder radially keeps its full t / sin(theta)), so the floor is
  // grazingCos |d_perp|.
  double acrossGenerator = direction.head<2>().norm();
  if (shape == SurfaceShape::eCone) {
    const double r = position.head<2>().norm();
    const Vector3 radial =
        r > 0.0 ? Vector3(position.x() / r, position.y() / r, 0.0)
                : Vector3::UnitX();
    const Vector3 generator =
        (coneSlope * radial + Vector3::UnitZ()).normalized();
    const double along = direction.dot(generator);
    acrossGenerator = std::sqrt(std::max(0.0, 1.0 - along * along));
  }
  const double cosIncidence =
      std::max(std::abs(direction.dot(normal(position))),
               std::max(minCosIncidence, grazingCos * acrossGenerator));
  return thicknessX0 / cosIncidence;
}

SurfaceNavigator::SurfaceNavigator(const Detector& detector) {
  // The shape, extent and material that sensitive layers and passive
  // surfaces have in common.
  auto surfaceOf = [](const auto& from) {
    NavigationSurface s;
    s.shape = from.shape;
    s.r = from.r;
    s.zMin = from.zMin;
    s.zMax = from.zMax;
    s.rMin = from.rMin;
    s.rMax = from.rMax;
    s.thicknessX0 = from.thicknessX0;
    return s;
  };
  for (std::size_t i = 0; i < detector.layers().size(); ++i) {
    NavigationSurface s = surfaceOf(detector.layers()[i]);
    s.layer = static_cast<std::int32_t>(i);
    m_surfaces.push_back(s);
  }
  for (const PassiveSurface& p : detector.passives()) {
    NavigationSurface s = surfaceOf(p);
    if (p.shape == SurfaceShape::eCone) {
      s.coneR1 = p.coneR1;
      s.coneSlope = (p.coneR2 - p.coneR1) / (p.zMax - p.zMin);
    }
    m_surfaces.push_back(s);
  }
  const double x0Mm = radiationLengthMm(kSilicon);
  for (NavigationSurface& s : m_surfaces) {
    // Radius of curvature of the surface: the cylinder radius; for a cone
    // the smaller end radius (conservative: the larger cap).
    const double radius = s.shape == SurfaceShape::eCylinder ? s.r : s.rMin;
    if (s.shape != SurfaceShape::eDisk && radius > 0.0) {
      s.grazingCos =
          std::min(1.0, std::sqrt(s.thicknessX0 * x0Mm / (2.0 * radius)));
    }
  }
  for (std::uint32_t i = 0; i < m_surfaces.size(); ++i) {
    switch (m_surfaces[i].shape) {
      case SurfaceShape::eCylinder:
        m_cylinders.push_back(i);
        break;
      case SurfaceShape::eDisk:
        m_disks.push_back(i);
        break;
      case SurfaceShape::eCone:
        m_cones.push_back(i);
        break;
    }
  }
  // Stable sorts keep the build order for equal keys, so the search result
  // for coincident surfaces is deterministic.
  std::stable_sort(m_cylinders.begin(), m_cylinders.end(),
                   [this](std::uint32_t a, std::uint32_t b) {
                     return m_surfaces[a].r < m_surfaces[b].r;
                   });
  std::stable_sort(m_disks.begin(), m_disks.end(),
                   [this](std::uint32_t a, std::uint32_t b) {
                     return m_surfaces[a].zMin < m_surfaces[b].zMin;
                   });
  for (std::uint32_t i : m_cylinders) {
    m_cylinderRadii.push_back(m_surfaces[i].r);
  }
  for (std::uint32_t i : m_disks) {
    m_diskZ.push_back(m_surfaces[i].zMin);
  }
}

SurfaceCrossing SurfaceNavigator::nextCrossing(const Helix& helix, double sMin,
                                               double sMax) const {
  SurfaceCrossing best;
  // Only crossings strictly before sMax count.
  double bestS = sMax;
  auto consider = [&](double s, std::uint32_t index) {
    if (s < bestS) {
      bestS = s;
      best.s = s;
      best.surface = index;
    }
  };

  const Vector3& origin = helix.origin();
  const double r0 = origin.head<2>().norm();
  const double z0 = origin.z();
  const double tanLambda = helix.tanLambda();
  // Radii the circle can reach, with a margin for rounding: the exact
  // intersection decides near tangency.
  const double margin = 1e-9 * (1.0 + r0);
  const double reachMin = helix.minRadius() - margin;
  const double reachMax = helix.maxRadius() + margin;

  // Cheap test whether the helix is inside a cylinder's z range somewhere
  // in (sMin, bestS).
  const double invTanLambda = tanLambda != 0.0 ? 1.0 / tanLambda : 0.0;
  auto zWindowOpen = [&](const NavigationSurface& c) {
    if (tanLambda == 0.0) {
      return z0 >= c.zMin && z0 <= c.zMax;
    }
    const double s1 = (c.zMin - z0) * invTanLambda;
    const double s2 = (c.zMax - z0) * invTanLambda;
    return std::max(s1, s2) > sMin && std::min(s1, s2) < bestS;
  };
  // Cylinders, first in the direction of radial motion, then the other
  // way. A lower bound on the arc length to radius R (|dr/ds| <= 1): |R - r0|
  // ahead; behind, the helix must first turn at its extreme radius, e.g.
  // moving out: (rMax - r0) + (rMax - R). Both grow along each walk, so a
  // walk stops at the first cylinder whose bound exceeds the best crossing.
  const auto split = static_cast<std::size_t>(
      std::lower_bound(m_cylinderRadii.begin(), m_cylinderRadii.end(), r0) -
      m_cylinderRadii.begin());
  const bool outwards = helix.radialDirection() >= 0.0;
  auto walkOut = [&] {
    for (std::size_t k = split; k < m_cylinders.size(); ++k) {
      const double r = m_cylinderRadii[k];
      const double bound = outwards ? r - r0 : r0 + r - 2.0 * reachMin;
      if (bound >= bestS || r > reachMax) {
        break;
      }
      const NavigationSurface& c = m_surfaces[m_cylinders[k]];
      if (!zWindowOpen(c)) {
        continue;
      }
      consider(helix.nextCylinderCrossing(r, c.zMin, c.zMax, sMin, bestS),
               m_cylinders[k]);
    }
  };
  auto walkIn = [&] {
    for (std::size_t k = split; k-- > 0;) {
      const double r = m_cylinderRadii[k];
      const double bound = outwards ? 2.0 * reachMax - r0 - r : r0 - r;
      if (bound >= bestS || r < reachMin) {
        break;
      }
      const NavigationSurface& c = m_surfaces[m_cylinders[k]];
      if (!zWindowOpen(c)) {
        continue;
      }
      consider(helix.nextCylinderCrossing(r, c.zMin, c.zMax, sMin, bestS),
               m_cylinders[k]);
    }
  };
  if (outwards) {
    walkOut();
    walkIn();
  } else {
    walkIn();
    walkOut();
  }

  // Disks in the direction of motion along z.
  // Disk k: false once it (and every later one) lies beyond the best
  // crossing so far.
  auto considerDisk = [&](std::size_t k) {
    if ((m_diskZ[k] - z0) / tanLambda >= bestS) {
      return false;
    }
    const NavigationSurface& d = m_surfaces[m_disks[k]];
    if (d.rMax >= reachMin && d.rMin <= reachMax) {
      consider(helix.nextDiskCrossing(d.zMin, d.rMin, d.rMax, sMin, bestS),
               m_disks[k]);
    }
    return true;
  };
  if (tanLambda > 0.0) {
    auto k = static_cast<std::size_t>(
        std::upper_bound(m_diskZ.begin(), m_diskZ.end(), z0) - m_diskZ.begin());
    while (k < m_disks.size() && considerDisk(k)) {
      ++k;
    }
  } else if (tanLambda < 0.0) {
    auto k = static_cast<std::size_t>(
        std::lower_bound(m_diskZ.begin(), m_diskZ.end(), z0) - m_diskZ.begin());
    while (k > 0 && considerDisk(k - 1)) {
      --k;
    }
  }

  // Cones: cheap bounds first (z window ahead, radial gap), then the search
  // limited to the best crossing so far.
  for (std::uint32_t index : m_cones) {
    const NavigationSurface& c = m_surfaces[index];
    if (c.rMax < reachMin || c.rMin > reachMax) {
      continue;
    }
    double lowerBound = std::max({0.0, c.rMin - r0, r0 - c.rMax});
    if (tanLambda != 0.0) {
      const double s1 = (c.zMin - z0) / tanLambda;
      const double s2 = (c.zMax - z0) / tanLambda;
      if (std::max(s1, s2) <= sMin) {
        continue;
      }
      lowerBound = std::max(lowerBound, std::min(s1, s2));
    } else if (z0 < c.zMin || z0 > c.zMax) {
      continue;
    }
    if (lowerBound >= bestS) {
      continue;
    }
    consider(helix.nextConeCrossing(c.zMin, c.zMax, c.coneR1, c.coneSlope, sMin,
                                    bestS),
             index);
  }
  return best;
}

}  // namespace conftrack
