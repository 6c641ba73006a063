#pragma once
// The wire form of the plain data in uav/shared: each LCM type is converted here, once, in each
// direction. FromMessage throws std::invalid_argument naming the field that is wrong; ToMessage
// fills everything but the header (the link's). Only the links, the fuzzers and the link tests
// include this (the rest of the program knows no LCM).
#include "uav/shared/active_stereo.hpp"
#include "uav/shared/avoidance_report.hpp"
#include "uav/shared/manual_control.hpp"
#include "uav/shared/mono_depth.hpp"
#include "uav/shared/obstacles.hpp"
#include "uav/shared/operator_messages.hpp"
#include "uav/shared/power_lines.hpp"
#include "uav/shared/parameter_table.hpp"
#include "uav/shared/pre_arm.hpp"
#include "uav/shared/sensing.hpp"
#include "uav/shared/tracking.hpp"
#include "uav/shared/vehicle_state.hpp"
#include "uav/shared/visual_odometry.hpp"
#include "uavmsg/active_stereo_t.hpp"
#include "uavmsg/avoidance_t.hpp"
#include "uavmsg/command_ack_t.hpp"
#include "uavmsg/map_tile_t.hpp"
#include "uavmsg/video_frame_t.hpp"
#include "uavmsg/mono_depth_t.hpp"
#include "uavmsg/obstacles_t.hpp"
#include "uavmsg/point_cloud_t.hpp"
#include "uavmsg/power_lines_t.hpp"
#include "uavmsg/param_table_t.hpp"
#include "uavmsg/pre_arm_t.hpp"
#include "uavmsg/sensing_t.hpp"
#include "uavmsg/track_status_t.hpp"
#include "uavmsg/track_target_t.hpp"
#include "uavmsg/manual_control_t.hpp"
#include "uavmsg/vehicle_state_t.hpp"
#include "uavmsg/visual_odometry_t.hpp"

namespace uav {

// The operator's messages (uav/shared/operator_messages.hpp): a JPEG's size must match its
// bytes (at most MAX_JPEG_BYTES); a result must be one the enum names.
VideoFrame FromMessage(const uavmsg::video_frame_t& m);
uavmsg::video_frame_t ToMessage(const VideoFrame& f);
MapTile FromMessage(const uavmsg::map_tile_t& m);
uavmsg::map_tile_t ToMessage(const MapTile& t);
CommandAck FromMessage(const uavmsg::command_ack_t& m);
uavmsg::command_ack_t ToMessage(const CommandAck& a);

// Active stereo (uav/shared/active_stereo.hpp)
// Throws std::invalid_argument naming what is wrong (arrays of other lengths, too many points or
// clusters, non-finite numbers, a cluster index out of range, an unhealthy report with a height
// or points, a healthy one without a positive height).
ActiveStereoReport FromMessage(const uavmsg::active_stereo_t& m);
uavmsg::active_stereo_t ToMessage(const ActiveStereoReport& r);

// Obstacle avoidance's plan and map (uav/shared/avoidance_report.hpp)
// Throws std::invalid_argument naming what is wrong (arrays of other lengths, more points or
// cells than the maximum, a state the planner does not send, non-finite numbers, a negative
// length or a cell size out of 0.05..2 m).
AvoidanceReport FromMessage(const uavmsg::avoidance_t& m);
// Keeps the first MAX_PATH path points and MAX_CELLS cells (the nearest) within 327 m of the origin.
uavmsg::avoidance_t ToMessage(const AvoidanceReport& r);

// Depth from motion (uav/shared/mono_depth.hpp)
// Throws std::invalid_argument naming what is wrong (a grid that is not rows x cols or larger
// than MAX_CELLS, arrays of other lengths, a state out of range, non-finite or negative
// numbers, a known cell without a depth, an unhealthy report with known cells).
DepthGrid FromMessage(const uavmsg::mono_depth_t& m);
uavmsg::mono_depth_t ToMessage(const DepthGrid& g);

// Stereo obstacles and the point cloud (uav/shared/obstacles.hpp)
// Throw std::invalid_argument naming what is wrong (counts that disagree with the arrays, more
// than the maximum, non-finite values, a top below the bottom, a negative radius or variance).
Obstacles FromMessage(const uavmsg::obstacles_t& m);
PointCloud FromMessage(const uavmsg::point_cloud_t& m);
// Keep the first MAX_OBSTACLES (nearest) obstacles.
uavmsg::obstacles_t ToMessage(const Obstacles& o);
// Keeps at most MAX_POINTS points (evenly spaced) within 327 m of the origin.
uavmsg::point_cloud_t ToMessage(const PointCloud& c);

// Power lines (uav/shared/power_lines.hpp)
// Throws std::invalid_argument naming what is wrong: array sizes that disagree with their
// counts, more than MAX_WIRES wires, non-finite or out-of-image coordinates, a range without
// points.
PowerLines FromMessage(const uavmsg::power_lines_t& m);
// Keeps the first MAX_WIRES wires (longest first).
uavmsg::power_lines_t ToMessage(const PowerLines& p);

// Sensing health (uav/shared/sensing.hpp)
// Throws std::invalid_argument naming what is wrong (a non-finite or negative figure, a nameless
// worker, an unhealthy worker without a reason).
SensingReport FromMessage(const uavmsg::sensing_t& m);
uavmsg::sensing_t ToMessage(const SensingReport& r);

// Pre-arm checks (uav/shared/pre_arm.hpp)
// Throws std::invalid_argument naming what is wrong (a count that disagrees, a nameless check, a
// failing check without a reason).
PreArmReport FromMessage(const uavmsg::pre_arm_t& m);
uavmsg::pre_arm_t ToMessage(const PreArmReport& r);

// The parameter table (uav/shared/parameter_table.hpp)
// Throws std::invalid_argument naming what is wrong (a count that disagrees, a nameless
// parameter, a value outside its limits or not finite, an unknown apply).
ParameterTable FromMessage(const uavmsg::param_table_t& m);
uavmsg::param_table_t ToMessage(const ParameterTable& t);

// The operator's sticks (uav/shared/manual_control.hpp). Throws std::invalid_argument naming the
// axis that is not a number in [-1, 1]; utime is the message's.
ManualSticks FromMessage(const uavmsg::manual_control_t& m);
uavmsg::manual_control_t ToMessage(const ManualSticks& s);

// Tracking: the selection and the tracker's status (uav/shared/tracking.hpp)
// Throws std::invalid_argument naming the first non-finite or out-of-range field.
TrackTarget FromMessage(const uavmsg::track_target_t& m);
uavmsg::track_target_t ToMessage(const TrackTarget& t);
TrackStatus FromMessage(const uavmsg::track_status_t& m);
uavmsg::track_status_t ToMessage(const TrackStatus& r);

// Vehicle state (uav/shared/vehicle_state.hpp)
// Decoding rejects, with std::invalid_argument naming the field, what the typed state cannot
// hold: a non-finite position, attitude or home, or an enum value no version of us sends.
VehicleState FromMessage(const uavmsg::vehicle_state_t& m);
void ToMessage(const VehicleState& s, uavmsg::vehicle_state_t* m);  // all but the header

// Visual odometry (uav/shared/visual_odometry.hpp)
// Throws std::invalid_argument naming what is wrong (a non-finite number, a negative count, an
// unknown source or method, an unhealthy report without a reason).
VisualOdometryReport FromMessage(const uavmsg::visual_odometry_t& m);
uavmsg::visual_odometry_t ToMessage(const VisualOdometryReport& r);

}  // namespace uav
