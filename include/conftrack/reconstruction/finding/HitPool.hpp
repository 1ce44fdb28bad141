#pragma once

/// @file HitPool.hpp
/// The hits of one step and their neighbour-search structures: a k-d tree
/// on (u, v) for disc searches (nanoflann) and an azimuth-sorted array for
/// window searches. Results come in a total order (distance, then index),
/// so that the output never depends on the tree's internal order
/// (docs/algorithm.md 3.2; the azimuth cells of the windows: section 6).

#include "conftrack/reconstruction/finding/ConformalHits.hpp"
#include "conftrack/reconstruction/finding/detail/PhiCells.hpp"

#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace conftrack {

class HitPool {
 public:
  /// A cone in the (z, R) plane: apex, unit axis and half-angle [rad].
  /// Limits cone() searches on each layer to the part of the layer (its
  /// members' z and R ranges) inside the cone.
  struct RzCone {
    double z;
    double r;
    double dz;
    double dr;
    double halfAngle;
  };

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
  /// Members within `radius` of (u, v) whose azimuth lies within
  /// `halfWidth` of `phi` (plus a 1e-9 rad margin, for the caller's exact
  /// cut), by distance then index: the hits of disc() in that window, in
  /// the same order, but only the window of each layer is examined (a disc
  /// around an outer-layer seed holds every hit of the layers beyond it).
  /// `keep` and `rz` as in cone().
  void discWindow(double u, double v, double radius, double phi,
                  double halfWidth, std::vector<ConfIndex>& out,
                  const std::function<bool(ConfIndex)>& keep = {},
                  const RzCone* rz = nullptr) const;
  /// Members within the disc (discU, discV, discRadius) and inside the
  /// cone with apex (u, v), unit axis (du, dv) and half-angle `halfAngle`,
  /// by distance to the disc centre then index. The same hits as disc()
  /// followed by an angle cut, but each layer is searched only in the
  /// azimuth window that the cone covers on it.
  /// If `keep` is given, only members for which it returns true are kept
  /// (applied before sorting: the same result as filtering afterwards, at
  /// the cost of sorting only the survivors). If `rz` is given, only
  /// members inside that (z, R) cone can be returned (a superset of them
  /// is examined: the layer bins along z, or R on disks, that the cone
  /// reaches).
  void cone(double u, double v, double du, double dv, double halfAngle,
            double discU, double discV, double discRadius,
            std::vector<ConfIndex>& out,
            const std::function<bool(ConfIndex)>& keep = {},
            const RzCone* rz = nullptr) const;
  /// Members with |phi - centre| <= halfWidth (wrapped), by |dphi| then
  /// index; with `keep`, only those it accepts (filtered before the sort,
  /// as in cone()).
  void azimuthWindow(double phi, double halfWidth, std::vector<ConfIndex>& out,
                     const std::function<bool(ConfIndex)>& keep = {}) const;
  /// Appends the members on one detector layer with azimuth in the window
  /// (unordered: callers choose among them by a total order). With `rz`,
  /// only the layer bins that the (z, R) cone reaches are examined (a
  /// superset of the members inside it).
  void layerWindow(std::uint32_t layer, double phi, double halfWidth,
                   std::vector<ConfIndex>& out,
                   const RzCone* rz = nullptr) const;
  /// Appends the members on one detector layer with azimuth in the window
  /// and z in [zLo, zHi] (barrel layers) or R in [rLo, rHi] (disks): a
  /// superset (whole bins along the layer), unordered.
  void layerBox(std::uint32_t layer, double phi, double halfWidth, double zLo,
                double zHi, double rLo, double rHi,
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
  /// Azimuth cells of m_phis (one range), of m_layerPhis (range k: layer
  /// k) and of m_binPhis (one range per bin: its hits' [begin, end)).
  detail::PhiCells m_phiCells;
  detail::PhiCells m_layerCells;
  detail::PhiCells m_binCells;
  /// Per layer: [begin, end) into m_layerHits (sorted by azimuth).
  std::vector<std::uint32_t> m_layers;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_layerRange;
  /// Per layer: smallest and largest conformal radius of its members.
  std::vector<std::pair<double, double>> m_layerRc;
  std::vector<ConfIndex> m_layerHits;
  std::vector<double> m_layerPhis;
  /// Per layer: its members binned along the layer's long coordinate w (z
  /// on barrel layers, R on disks: whichever range is longer), each bin
  /// sorted by azimuth, for the (z, R) cone of cone().
  struct LayerBins {
    bool alongZ = true;
    double zMin = 0.0, zMax = 0.0, rMin = 0.0, rMax = 0.0;
    double wMin = 0.0, binWidth = 0.0;
    std::uint32_t nBins = 1;
    std::uint32_t firstBin = 0;  ///< range id of bin 0 in m_binCells
    std::uint32_t binOf(double w) const;
  };
  /// An RzCone with its trigonometry done once per search.
  struct PreparedRz {
    explicit PreparedRz(const RzCone& rz);
    RzCone cone;
    bool unbounded = false;  ///< half-angle >= pi/2: no restriction
    double edgeZ[2] = {0.0, 0.0}, edgeR[2] = {0.0, 0.0};
    /// The edges' slopes dz/dR and dR/dz (0 where undefined), for the
    /// closed-form range when both edges run towards a layer's band.
    double dzdr[2] = {0.0, 0.0}, drdz[2] = {0.0, 0.0};
  };
  /// Range of w of the layer's part inside `rz`; false if none.
  static bool rzRange(const PreparedRz& rz, const LayerBins& bins, double& wLo,
                      double& wHi);
  /// A box in (z, R).
  struct RzBox {
    double zMin, zMax, rMin, rMax;
    bool overlaps(const LayerBins& b) const {
      return b.zMax >= zMin && b.zMin <= zMax && b.rMax >= rMin &&
             b.rMin <= rMax;
    }
  };
  /// The (z, R) bounding box of the part of `rz` inside `box`, widened by
  /// a margin; false if there is none to use (unbounded cone, or no part).
  /// A layer whose box misses it misses the cone: rzRange() would refuse
  /// it, at several times the cost of this test (most layers of a search
  /// are refused so, e.g. the disks for a barrel track).
  static bool rzReach(const PreparedRz& rz, const RzBox& box, RzBox& out);
  /// With a (z, R) cone `rz` (null: none): prepares it into `prepared` and
  /// the box of its reach in the pool into `reach`; true if layers outside
  /// that box can be refused.
  bool prepareReach(const RzCone* rz, std::optional<PreparedRz>& prepared,
                    RzBox& reach) const;
  /// The (z, R) box of all members.
  RzBox m_box{0.0, 0.0, 0.0, 0.0};
  /// Appends the members of layer k (index into m_layers) within the
  /// azimuth window whose long coordinate w may lie in [wLo, wHi] (a
  /// superset: whole bins, or the exact range).
  void collectLayer(std::size_t k, double wLo, double wHi, double phi,
                    double halfWidth, std::vector<ConfIndex>& out) const;
  std::vector<LayerBins> m_layerBins;
  std::vector<ConfIndex> m_binHits;
  std::vector<double> m_binPhis;
  /// Each layer member's long coordinate (z or R, as its LayerBins),
  /// parallel to m_layerHits.
  std::vector<double> m_layerWs;
};

}  // namespace conftrack
