#include "uav/app/flight_log.hpp"

#include <filesystem>
#include <stdexcept>

namespace uav::app {

FlightLog::FlightLog(const std::string& dir, int64_t start_utime, int attitude_mode)
    : start_utime_(start_utime), attitude_mode_(attitude_mode) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  path_ = (std::filesystem::path(dir) / ("flight_" + std::to_string(start_utime) + ".csv")).string();
  file_ = std::fopen(path_.c_str(), "w");
  if (!file_) throw std::runtime_error("cannot write flight log '" + path_ + "'");
  std::fprintf(file_, "%s\n", Header());
  std::fflush(file_);
}

FlightLog::~FlightLog() {
  if (file_) std::fclose(file_);
}

const char* FlightLog::Header() {
  return "t,x,y,z,u,v,w,phi,theta,psi,p,q,r,acx,acy,acz,M1,M2,M3,M4,Ua,Ue,Uth,Ur,"
         "armed,task,battery_v,mission_item,capturing,obstacle_range_m,chirp,att_mode";
}

void FlightLog::Write(int64_t utime, const BlackboardData& d) {
  const auto& e = d.estimate;
  const Eigen::Vector3d v_B = e.q_NB.conjugate() * e.v_N;
  std::fprintf(file_,
               "%.3f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.4f,%.4f,%.4f,"
               "%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%d,%d,%.3f,%d,%d,%.3f,%d,%d\n",
               (utime - start_utime_) * 1e-6, e.p_N.x(), e.p_N.y(), e.p_N.z(), v_B.x(), v_B.y(),
               v_B.z(), e.euler.phi, e.euler.theta, e.euler.psi, e.w_B.x(), e.w_B.y(), e.w_B.z(),
               e.f_B.x(), e.f_B.y(), e.f_B.z(), d.rotor_inputs[0], d.rotor_inputs[1],
               d.rotor_inputs[2], d.rotor_inputs[3], d.servo.aileron, d.servo.elevator,
               d.servo.throttle, d.servo.rudder, d.armed ? 1 : 0, static_cast<int>(d.task),
               d.sample.battery_voltage_v, d.mission_item,
               d.capture_interval_s || d.capture_distance_m ? 1 : 0, d.obstacle_range_m, d.chirp_channel,
               attitude_mode_);
  // Flush every 5 rows (0.1 s) so that a crash or kill -9 loses at most that much (the limit is
  // 0.2 s; integration.kill9_logs measures it).
  if (++rows_since_flush_ >= 5) {
    std::fflush(file_);
    rows_since_flush_ = 0;
  }
}

}  // namespace uav::app
