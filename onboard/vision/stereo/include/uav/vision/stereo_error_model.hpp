#pragma once
// The stereo error model of thesis 3.2: a point at depth Z seen with a disparity uncertainty
// dd and a calibration (pixel position) error p has lateral errors dX = p Z / fx,
// dY = p Z / fy (Eq. 3.4-3.5) and a depth error dZ = Z^2 / (f B) dd (Eq. 3.6-3.7, from
// Z = f B / d, Eq. 3.3). The working range of a stereo rig is where dZ stays under a limit.
namespace uav::vision {

struct StereoErrorModel {
  double f_px = 0.0;           // [px] focal length at the resolution the disparities are in
  double baseline_m = 0.0;     // [m]
  double sigma_d_px = 0.15;    // [px] disparity standard deviation (thesis Tables 3.1-3.2; uav-stereo-error measures it)
  double calibration_px = 0.5; // [px] pixel position error p of Eq. 3.4-3.5

  // Eq. 3.6-3.7: depth standard deviation at depth z [m].
  double DepthSigma(double z_m) const { return z_m * z_m / (f_px * baseline_m) * sigma_d_px; }
  // Eq. 3.4-3.5 (fx = fy = f after rectification): lateral standard deviation at depth z [m].
  double LateralSigma(double z_m) const { return calibration_px * z_m / f_px; }
  // Eq. 3.7 solved for Z: the depth where DepthSigma reaches sigma_z_m (the range gate).
  double DepthWhereSigmaReaches(double sigma_z_m) const;
  // Throws std::invalid_argument naming a non-finite or non-positive field.
  void Validate() const;
};

}  // namespace uav::vision
