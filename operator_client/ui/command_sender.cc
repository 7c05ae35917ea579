#include "operator_client/ui/command_sender.h"

namespace mostar::ui {

CommandSender::CommandSender(const CommandSenderOptions& options, CommandSinks sinks,
                             const Clock* clock)
    : options_(options), sinks_(std::move(sinks)), clock_(clock), estop_(options.estop) {
  next_ping_ = clock_->SteadyNow();
}

CommandSender::~CommandSender() { Stop(); }

void CommandSender::Start() {
  if (thread_.joinable()) return;
  thread_ = std::thread([this] {
    SteadyTime next = clock_->SteadyNow();
    while (!stop_) {
      next += options_.command_period;
      Tick();
      std::this_thread::sleep_until(next);
    }
  });
}

void CommandSender::Stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void CommandSender::SetDrive(const DriveOutput& drive) {
  std::lock_guard<std::mutex> lock(mutex_);
  drive_ = drive;
}

void CommandSender::SetActive(bool active) {
  std::lock_guard<std::mutex> lock(mutex_);
  active_ = active;
}

void CommandSender::RequestControl(bool take) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_control_ = take;
}

void CommandSender::SendEmergencyStop(bool engage) {
  const SteadyTime now = clock_->SteadyNow();
  std::lock_guard<std::mutex> lock(mutex_);
  estop_.Request(engage, now);
}

std::optional<bool> CommandSender::pending_estop() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return estop_.pending();
}

EstopResenderStats CommandSender::estop_stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return estop_.stats();
}

void CommandSender::Tick() {
  DriveOutput drive;
  bool active = true;
  std::optional<bool> control;
  std::optional<bool> estop;
  const std::optional<ReportedEstop> reported =
      sinks_.robot_estop ? sinks_.robot_estop() : std::nullopt;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    drive = drive_;
    active = active_;
    control.swap(pending_control_);
    if (reported) estop_.OnRobotReport(*reported);
    estop = estop_.Due(clock_->SteadyNow());
  }
  const Time now = clock_->Now();
  if (estop && sinks_.estop) sinks_.estop({now, options_.client_id, *estop});
  if (control && sinks_.control) {
    sinks_.control({now, options_.client_id, options_.strength, *control});
  }
  if (options_.pilot && active && sinks_.command) {
    VelocityCommand cmd;
    cmd.stamp = now;
    cmd.sequence = ++sequence_;
    cmd.sender_id = options_.client_id;
    cmd.enable = drive.enable;
    cmd.linear_mps = drive.enable ? drive.linear_mps : 0.0;
    cmd.angular_radps = drive.enable ? drive.angular_radps : 0.0;
    if (sinks_.command(cmd)) {
      ++commands_sent_;
      if (sinks_.on_sent) sinks_.on_sent(cmd);
    }
  }
  const SteadyTime steady = clock_->SteadyNow();
  if (steady >= next_ping_ && sinks_.ping) {
    next_ping_ = steady + options_.ping_period;
    ClockProbe probe;
    probe.sender_id = options_.client_id;
    probe.sequence = ++ping_sequence_;
    probe.t0 = now;
    sinks_.ping(probe);
  }
}

}  // namespace mostar::ui
