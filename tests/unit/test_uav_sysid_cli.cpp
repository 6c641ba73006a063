// uav-sysid as the operator runs it: on a synthetic flight log whose thrust follows Eq. 2.13
// exactly (so the answer is known), and on broken logs, which must be refused with the file,
// line and column named.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace {

struct CliRun {
  int status;
  std::string out;
};

CliRun RunSysid(const std::string& args) {
  const std::string cmd = std::string(UAV_SYSID_BIN) + " " + args + " 2>&1";
  CliRun r{0, ""};
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p)) r.out += buf;
  r.status = WEXITSTATUS(pclose(p));
  return r;
}

const char* kHeader = "t,x,y,z,u,v,w,phi,theta,psi,p,q,r,acx,acy,acz,M1,M2,M3,M4,Ua,Ue,Uth,Ur,armed,task,chirp,att_mode";

// 12 s of still hover, then a 30 s throttle chirp: thrust = 4 Kf / (1 + tau s) (u - u0), the
// accelerometer reading its mean over each 20 ms (as the simulated IMU does).
std::string SyntheticLog(double Kf, double tau, double u0, double mass) {
  std::ostringstream csv;
  csv << kHeader << "\n";
  const double dt = 0.02;
  const int sub = 200;
  double x = 0.18;  // lag state, steady at the hover input
  double prev_u = 0.18;
  for (int k = 0; k < 2500; ++k) {
    const double t = k * dt;
    // Mean of the lag state over the interval that ends at t, driven by the previous input.
    double mean = x;
    if (k > 0) {
      double sum = 0;
      for (int s = 0; s < sub; ++s) {
        const double before = x;
        x += (prev_u - x) * (1 - std::exp(-dt / sub / tau));
        sum += 0.5 * (before + x);
      }
      mean = sum / sub;
    }
    const bool chirping = t >= 12.0 && t < 42.0;
    const double tc = t - 12.0, kc = (4.0 - 0.2) / 30.0;
    const double u = 0.18 + (chirping ? 0.05 * std::sin(2 * M_PI * (0.2 + kc / 2 * tc) * tc) : 0.0);
    const double acz = -4 * Kf * (mean - u0) / mass;
    char row[512];
    std::snprintf(row, sizeof row,
                  "%.3f,0,0,-10,0,0,0,0,0,0,0,0,0,0,0,%.6f,%.6f,%.6f,%.6f,%.6f,0.066,0.066,%.6f,-0.013,1,2,%d,0\n", t,
                  acz, u, u, u, u, u, chirping ? 3 : 0);
    csv << row;
    prev_u = u;
  }
  return csv.str();
}

std::filesystem::path Dir() {
  const auto d = std::filesystem::temp_directory_path() / "uav_test_sysid_cli";
  std::filesystem::create_directories(d);
  return d;
}

TEST(UavSysid, RecoversTheThrustModelAndWritesJsonAndPlot) {
  const auto log = Dir() / "flight_synthetic.csv";
  std::ofstream(log) << SyntheticLog(3.8738, 0.095583, -0.687, 1.37);
  const auto json_path = Dir() / "sysid.json", plot = Dir() / "sysid.png";
  std::filesystem::remove(json_path);
  std::filesystem::remove(plot);
  const CliRun r = RunSysid(log.string() + " --json " + json_path.string() + " --plot " + plot.string());
  ASSERT_EQ(r.status, 0) << r.out;
  std::ifstream in(json_path);
  const auto j = nlohmann::json::parse(in);
  ASSERT_EQ(j["models"].size(), 1u) << j.dump(2);
  const auto& m = j["models"][0];
  EXPECT_EQ(m["model"], "rotor_thrust");
  EXPECT_NEAR(m["params"]["Kf"].get<double>(), 3.8738, 0.001 * 3.8738);
  EXPECT_NEAR(m["params"]["tau_f"].get<double>(), 0.095583, 0.001 * 0.095583);
  EXPECT_NEAR(m["params"]["u_zero_thrust"].get<double>(), -0.687, 0.001);
  EXPECT_GT(m["fit_percent"].get<double>(), 99.0);
  // The trim comes from the still hover before the chirp (Table 2.4's method).
  EXPECT_NEAR(j["trim"]["values"]["u_th0"].get<double>(), 0.18, 1e-9);
  EXPECT_NEAR(j["trim"]["values"]["u_a0"].get<double>(), 0.066, 1e-9);
  EXPECT_GT(std::filesystem::file_size(plot), 10000u);
}

TEST(UavSysid, BrokenLogsAreRefusedNamingWhatIsWrong) {
  const auto missing = RunSysid((Dir() / "no_such.csv").string());
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.out.find("no_such.csv"), std::string::npos) << missing.out;

  const auto bad_value = Dir() / "bad_value.csv";
  std::string text = SyntheticLog(3.8738, 0.095583, -0.687, 1.37);
  const auto third_row = text.find('\n', text.find('\n', text.find('\n') + 1) + 1) + 1;
  text.replace(third_row, 5, "0.0x0");  // the t field of line 4
  std::ofstream(bad_value) << text;
  const auto r1 = RunSysid(bad_value.string());
  EXPECT_EQ(r1.status, 2);
  EXPECT_NE(r1.out.find("bad_value.csv:4: column t is '0.0x0', not a finite number"), std::string::npos) << r1.out;

  const auto no_column = Dir() / "no_chirp_column.csv";
  std::ofstream(no_column) << "t,x\n0,1\n0.02,1\n";
  const auto r2 = RunSysid(no_column.string());
  EXPECT_EQ(r2.status, 2);
  EXPECT_NE(r2.out.find("no column 'chirp'"), std::string::npos) << r2.out;

  const auto nan_row = Dir() / "nan.csv";
  std::string with_nan = SyntheticLog(3.8738, 0.095583, -0.687, 1.37);
  const auto at = with_nan.find(",1,2,0,0\n");
  with_nan.replace(at, 9, ",nan,2,0,0\n");
  std::ofstream(nan_row) << with_nan;
  const auto r3 = RunSysid(nan_row.string());
  EXPECT_EQ(r3.status, 2);
  EXPECT_NE(r3.out.find("column armed is 'nan'"), std::string::npos) << r3.out;
}

}  // namespace
