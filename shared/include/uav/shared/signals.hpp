#pragma once
// Telemetry signals: a named, unit-carrying number read from a typed message. One table per
// message drives the GCS's telemetry tree, its plots, scripts and CSV export, and the vehicle's
// flight-log columns; a signal is declared in its table and nowhere else.
#include <string>
#include <string_view>
#include <vector>

namespace uav {

// How a signal is shown and logged. SI inside; the UI shows angles in degrees.
enum class SignalFormat {
  kMetres, kSpeed, kAccel, kAngle, kAngularRate, kLatLon, kGeodeticAlt, kNormalised, kVolts, kFraction,
  kInteger, kBool, kTask, kFailsafe, kFlightMode, kAttitudeMode, kAvoidState, kMilliseconds, kVehicleType, kVtolMode
};

struct SignalDef {
  std::string_view name;   // as in scripts, plots and the flight-log header ("phi")
  std::string_view field;  // the message field it reads ("rotor_input[0]"); empty: derived
  std::string_view unit;   // SI unit of the value ("rad", "m/s", "1" dimensionless)
  std::string_view frame;  // "N", "B", "WGS84", or empty
  SignalFormat format;
};

// The unit the UI shows ("deg" for angles) and the value converted to it.
std::string_view DisplayUnit(const SignalDef& d);
double DisplayValue(const SignalDef& d, double si);
// The value as the operator reads it: "12.35 m", "-3.1 deg", "hover", "yes", "75 %".
std::string FormatForDisplay(const SignalDef& d, double si);
// The value as the flight log writes it (fixed decimals per format, integers as integers).
std::string FormatForLog(const SignalDef& d, double si);

// A signal of a typed message T: its declaration and how to read it.
template <class T>
struct Signal {
  SignalDef def;
  double (*read)(const T&);
};

// A vehicle report's signals (uav/shared/reports.hpp): the group they go by ("DEPTH": keys
// "DEPTH.r0c0" in the GCS and flight-log columns of that name) and their table. Specialised
// beside each report's struct; a report without one has no signals.
template <class T>
struct ReportSignals {
  static constexpr std::string_view kGroup = "";
  static const std::vector<Signal<T>>& Table() {
    static const std::vector<Signal<T>> kNone;
    return kNone;
  }
};

}  // namespace uav
