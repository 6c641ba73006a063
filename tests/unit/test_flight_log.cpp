#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "uav/app/flight_log.hpp"

namespace uav::app {
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

TEST(FlightLog, UnwritableDirectoryNamesThePath) {
  try {
    FlightLog log("/proc/definitely/not/here", 1, AttitudeMode::kDirect);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/definitely/not/here"), std::string::npos);
  }
}

}  // namespace
}  // namespace uav::app
