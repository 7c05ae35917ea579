#include "robot_server/node/clock_responder.h"

#include "common/check/check.h"

namespace mostar::server {

ClockResponder::ClockResponder(const Clock& clock, size_t max_clients,
                               timesync::ClockOffsetEstimatorOptions estimator)
    : clock_(clock), max_clients_(max_clients), estimator_options_(estimator) {
  MOSTAR_CHECK(max_clients_ >= 1) << "max_clients must be at least 1";
  std::string error;
  MOSTAR_CHECK(estimator_options_.IsValid(&error)) << error;
}

ClockProbe ClockResponder::Answer(const std::string& client_id, const ClockProbe& ping,
                                  Time received) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = clients_.find(client_id);
  if (it == clients_.end()) {
    if (clients_.size() >= max_clients_) {
      auto oldest = clients_.begin();
      for (auto c = clients_.begin(); c != clients_.end(); ++c) {
        if (c->second.last_heard < oldest->second.last_heard) oldest = c;
      }
      clients_.erase(oldest);
      ++evicted_;
    }
    it = clients_
             .emplace(client_id,
                      Client{timesync::ClockOffsetEstimator(estimator_options_), std::nullopt, 0})
             .first;
  }
  Client& client = it->second;
  client.last_heard = ++pings_;
  // Complete the previous exchange with the client's receive time carried by this ping.
  if (client.last_pong && client.last_pong->sequence + 1 == ping.sequence &&
      ToUnixNanos(ping.t3) > 0) {
    client.estimator.AddSample(
        {client.last_pong->t0, client.last_pong->t1, client.last_pong->t2, ping.t3});
  }
  ClockProbe pong = ping;
  pong.sender_id = client_id;
  pong.t1 = received;
  pong.t3 = Time();
  pong.t2 = clock_.Now();
  client.last_pong = pong;
  return pong;
}

std::optional<Duration> ClockResponder::RobotMinusClient(const std::string& client_id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = clients_.find(client_id);
  if (it == clients_.end()) return std::nullopt;
  const timesync::ClockOffsetEstimate estimate = it->second.estimator.Estimate();
  if (!estimate.known) return std::nullopt;
  return estimate.responder_minus_requester;
}

void ClockResponder::Forget(const std::string& client_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  clients_.erase(client_id);
}

size_t ClockResponder::clients() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return clients_.size();
}

uint64_t ClockResponder::evicted() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return evicted_;
}

}  // namespace mostar::server
