#include "uav/vision/stereo_error_model.hpp"

#include <cmath>
#include <stdexcept>

namespace uav::vision {

void StereoErrorModel::Validate() const {
  if (!(std::isfinite(f_px) && f_px > 0)) throw std::invalid_argument("error model: focal length must be positive");
  if (!(std::isfinite(baseline_m) && baseline_m > 0)) throw std::invalid_argument("error model: baseline must be positive");
  if (!(std::isfinite(sigma_d_px) && sigma_d_px > 0))
    throw std::invalid_argument("error model: disparity sigma must be positive");
  if (!(std::isfinite(calibration_px) && calibration_px >= 0))
    throw std::invalid_argument("error model: calibration error must not be negative");
}

double StereoErrorModel::DepthWhereSigmaReaches(double sigma_z_m) const {
  // Eq. 3.7: dZ = Z^2 dd / (f B)  =>  Z = sqrt(dZ f B / dd).
  return std::sqrt(sigma_z_m * f_px * baseline_m / sigma_d_px);
}

}  // namespace uav::vision
