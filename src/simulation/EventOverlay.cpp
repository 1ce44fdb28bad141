#include "conftrack/simulation/EventOverlay.hpp"

#include "conftrack/core/Error.hpp"

#include <cmath>
#include <string>

namespace conftrack {

void EventOverlayConfig::validate() const {
  if (copies == 0) {
    throw InputError("event overlay: copies must be at least 1");
  }
  if (!std::isfinite(rotation)) {
    throw InputError("event overlay: rotation must be finite");
  }
}

Event overlayEvents(std::span<const Event> events,
                    const EventOverlayConfig& config) {
  config.validate();
  std::size_t total = 0;
  for (const Event& e : events) {
    total += e.hits.size();
  }
  Event out;
  out.number = config.number;
  out.hits.reserve(total * config.copies);
  for (const Event& e : events) {
    for (std::uint32_t k = 0; k < config.copies; ++k) {
      const double angle = static_cast<double>(k) * config.rotation;
      const double c = std::cos(angle);
      const double s = std::sin(angle);
      Matrix3 rot = Matrix3::Identity();
      rot(0, 0) = c;
      rot(0, 1) = -s;
      rot(1, 0) = s;
      rot(1, 1) = c;
      for (const Hit& h : e.hits) {
        Hit r = h;
        if (k > 0) {
          r.position = rot * h.position;
          r.uAxis = rot * h.uAxis;
          r.vAxis = rot * h.vAxis;
        }
        r.id = out.hits.size() + 1;
        out.hits.push_back(r);
      }
    }
  }
  return out;
}

}  // namespace conftrack
