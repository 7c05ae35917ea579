#include "operator_client/ui/estop_resender.h"

#include "common/check/check.h"

namespace mostar::ui {

bool EstopResenderOptions::IsValid(std::string* error) const {
  if (resend_period <= Duration::zero() || release_timeout <= Duration::zero()) {
    if (error) *error = "resend_period and release_timeout must be positive";
    return false;
  }
  return true;
}

EstopResender::EstopResender(const EstopResenderOptions& options) : options_(options) {
  std::string error;
  MOSTAR_CHECK(options_.IsValid(&error)) << error;
}

void EstopResender::Request(bool engage, SteadyTime now) {
  ++stats_.requests;
  pending_ = engage;
  requested_ = now;
  last_sent_.reset();
}

void EstopResender::OnRobotReport(const ReportedEstop& report) {
  if (!pending_ || report.received < requested_ || report.engaged != *pending_) return;
  pending_.reset();
  ++stats_.confirmed;
}

std::optional<bool> EstopResender::Due(SteadyTime now) {
  if (!pending_) return std::nullopt;
  if (!*pending_ && now - requested_ >= options_.release_timeout) {
    pending_.reset();
    ++stats_.releases_unconfirmed;
    return std::nullopt;
  }
  if (last_sent_ && now - *last_sent_ < options_.resend_period) return std::nullopt;
  if (last_sent_) ++stats_.resent;
  ++stats_.sent;
  last_sent_ = now;
  return pending_;
}

}  // namespace mostar::ui
