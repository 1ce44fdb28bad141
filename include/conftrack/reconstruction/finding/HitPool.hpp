#pragma once

/// @file HitPool.hpp
/// The hits of one step and their neighbour-search structures: a k-d tree
/// on (u, v) for disc searches (nanoflann) and an azimuth-sorted array for
/// window searches. Results come in a total order (distance, then index),
/// so that the output never depends on the tree's internal order
/// (algorithm.md 2.4 and 14.2).

#include "conftrack/reconstruction/finding/ConformalHits.hpp"

#include <memory>
#include <vector>

namespace conftrack {

class HitPool {
 public:
  /// Indexes `members` (conformal-hit indices; any order).
  HitPool(const ConformalHits& hits, std::vector<ConfIndex> members);
  ~HitPool();
  HitPool(HitPool&&) noexcept;
  HitPool& operator=(HitPool&&) noexcept;

  /// Members in ascending index order (innermost first).
  const std::vector<ConfIndex>& members() const { return m_members; }
  /// Members within `radius` of (u, v), by distance then index.
  void disc(double u, double v, double radius,
            std::vector<ConfIndex>& out) const;
  /// Members within the disc (discU, discV, discRadius) and inside the
  /// cone with apex (u, v), unit axis (du, dv) and half-angle `halfAngle`,
  /// by distance to the disc centre then index. The same hits as disc()
  /// followed by an angle cut, but each layer is searched only in the
  /// azimuth window that the cone covers on it (algorithm.md 14.12).
  void cone(double u, double v, double du, double dv, double halfAngle,
            double discU, double discV, double discRadius,
            std::vector<ConfIndex>& out) const;
  /// Members with |phi - centre| <= halfWidth (wrapped), by |dphi| then
  /// index.
  void azimuthWindow(double phi, double halfWidth,
                     std::vector<ConfIndex>& out) const;
  /// Members on one detector layer with azimuth in the window, by index.
  void layerWindow(std::uint32_t layer, double phi, double halfWidth,
                   std::vector<ConfIndex>& out) const;
  /// Detector layers that have members, ascending.
  const std::vector<std::uint32_t>& layers() const { return m_layers; }

 private:
  struct Tree;
  const ConformalHits* m_hits;
  std::vector<ConfIndex> m_members;
  std::unique_ptr<Tree> m_tree;
  /// Members sorted by azimuth, and their azimuths.
  std::vector<ConfIndex> m_byPhi;
  std::vector<double> m_phis;
  /// Per layer: [begin, end) into m_layerHits (sorted by azimuth).
  std::vector<std::uint32_t> m_layers;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_layerRange;
  /// Per layer: smallest and largest conformal radius of its members.
  std::vector<std::pair<double, double>> m_layerRc;
  std::vector<ConfIndex> m_layerHits;
  std::vector<double> m_layerPhis;
};

}  // namespace conftrack
