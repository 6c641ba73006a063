#include "uav/runtime/flight_log.hpp"

#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "uav/runtime/reported_state.hpp"

namespace uav::runtime {

FlightLog::FlightLog(const std::string& dir, int64_t start_utime, AttitudeMode attitude_mode, const GeodeticPoint& home,
                     std::vector<LogColumn> extra)
    : start_utime_(start_utime), attitude_mode_(attitude_mode), home_(home), extra_(std::move(extra)) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  path_ = (std::filesystem::path(dir) / ("flight_" + std::to_string(start_utime) + ".csv")).string();
  file_ = std::fopen(path_.c_str(), "w");
  if (!file_) throw std::runtime_error("cannot write flight log '" + path_ + "'");
  std::fprintf(file_, "%s\n", Header().c_str());
  std::fflush(file_);
}

FlightLog::~FlightLog() {
  if (file_) std::fclose(file_);
}

void FlightLog::Flush() {
  std::fflush(file_);
  rows_since_flush_ = 0;
}

std::string FlightLog::Header() const {
  std::string h = "t";
  for (const auto& s : VehicleStateSignals()) h += "," + std::string(s.def.name);
  for (const std::string& name : ReportSlots<VehicleReports>::ColumnNames()) h += "," + name;
  for (const LogColumn& c : extra_) h += "," + c.name;
  return h;
}

void FlightLog::Write(int64_t utime, const BlackboardData& d, const std::vector<double>& reports) {
  const VehicleState state = ReportedState(d, home_, attitude_mode_);
  std::string row;
  char t[32];
  std::snprintf(t, sizeof t, "%.3f", (utime - start_utime_) * 1e-6);
  row += t;
  for (const auto& s : VehicleStateSignals()) row += "," + FormatForLog(s.def, s.read(state));
  const std::vector<SignalDef>& report_defs = ReportSlots<VehicleReports>::ColumnDefs();
  for (std::size_t i = 0; i < report_defs.size(); ++i) {
    const double v = i < reports.size() ? reports[i] : std::numeric_limits<double>::quiet_NaN();
    row += "," + (std::isfinite(v) ? FormatForLog(report_defs[i], v) : std::string("nan"));
  }
  for (const LogColumn& c : extra_) {
    char v[32];
    const double x = c.read();
    std::snprintf(v, sizeof v, "%.3f", x);
    row += std::isfinite(x) ? std::string(",") + v : std::string(",nan");
  }
  row += '\n';
  std::fputs(row.c_str(), file_);
  // Flush every 5 rows (0.1 s) so that a crash or kill -9 loses at most that much (the limit is
  // 0.2 s; integration.kill9_logs measures it).
  if (++rows_since_flush_ >= 5) {
    std::fflush(file_);
    rows_since_flush_ = 0;
  }
}

}  // namespace uav::runtime
