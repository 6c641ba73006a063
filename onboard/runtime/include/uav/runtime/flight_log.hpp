#pragma once
// DLG thread's CSV flight log (thesis 2.3.2): a header row, then one row per 20 ms with time,
// every signal of the vehicle-state table (Table 2.3's first, under the thesis's names), then
// every vehicle report's signals ("VO.inliers", the newest report's, nan before the first):
// the same tables the GCS shows; readable by MATLAB, Excel and pandas.
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "uav/runtime/blackboard.hpp"
#include "uav/shared/vehicle_enums.hpp"
#include "uav/shared/geodesy.hpp"

namespace uav::runtime {

// A column of the backend's own (the simulator's true clearance): its name (with its unit, as
// "clearance_m") and how to read it on the log's thread (thread-safe; nan: none).
struct LogColumn {
  std::string name;
  std::function<double()> read;
};

class FlightLog {
 public:
  // Creates DIR/flight_<utime>.csv (DIR is created if missing). Throws std::runtime_error
  // naming the path when it cannot be written. `attitude_mode` is written on every row so that
  // uav-sysid knows which model structure the data follow; `home` is the origin of N.
  // `extra`: columns the vehicle's backend adds after the others (the simulator's truth).
  FlightLog(const std::string& dir, int64_t start_utime, AttitudeMode attitude_mode, const GeodeticPoint& home = {},
            std::vector<LogColumn> extra = {});
  ~FlightLog();
  FlightLog(const FlightLog&) = delete;
  FlightLog& operator=(const FlightLog&) = delete;

  std::string Header() const;
  // `reports`: the vehicle reports' columns (ReportSlots::Columns()); empty: all nan.
  void Write(int64_t utime, const BlackboardData& d, const std::vector<double>& reports = {});
  const std::string& path() const { return path_; }
  void Flush();  // every row written so far is in the file

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  int64_t start_utime_;
  AttitudeMode attitude_mode_;
  GeodeticPoint home_;
  std::vector<LogColumn> extra_;
  int rows_since_flush_ = 0;
};

}  // namespace uav::runtime
