// Sends the pilot's velocity commands at a steady rate (20 Hz), whatever the render rate, plus
// clock pings (1 Hz), queued control requests, and emergency stops, re-sent until the robot
// reports them (EstopResender, fed by CommandSinks::robot_estop). Commands carry a strictly
// increasing sequence number and the sender's clock stamp; when the deadman is released the
// sender keeps sending enable = false with zero velocity (so the robot stops at once and the
// pilot's liveliness holds). Own thread; the setters are thread-safe.
#pragma once

#include <atomic>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "common/time/time.h"
#include "common/types/commands.h"
#include "operator_client/ui/drive_input.h"
#include "operator_client/ui/estop_resender.h"

namespace mostar::ui {

struct CommandSenderOptions {
  std::string client_id;
  bool pilot = true;      // observers send no velocity commands
  int32_t strength = 10;  // sent in control requests; the robot's role table decides instead
  Duration command_period = std::chrono::milliseconds(50);
  Duration ping_period = std::chrono::seconds(1);
  EstopResenderOptions estop{};
};

// Transport functions (the DDS node in the program, fakes in tests). Each returns false when
// the sample was not sent.
struct CommandSinks {
  std::function<bool(const VelocityCommand&)> command;
  std::function<bool(const ClockProbe&)> ping;
  std::function<bool(const ControlRequest&)> control;
  std::function<bool(const EmergencyStop&)> estop;
  std::function<void(const VelocityCommand&)> on_sent;  // optional: traces
  // Optional: the robot's e-stop as last reported (nullopt before any report). Without it an
  // engagement is re-sent for ever and a release until its timeout.
  std::function<std::optional<ReportedEstop>()> robot_estop;
};

class CommandSender {
 public:
  CommandSender(const CommandSenderOptions& options, CommandSinks sinks, const Clock* clock);
  ~CommandSender();  // Stop()
  void Start();
  void Stop();

  void SetDrive(const DriveOutput& drive);
  // Velocity commands are written only while active (the pilot wants or holds control): an
  // idle pilot must not occupy the exclusively owned command topic.
  void SetActive(bool active);
  void RequestControl(bool take);
  // Engages (true) or releases the e-stop: sent at the next cycle, then re-sent until the robot
  // reports it (see EstopResender).
  void SendEmergencyStop(bool engage);
  uint64_t commands_sent() const { return commands_sent_.load(); }
  // The e-stop request the robot has not confirmed yet, if any.
  std::optional<bool> pending_estop() const;
  EstopResenderStats estop_stats() const;
  // One cycle's work, exposed for tests (Start() calls it periodically).
  void Tick();

 private:
  const CommandSenderOptions options_;
  const CommandSinks sinks_;
  const Clock* clock_;
  mutable std::mutex mutex_;
  DriveOutput drive_;
  bool active_ = true;
  std::optional<bool> pending_control_;
  EstopResender estop_;
  uint64_t sequence_ = 0;
  uint64_t ping_sequence_ = 0;
  SteadyTime next_ping_;
  std::atomic<bool> stop_{false};
  std::atomic<uint64_t> commands_sent_{0};
  std::thread thread_;
};

}  // namespace mostar::ui
