#pragma once
// Each vehicle report's wire form: its LCM message type and its topic (the channel is
// "<vehicle>/<topic>"), declared once, here only. The conversions are the FromMessage/ToMessage
// overloads of uav/wire/messages.hpp.
#include "uav/shared/channels.hpp"
#include "uav/shared/reports.hpp"
#include "uav/wire/messages.hpp"

namespace uav {

template <class T>
struct Report;  // specialised once per type of VehicleReports

template <>
struct Report<PowerLines> {
  using Message = uavmsg::power_lines_t;
  static constexpr Topic kTopic{"POWER_LINES"};
};
template <>
struct Report<Obstacles> {
  using Message = uavmsg::obstacles_t;
  static constexpr Topic kTopic{"OBSTACLES"};
};
template <>
struct Report<PointCloud> {
  using Message = uavmsg::point_cloud_t;
  static constexpr Topic kTopic{"POINT_CLOUD"};
};
template <>
struct Report<DepthGrid> {
  using Message = uavmsg::mono_depth_t;
  static constexpr Topic kTopic{"MONO_DEPTH"};
};
template <>
struct Report<ActiveStereoReport> {
  using Message = uavmsg::active_stereo_t;
  static constexpr Topic kTopic{"ACTIVE_STEREO"};
};
template <>
struct Report<VisualOdometryReport> {
  using Message = uavmsg::visual_odometry_t;
  static constexpr Topic kTopic{"VISUAL_ODOMETRY"};
};
template <>
struct Report<SensingReport> {
  using Message = uavmsg::sensing_t;
  static constexpr Topic kTopic{"SENSING"};
};
template <>
struct Report<PreArmReport> {
  using Message = uavmsg::pre_arm_t;
  static constexpr Topic kTopic{"PRE_ARM"};
};

template <>
struct Report<ParameterTable> {
  using Message = uavmsg::param_table_t;
  static constexpr Topic kTopic{"PARAMS"};
};

template <>
struct Report<AvoidanceReport> {
  using Message = uavmsg::avoidance_t;
  static constexpr Topic kTopic{"AVOIDANCE"};
};

}  // namespace uav
