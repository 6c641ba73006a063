#pragma once
// The hover position and velocity loops' gains and limits (the vehicle file's ctl_*), shared by
// the quadrotor's controller and the tail-sitter's hover.
#include "uav/shared/parameters.hpp"

namespace uav::control {

struct PositionLoopParams {
  double pos_gain_xy, pos_gain_z, vel_gain_xy, vel_int_xy, vel_gain_z, vel_int_z, vel_int_limit;
  double speed_max_xy, speed_max_up, speed_max_down, accel_max_xy;
  static PositionLoopParams FromParameters(const ParameterSet& p) {
    return {p.Get("ctl_pos_gain_xy"),  p.Get("ctl_pos_gain_z"),    p.Get("ctl_vel_gain_xy"),    p.Get("ctl_vel_int_xy"),
            p.Get("ctl_vel_gain_z"),   p.Get("ctl_vel_int_z"),     p.Get("ctl_vel_int_limit"),  p.Get("ctl_speed_max_xy"),
            p.Get("ctl_speed_max_up"), p.Get("ctl_speed_max_down"), p.Get("ctl_accel_max_xy")};
  }
};

}  // namespace uav::control
