// DDS topic names (ROS 2 style: "rt/" + ROS topic name). See docs/architecture.md for types,
// QoS, rates and units of each.
#pragma once

namespace mostar::dds::topics {

// ROS 2 compatible sensor topics.
inline constexpr const char* kCameraLeft = "rt/mostar/camera/left/image_raw/compressed";
inline constexpr const char* kCameraRight = "rt/mostar/camera/right/image_raw/compressed";
inline constexpr const char* kCameraInfoLeft = "rt/mostar/camera/left/camera_info";
inline constexpr const char* kCameraInfoRight = "rt/mostar/camera/right/camera_info";
inline constexpr const char* kScan = "rt/mostar/scan";
inline constexpr const char* kOdometry = "rt/mostar/odom";
// One sensor_msgs/Range sample per sonar per belt cycle; frame_id names the sensor.
inline constexpr const char* kSonarRange = "rt/mostar/sonar/range";
// foxglove_msgs/CompressedVideo, one eye's H.264 stream (camera codec H264), for Foxglove and
// ROS 2 tools; written only while a reader is matched.
inline constexpr const char* kCameraLeftVideo = "rt/mostar/camera/left/h264";
inline constexpr const char* kCameraRightVideo = "rt/mostar/camera/right/h264";

// mostar's own topics.
inline constexpr const char* kCommand = "rt/mostar/cmd_vel";
inline constexpr const char* kEmergencyStop = "rt/mostar/estop";
inline constexpr const char* kControlRequest = "rt/mostar/control/request";
inline constexpr const char* kControlLease = "rt/mostar/control/lease";
inline constexpr const char* kHealth = "rt/mostar/health";
inline constexpr const char* kClockPing = "rt/mostar/clock/ping";
inline constexpr const char* kClockPong = "rt/mostar/clock/pong";
// FrameTiming_: capture, encode and write instants of each pair sent (latency trace).
inline constexpr const char* kCameraTiming = "rt/mostar/camera/timing";
inline constexpr const char* kSonar = "rt/mostar/sonar";  // SonarRing_: the belt with mounts
inline constexpr const char* kBumpers = "rt/mostar/bumpers";
// StereoVideoFrame_: both eyes' H.264 access units of one capture (camera codec H264).
inline constexpr const char* kCameraStereoVideo = "rt/mostar/camera/stereo/h264";
// KeyframeRequest_: a viewer asks for an IDR (default partition: any viewer may ask; the robot
// acts on one per 300 ms).
inline constexpr const char* kKeyframeRequest = "rt/mostar/keyframe_request";
// VideoFeedback_: a viewer's receive times of the H.264 frames, for the robot's rate control
// (default partition, like keyframe requests).
inline constexpr const char* kVideoFeedback = "rt/mostar/video_feedback";

}  // namespace mostar::dds::topics
