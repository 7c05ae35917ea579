// The e-stop the operator asked for, kept until the robot reports it. The e-stop topic is
// volatile: a sample lost on the way, or sent while the robot restarts, would otherwise leave
// the robot driving. An engagement is sent at once and re-sent every `resend_period` until a
// robot health received after the request reports the e-stop engaged, however long that takes;
// a release likewise, but for at most `release_timeout` (a release the robot refuses, e.g. from
// an observer, is not repeated for ever). A new request replaces the pending one. Once
// confirmed, nothing is re-sent: a later change made by someone else is not fought.
// Pure: the caller passes the time (steady clock of this machine) and the robot's reports. Not
// thread-safe.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "common/time/time.h"

namespace mostar::ui {

struct EstopResenderOptions {
  Duration resend_period = std::chrono::milliseconds(250);  // > 0
  Duration release_timeout = std::chrono::seconds(3);       // > 0
  bool IsValid(std::string* error) const;
};

// The robot's e-stop as its latest health reported it, and when that report arrived here.
struct ReportedEstop {
  bool engaged = false;
  SteadyTime received;
};

struct EstopResenderStats {
  uint64_t requests = 0;
  uint64_t sent = 0;    // samples handed out by Due(), first sends and re-sends
  uint64_t resent = 0;  // of which re-sends
  uint64_t confirmed = 0;
  uint64_t releases_unconfirmed = 0;  // given up after release_timeout
};

class EstopResender {
 public:
  explicit EstopResender(const EstopResenderOptions& options = {});

  // The operator asks to engage (true) or release (false) at `now`.
  void Request(bool engage, SteadyTime now);
  // A robot health report; confirms the pending request when it was received after the request
  // and reports the requested state.
  void OnRobotReport(const ReportedEstop& report);
  // The state to send now, if any: the pending request when it was never sent or was last sent
  // at least resend_period ago.
  std::optional<bool> Due(SteadyTime now);

  // The request not confirmed yet, if any.
  std::optional<bool> pending() const { return pending_; }
  const EstopResenderStats& stats() const { return stats_; }

 private:
  const EstopResenderOptions options_;
  std::optional<bool> pending_;
  SteadyTime requested_;
  std::optional<SteadyTime> last_sent_;
  EstopResenderStats stats_;
};

}  // namespace mostar::ui
