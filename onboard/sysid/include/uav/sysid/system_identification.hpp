#pragma once
// System identification from a flight log (thesis 2.4.5 and 2.5): trim values from a hover
// segment (Table 2.4 method) and, for each chirp segment (Eq. 2.14), the model structure that
// channel excites in the vehicle's wiring, fitted by prediction error (output error for the
// lag models, least squares on the yaw equation):
//   throttle, any wiring:  rotor thrust lag of Eq. 2.13 -> K_f, tau_f (thrust from Eq. 2.15)
//   rudder, direct:        yaw dynamics of Eq. 2.16 -> d
//   aileron/elevator/rudder, gyro cruise: Eq. 2.20-2.22 -> K_p, tau_p, K_q, tau_q, K_r, tau_r
//   aileron/elevator/rudder, gyro hover:  Eq. 2.17-2.19 -> K_phi, tau_phi, T_phi, ... K_r, tau_r
// Plain functions on plain data.
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "uav/shared/parameters.hpp"

namespace uav::sysid {

// A flight log as named numeric columns (the DLG thread's CSV).
class LogTable {
 public:
  // Throws std::runtime_error naming the file and line of the first bad row (wrong number of
  // fields, not a number), or the file when it is missing or empty. A "nan" cell (a perception
  // report's column before its first report) is kept: only a column that is used must have none.
  static LogTable ReadCsv(const std::string& path);
  static LogTable Parse(const std::string& text, const std::string& source);
  // Throws std::runtime_error naming the column and the file when it is missing, or the line of
  // its first "nan".
  const std::vector<double>& Column(const std::string& name) const;
  bool Has(const std::string& name) const { return columns_.count(name) != 0; }
  std::size_t rows() const { return rows_; }

 private:
  std::string source_;
  std::map<std::string, std::vector<double>> columns_;
  std::map<std::string, int> first_nan_line_;
  std::size_t rows_ = 0;
};

// What identification takes as known (thesis Table 2.2: weighed and measured on the ground).
struct KnownParams {
  double mass, gravity, rotor_speed_gain;
  Eigen::Vector3d inertia;
  static KnownParams FromParameters(const ParameterSet& p);
};

struct ModelFit {
  std::string model;     // e.g. "rotor_thrust"
  std::string equation;  // e.g. "Eq. 2.13"
  std::map<std::string, double> params;
  double fit_percent = 0;  // 100 (1 - |y - y_model| / |y - mean(y)|), as MATLAB's compare
  double t0 = 0, t1 = 0;   // [s] segment of the log
  std::string output_name;  // what was compared
  std::vector<double> t, measured, predicted;
};

struct TrimValues {
  bool found = false;
  double t0 = 0, t1 = 0;
  std::map<std::string, double> values;  // u_a0, u_e0, u_th0, u_r0, u0, v0, w0, phi0, ... (Table 2.4)
};

struct Identification {
  TrimValues trim;
  std::vector<ModelFit> fits;
  std::vector<std::string> notes;  // segments that could not be used, and why
};

// Throws std::runtime_error when a needed column is missing.
Identification Identify(const LogTable& log, const KnownParams& known);

// The result as JSON text (units in the key names' documentation in docs/modules/flight-stack.md).
std::string ToJson(const Identification& id);

}  // namespace uav::sysid
