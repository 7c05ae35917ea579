// The simulated MORDUC in its scene: one object that answers velocity commands and produces
// laser scans, stereo pairs and encoder counts at a given time, with their ground truth.
//
// Time is injected: each call names the time `t` it is for and the robot is first integrated up
// to `t` (fixed steps; a `t` earlier than the last one is served from the current state). The
// world starts at the `start` time given to Create.
//
// Threading: every method may be called from any thread. One thread usually steps and commands
// (AdvanceTo, SetVelocity), others read (ScanAt, StereoAt, EncodersAt). State is guarded by a
// mutex; rendering happens outside it, from a snapshot of the pose.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "common/time/time.h"
#include "common/types/laser_scan.h"
#include "common/types/odometry.h"
#include "robot_server/sim/bumper_contacts.h"
#include "robot_server/sim/diff_drive.h"
#include "robot_server/sim/ground_truth.h"
#include "robot_server/sim/laser_raycast.h"
#include "robot_server/sim/scene.pb.h"
#include "robot_server/sim/sim_config.pb.h"
#include "robot_server/sim/sonar_raycast.h"
#include "robot_server/sim/stereo_renderer.h"
#include "robot_server/sim/world.h"

namespace mostar::sim {

// Reads and checks a SimConfig file: ranges (config_loader) and the combinations the LMS200
// does not offer (0.25 deg needs the 100 deg field of view). Error: "<file>: <key>: <reason>".
bool LoadSimConfig(const std::string& path, proto::SimConfig* config, std::string* error);
bool ValidateSimConfig(const proto::SimConfig& config, const std::string& name, std::string* error);

// Everything known about the robot at one instant.
struct RobotState {
  Time time;
  Pose2D world_from_base;
  double linear_mps = 0;
  double angular_radps = 0;
  EncoderTicks encoders;
  bool in_collision = false;     // the robot is pressed against an obstacle now
  uint64_t collision_count = 0;  // contacts since start
};

class SimWorld {
 public:
  // Builds the world; fails (with a message) on an invalid config or a start pose whose
  // footprint overlaps an obstacle. `scene` must have passed ValidateScene.
  static std::unique_ptr<SimWorld> Create(const proto::Scene& scene, const proto::SimConfig& config,
                                          Time start, std::string* error);

  SimWorld(const SimWorld&) = delete;
  SimWorld& operator=(const SimWorld&) = delete;

  // Velocity of the robot (axle midpoint): m/s forward, rad/s counter-clockwise. Clamped to
  // the configured limits, reached with the configured accelerations; holds until replaced.
  void SetVelocity(double linear_mps, double angular_radps);
  // Integrates the robot up to t.
  void AdvanceTo(Time t);

  // A laser scan (laser frame) at t; `truth` gets the noise-free ranges and the pose.
  LaserScan ScanAt(Time t, LaserGroundTruth* truth = nullptr);
  // The ranges of ScanAt(t), for the LMS200 emulator: metres, +Inf = no echo (nothing within
  // the maximum range), NaN = dazzled, beam 0 at the rightmost angle.
  std::vector<float> RangesAt(Time t);
  // Ranges of `count` beams at angle_min + i * increment (laser frame) at t, same conventions;
  // the beam layout is the caller's (the LMS200 emulator follows its host's configuration).
  void SampleRanges(Time t, double angle_min_rad, double increment_rad, int count,
                    std::vector<float>* ranges_m);
  // A stereo pair at t (BGR8 images); with `with_truth` the labels and base rows too.
  StereoImages StereoAt(Time t, bool with_truth, Pose2D* world_from_base = nullptr);
  // The first echo of a sonar at `mount` at t (sonar_raycast.h: metres, +Inf = nothing).
  float SonarEchoAt(Time t, const SonarMount& mount, const SonarCone& cone);
  // The pressed bumper segments at t (bumper_contacts.h; bit i = segment i of `count`).
  uint32_t BumpersAt(Time t, int count);
  EncoderTicks EncodersAt(Time t);
  RobotState StateAt(Time t);

  const LaserCameraCalibration& calibration() const { return renderer_.params().calibration; }
  const LaserParams& laser_params() const { return laser_.params(); }
  const DriveParams& drive_params() const { return drive_.params(); }
  const World& world() const { return *world_; }

 private:
  SimWorld(std::unique_ptr<World> world, const proto::SimConfig& config, Time start);
  void AdvanceLocked(Time t);

  std::unique_ptr<World> world_;
  mutable std::mutex mutex_;
  DiffDrive drive_;           // guarded by mutex_
  LaserRaycaster laser_;      // guarded by mutex_
  StereoRenderer renderer_;   // const, thread-safe
  Time time_;                 // guarded by mutex_
  uint64_t frame_index_ = 0;  // guarded by mutex_
};

}  // namespace mostar::sim
