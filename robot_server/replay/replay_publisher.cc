#include "robot_server/replay/replay_publisher.h"

#include <iostream>
#include <memory>
#include <thread>
#include <type_traits>
#include <variant>

#include "common/log/log.h"
#include "common/process/stop_signals.h"
#include "common/record/recording_reader.h"
#include "common/service/service_notifier.h"
#include "robot_server/replay/replay_control.h"

namespace mostar::replay {

ReplayPublisher::ReplayPublisher(record::ReplayPlayer* player, server::RobotLink* link,
                                 StampTrace* trace)
    : player_(player), link_(link), trace_(trace) {}

size_t ReplayPublisher::PublishDue() {
  size_t count = 0;
  for (const record::RecordedMessage& m : player_->PollDue()) {
    ++count;
    std::visit(
        [&](const auto& p) {
          using T = std::decay_t<decltype(p)>;
          if constexpr (std::is_same_v<T, record::RecordedImage>) {
            link_->PublishImage(p.eye, p.image);
            if (trace_) {
              trace_->Add(p.eye == Eye::kLeft ? "left" : "right", p.image.stamp, p.pair_sequence);
            }
          } else if constexpr (std::is_same_v<T, LaserScan>) {
            link_->PublishScan(p);
            if (trace_) trace_->Add("scan", p.stamp, p.sequence);
          } else if constexpr (std::is_same_v<T, Odometry>) {
            link_->PublishOdometry(p);
          } else if constexpr (std::is_same_v<T, RobotHealth>) {
            link_->PublishHealth(p);
          } else if constexpr (std::is_same_v<T, ControlLease>) {
            link_->PublishLease(p);
          } else if constexpr (std::is_same_v<T, SonarRanges>) {
            link_->PublishSonar(p);
          } else if constexpr (std::is_same_v<T, BumperState>) {
            link_->PublishBumpers(p);
          }
        },
        m.payload);
  }
  published_ += count;
  return count;
}

int RunReplaySession(const ReplaySessionOptions& options, server::RobotLink* link,
                     StampTrace* trace, std::istream* controls) {
  std::string error;
  if (!options.replay.IsValid(&error)) {
    std::cerr << "robot_server: --replay-rate: " << error << "\n";
    return 2;
  }
  // Shared with the control reader, which may outlive this function (blocked in getline).
  std::shared_ptr<record::RecordingReader> reader =
      record::RecordingReader::Open(options.path, &error);
  if (!reader) {
    std::cerr << "robot_server: cannot replay: " << error << "\n";
    return 2;
  }
  const Clock& clock = SystemClock::Instance();
  auto player = std::make_shared<record::ReplayPlayer>(reader.get(), clock, options.replay);
  MOSTAR_LOG(INFO) << "replaying " << options.path << " (robot '" << reader->info().robot_id
                   << "') at " << options.replay.rate << "x"
                   << (options.replay.loop ? ", looping" : "");
  std::thread([player, reader, controls] {
    std::string line;
    while (!StopRequested() && std::getline(*controls, line)) {
      ReplayControl control;
      std::string why;
      if (!ParseReplayControl(line, &control, &why)) {
        MOSTAR_LOG(WARNING) << why;
        continue;
      }
      if (!ApplyReplayControl(control, player.get())) RequestStop();
      if (control.kind == ReplayControl::Kind::kTogglePause) {
        MOSTAR_LOG(INFO) << "replay " << (player->paused() ? "paused" : "resumed");
      } else if (control.kind == ReplayControl::Kind::kSetRate) {
        MOSTAR_LOG(INFO) << "replay rate " << control.rate;
      }
    }
  }).detach();

  ReplayPublisher publisher(player.get(), link, trace);
  service::ServiceNotifier service;
  service.Ready("replaying " + options.path);
  const SteadyTime start = clock.SteadyNow();
  while (!StopRequested() && !player->finished()) {
    service.Alive(clock.SteadyNow());
    publisher.PublishDue();
    if (options.duration > Duration::zero() && clock.SteadyNow() - start > options.duration) break;
    const std::optional<SteadyTime> next = player->NextDueTime();
    const SteadyTime wake = clock.SteadyNow() + std::chrono::milliseconds(50);
    std::this_thread::sleep_until(next ? std::min(*next, wake) : wake);
  }
  if (reader->damage()) {
    MOSTAR_LOG(WARNING) << "recording damaged at byte " << reader->damage()->offset << ": "
                        << reader->damage()->reason << " (replayed everything before it)";
  }
  MOSTAR_LOG(INFO) << "replay done: " << publisher.published() << " records published";
  service.Stopping("replay done");
  if (trace) trace->Flush();
  return 0;
}

}  // namespace mostar::replay
