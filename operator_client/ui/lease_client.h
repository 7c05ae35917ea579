// The console's side of the pilot lease (robot_server/drive): pilots ask for control until the
// robot's lease names them, repeating the request because it travels on a volatile topic;
// the operator can give control up and ask again. Pure: the caller passes the lease it last
// received and the time, and sends the request this returns (CommandSender::RequestControl).
#pragma once

#include <optional>
#include <string>

#include "common/time/time.h"
#include "common/types/commands.h"

namespace mostar::ui {

// What to send to the robot's lease arbiter.
enum class ControlRequest { kNone, kTake, kRelease };

class LeaseClient {
 public:
  // Re-request period while a wanted lease has not shown up. Requests written while the robot
  // is not matched are lost (volatile), so after a rediscovery the next one is what gets
  // through: short, so that control comes back soon after the link (a request is ~100 bytes).
  static constexpr Duration kRequestPeriod = std::chrono::milliseconds(250);
  // Scripted drives arm once the lease has been held for longer than this: three command
  // periods, so the robot has seen enable = false after its lease change before enable = true.
  static constexpr Duration kArmDelay = std::chrono::milliseconds(150);

  // `pilot`: this console may drive, and wants control from the start (the first Update()
  // asks for it). Observers never ask.
  LeaseClient(std::string client_id, bool pilot);

  // With the latest lease the robot published (nullopt: none yet) at `now` (steady): kTake when
  // control is wanted, not held, and the last request is at least kRequestPeriod old.
  ControlRequest Update(const std::optional<ControlLease>& lease, SteadyTime now);
  // The operator asks for control (pilots only; ignored for observers): the next Update() sends
  // the request at once.
  void Take();
  // The operator gives control up: send the returned kRelease; no more requests until Take().
  ControlRequest Release();

  bool holding() const { return holding_since_.has_value(); }  // as of the last Update()
  // Control is wanted or held: the command sender should stream drive commands.
  bool active() const { return want_control_ || holding(); }
  // Held for more than kArmDelay at `now` (a scripted drive may start).
  bool armed(SteadyTime now) const { return holding_since_ && now - *holding_since_ > kArmDelay; }

 private:
  const std::string client_id_;
  const bool pilot_;
  bool want_control_;
  std::optional<SteadyTime> next_request_;   // nullopt: at the next Update()
  std::optional<SteadyTime> holding_since_;  // first Update() that saw us hold the lease
};

}  // namespace mostar::ui
