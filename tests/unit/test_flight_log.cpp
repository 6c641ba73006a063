#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "uav/runtime/flight_log.hpp"

namespace uav::runtime {
namespace {

TEST(FlightLog, HeaderNamesTable23SignalsAndRowsMatchIt) {
  const auto dir = std::filesystem::temp_directory_path() / "uav_flight_log_test";
  std::filesystem::remove_all(dir);
  std::string path;
  {
    FlightLog log(dir.string(), 1000000, AttitudeMode::kGyroCruise);
    path = log.path();
    BlackboardData d;
    d.estimate.p_N = {1, 2, -3};
    d.rotor_inputs = {0.1, 0.2, 0.3, 0.4};
    d.chirp_channel = 3;
    for (int i = 0; i < 5; ++i) log.Write(1000000 + i * 20000, d);
  }
  std::ifstream in(path);
  std::string header, row, last;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("t,x,y,z,u,v,w,phi,theta,psi,p,q,r,acx,acy,acz,M1,M2,M3,M4,Ua,Ue,Uth,Ur", 0), 0u);
  int rows = 0;
  const auto columns = std::count(header.begin(), header.end(), ',');
  while (std::getline(in, row)) {
    ++rows;
    EXPECT_EQ(std::count(row.begin(), row.end(), ','), columns);
    last = row;
  }
  EXPECT_EQ(rows, 5);
  EXPECT_EQ(last.rfind("0.080,1.0000,2.0000,-3.0000", 0), 0u);
  // Chirp on the throttle, gyro in cruise mode, read by their columns' names (uav-sysid does).
  auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    return cells;
  };
  const auto names = split(header), values = split(last);
  auto value = [&](const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? std::string("missing") : values.at(static_cast<std::size_t>(it - names.begin()));
  };
  EXPECT_EQ(value("chirp"), "3");
  EXPECT_EQ(value("att_mode"), "2");
}

// The vehicle reports' signals follow the state's columns, under their group's name: nan until
// the first report, then the newest report's values.
TEST(FlightLog, ReportColumnsCarryTheNewestReport) {
  const auto dir = std::filesystem::temp_directory_path() / "uav_flight_log_reports_test";
  std::filesystem::remove_all(dir);
  std::string path;
  {
    FlightLog log(dir.string(), 0, AttitudeMode::kDirect);
    path = log.path();
    ReportSlots<VehicleReports> slots;
    log.Write(20000, BlackboardData{}, slots.Columns());
    VisualOdometryReport vo;
    vo.inliers = 57;
    vo.rms_px = 0.25;
    slots.Put(vo);
    SensingReport sensing;
    sensing.control_period_p99_ms = 23.5;
    sensing.workers.resize(3);
    slots.Put(sensing);
    log.Write(40000, BlackboardData{}, slots.Columns());
    EXPECT_TRUE(slots.Take<VisualOdometryReport>());  // the link's slot is unchanged
  }
  std::ifstream in(path);
  std::string header, first, second;
  std::getline(in, header);
  std::getline(in, first);
  std::getline(in, second);
  auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    return cells;
  };
  const auto names = split(header);
  auto value = [&](const std::string& row, const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? std::string("missing") : split(row).at(static_cast<std::size_t>(it - names.begin()));
  };
  EXPECT_EQ(value(first, "VO.inliers"), "nan");
  EXPECT_EQ(value(second, "VO.inliers"), "57");
  EXPECT_EQ(value(second, "SENSING.workers"), "3");
  EXPECT_EQ(value(second, "SENSING.ctl_p99").rfind("23.5", 0), 0u) << value(second, "SENSING.ctl_p99");
  EXPECT_EQ(value(second, "DEPTH.r0c0"), "nan");  // no depth report yet
  EXPECT_EQ(split(second).size(), names.size());
}

TEST(FlightLog, UnwritableDirectoryNamesThePath) {
  try {
    FlightLog log("/proc/definitely/not/here", 1, AttitudeMode::kDirect);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/definitely/not/here"), std::string::npos);
  }
}

}  // namespace
}  // namespace uav::runtime
