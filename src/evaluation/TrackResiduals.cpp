#include "conftrack/evaluation/TrackResiduals.hpp"

#include "conftrack/core/Units.hpp"
#include "conftrack/reconstruction/fitting/HelixState.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace conftrack {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double ptFromOmega(double omega, double bz) {
  return constants::kPtPerTeslaMm * std::abs(bz) /
         std::max(std::abs(omega), kMinAbsOmega);
}

double thetaFromTanLambda(double tanLambda) {
  return std::atan2(1.0, tanLambda);
}

double pull(double residual, double variance) {
  return variance > 0.0 ? residual / std::sqrt(variance) : kNaN;
}

}  // namespace

TrackKinematics trackKinematics(const Track& track, const Event& event,
                                double bz) {
  TrackKinematics k;
  if (track.fitted) {
    const TrackVector& p = track.atIp.parameters;
    k.pt = ptFromOmega(p[eOmega], bz);
    k.theta = thetaFromTanLambda(p[eTanLambda]);
    k.phi = wrapAngle(p[ePhi0]);
    k.fromFit = true;
    return k;
  }
  k.pt = track.ptEstimate;
  // The outermost hit seen from the origin: the track direction up to the
  // bending, enough to bin unfitted tracks in theta.
  const Hit* outer = nullptr;
  for (HitIndex h : track.hits) {
    if (h < event.hits.size() &&
        (outer == nullptr ||
         event.hits[h].position.norm() > outer->position.norm())) {
      outer = &event.hits[h];
    }
  }
  if (outer == nullptr) {
    k.theta = kNaN;
    k.phi = kNaN;
    return k;
  }
  const Vector3& x = outer->position;
  k.theta = std::atan2(x.head<2>().norm(), x.z());
  k.phi = std::atan2(x.y(), x.x());
  return k;
}

TrackVector trueTrackParameters(const Particle& particle, double bz,
                                const Vector3& reference) {
  return helixParametersAt(particle.vertex, particle.momentum, particle.charge,
                           bz, reference);
}

std::string_view residualName(ResidualQuantity quantity) {
  switch (quantity) {
    case eResidualD0:
      return "d0";
    case eResidualZ0:
      return "z0";
    case eResidualPhi0:
      return "phi0";
    case eResidualTheta:
      return "theta";
    case eResidualPt:
      return "pt";
    case eResidualPtOverPt2:
      return "pt_over_pt2";
    default:
      return "?";
  }
}

std::string_view residualUnit(ResidualQuantity quantity) {
  switch (quantity) {
    case eResidualD0:
    case eResidualZ0:
      return "um";
    case eResidualPhi0:
    case eResidualTheta:
      return "mrad";
    case eResidualPt:
      return "GeV";
    case eResidualPtOverPt2:
      return "1/GeV";
    default:
      return "";
  }
}

double residualScale(ResidualQuantity quantity) {
  switch (quantity) {
    case eResidualD0:
    case eResidualZ0:
      return 1.0 / units::um;
    case eResidualPhi0:
    case eResidualTheta:
      return 1.0 / units::mrad;
    case eResidualPt:
      return 1.0 / units::GeV;
    case eResidualPtOverPt2:
      return units::GeV;
    default:
      return 1.0;
  }
}

std::string_view pullName(PullQuantity quantity) {
  switch (quantity) {
    case ePullD0:
      return "d0";
    case ePullZ0:
      return "z0";
    case ePullPhi0:
      return "phi0";
    case ePullOmega:
      return "omega";
    case ePullTanLambda:
      return "tanlambda";
    case ePullPt:
      return "pt";
    case ePullTheta:
      return "theta";
    default:
      return "?";
  }
}

TrackResidual computeTrackResidual(const Track& track, const Particle& particle,
                                   double bz) {
  // Both about the line the track's perigee was taken about.
  const TrackVector truth =
      trueTrackParameters(particle, bz, track.atIp.reference);
  const TrackVector& reco = track.atIp.parameters;
  const TrackCovariance& cov = track.atIp.covariance;

  TrackResidual r;
  r.truePt = particle.pt();
  r.trueTheta = std::atan2(r.truePt, particle.momentum.z());

  TrackVector delta = reco - truth;
  delta[ePhi0] = wrapAngle(delta[ePhi0]);
  const double thetaReco = thetaFromTanLambda(reco[eTanLambda]);
  const double ptReco = ptFromOmega(reco[eOmega], bz);
  const double dTheta = thetaReco - r.trueTheta;
  const double dPt = ptReco - r.truePt;

  r.residuals[eResidualD0] = delta[eD0];
  r.residuals[eResidualZ0] = delta[eZ0];
  r.residuals[eResidualPhi0] = delta[ePhi0];
  r.residuals[eResidualTheta] = dTheta;
  r.residuals[eResidualPt] = dPt;
  r.residuals[eResidualPtOverPt2] = dPt / (r.truePt * r.truePt);

  r.pulls[ePullD0] = pull(delta[eD0], cov(eD0, eD0));
  r.pulls[ePullZ0] = pull(delta[eZ0], cov(eZ0, eZ0));
  r.pulls[ePullPhi0] = pull(delta[ePhi0], cov(ePhi0, ePhi0));
  r.pulls[ePullOmega] = pull(delta[eOmega], cov(eOmega, eOmega));
  r.pulls[ePullTanLambda] =
      pull(delta[eTanLambda], cov(eTanLambda, eTanLambda));
  // Jacobians: dpT/dOmega = -pT/Omega; dtheta/dtanLambda = -1/(1 + tan^2).
  const double dPtdOmega =
      ptReco / std::max(std::abs(reco[eOmega]), kMinAbsOmega);
  r.pulls[ePullPt] = pull(dPt, dPtdOmega * dPtdOmega * cov(eOmega, eOmega));
  const double dThetadTan = 1.0 / (1.0 + reco[eTanLambda] * reco[eTanLambda]);
  r.pulls[ePullTheta] =
      pull(dTheta, dThetadTan * dThetadTan * cov(eTanLambda, eTanLambda));
  return r;
}

}  // namespace conftrack
