#include "robot_server/camera/link_rate_controller.h"

#include <algorithm>
#include <cmath>

namespace mostar::camera {

namespace {
constexpr int64_t kThroughputWindowNs = 500'000'000;
// The delivery rate a frame's transmission time is taken at: the highest throughput measured
// over this long (a release after a repair leaves a gap in the 500 ms window; that dip is not
// the link slowing down).
constexpr int64_t kPeakRateWindowNs = 2'000'000'000;
constexpr double kMinFramesForLoss = 20;
}  // namespace

bool LinkRateOptions::IsValid(std::string* error) const {
  if (!(min_bits_per_s > 0) || !(max_bits_per_s >= min_bits_per_s)) {
    *error = "link rate: need 0 < min_bits_per_s <= max_bits_per_s";
    return false;
  }
  if (!(start_fraction > 0 && start_fraction <= 1) || !(increase_per_s > 1) ||
      !(backoff > 0 && backoff < 1)) {
    *error = "link rate: start_fraction in (0, 1], increase_per_s > 1, backoff in (0, 1)";
    return false;
  }
  if (!(near_increase_per_s > 1) || near_increase_per_s > increase_per_s) {
    *error = "link rate: need 1 < near_increase_per_s <= increase_per_s";
    return false;
  }
  if (!(normal_queue_ms >= 0) || !(overuse_queue_ms > normal_queue_ms) ||
      !(skip_queue_ms >= overuse_queue_ms)) {
    *error = "link rate: need 0 <= normal_queue_ms < overuse_queue_ms <= skip_queue_ms";
    return false;
  }
  if (!(silence_backoff > 0 && silence_backoff < 1)) {
    *error = "link rate: silence_backoff in (0, 1)";
    return false;
  }
  if (decrease_interval <= Duration::zero() || capacity_memory <= Duration::zero() ||
      base_window <= Duration::zero() || silence_after <= Duration::zero() ||
      silence_interval <= Duration::zero() || repair_hold < Duration::zero() ||
      silence_margin < Duration::zero()) {
    *error = "link rate: intervals must be positive";
    return false;
  }
  return true;
}

const char* LinkUsageName(LinkUsage usage) {
  switch (usage) {
    case LinkUsage::kNormal:
      return "normal";
    case LinkUsage::kOverusing:
      return "overusing";
    case LinkUsage::kQueueing:
      return "queueing";
  }
  return "?";
}

LinkRateController::LinkRateController(const LinkRateOptions& options) : options_(options) {
  stats_.target_bits_per_s =
      std::max(options_.min_bits_per_s, options_.max_bits_per_s * options_.start_fraction);
}

void LinkRateController::SetMaxBitsPerSecond(double bits_per_s) {
  if (bits_per_s > 0) options_.max_bits_per_s = std::max(bits_per_s, options_.min_bits_per_s);
  stats_.target_bits_per_s = std::min(stats_.target_bits_per_s, options_.max_bits_per_s);
}

void SentFrames::Add(uint64_t sequence, SteadyTime sent, uint32_t bytes) {
  if (!frames_.empty() && sequence <= std::get<0>(frames_.back())) frames_.clear();  // restart
  frames_.emplace_back(sequence, sent, bytes);
  while (frames_.size() > capacity_) frames_.pop_front();
}

std::optional<SteadyTime> SentFrames::SendTime(uint64_t sequence) const {
  if (frames_.empty() || sequence < std::get<0>(frames_.front())) return std::nullopt;
  const auto it =
      std::lower_bound(frames_.begin(), frames_.end(), sequence,
                       [](const auto& frame, uint64_t s) { return std::get<0>(frame) < s; });
  if (it == frames_.end() || std::get<0>(*it) != sequence) return std::nullopt;
  return std::get<1>(*it);
}

uint64_t SentFrames::BitsAfter(uint64_t sequence) const {
  uint64_t bits = 0;
  for (auto it = frames_.rbegin(); it != frames_.rend() && std::get<0>(*it) > sequence; ++it) {
    bits += uint64_t{std::get<2>(*it)} * 8;
  }
  return bits;
}

std::optional<SteadyTime> SentFrames::FirstSentAfter(uint64_t sequence) const {
  const auto it =
      std::upper_bound(frames_.begin(), frames_.end(), sequence,
                       [](uint64_t s, const auto& frame) { return s < std::get<0>(frame); });
  if (it == frames_.end()) return std::nullopt;
  return std::get<1>(*it);
}

double LinkRateController::OnSilence(const SentFrames& sent, SteadyTime now) {
  // Only once the viewer has reported frames: before that the start rate applies.
  if (!last_arrivals_ || !last_sequence_) return stats_.target_bits_per_s;
  const Duration silence_after = SilenceAfter();
  const std::optional<SteadyTime> unreported = sent.FirstSentAfter(*last_sequence_);
  // Measured from the frame's writing, not from the last report (a report that took older frames
  // is no news about the frames after them, written into the same link); but only once the
  // viewer has gone quiet, two report periods without a frame: while frames keep coming, late,
  // the queue is the delay-based part's to judge.
  if (!unreported || now - *unreported < silence_after) return stats_.target_bits_per_s;
  const Duration quiet =
      stats_.report_period_ms > 0
          ? std::chrono::microseconds(static_cast<int64_t>(2 * stats_.report_period_ms * 1e3)) +
                options_.silence_margin
          : silence_after;
  if (now - *last_arrivals_ < quiet) return stats_.target_bits_per_s;
  if (last_decrease_ && now - *last_decrease_ < options_.silence_interval) {
    return stats_.target_bits_per_s;
  }
  double& target = stats_.target_bits_per_s;
  // The first halving starts from what the viewer last received when that is lower (an encoder
  // below its target, or a target that had grown past the link): the target alone left the
  // first halving above a link that had lost three quarters of its capacity.
  const double from = !silent_ && stats_.throughput_bits_per_s > 0
                          ? std::min(target, stats_.throughput_bits_per_s)
                          : target;
  silent_ = true;
  target = std::max(options_.min_bits_per_s, from * options_.silence_backoff);
  last_decrease_ = now;
  ++stats_.decreases;
  ++stats_.silence_decreases;
  return target;
}

Duration LinkRateController::SilenceAfter() const {
  if (report_lags_.empty()) return options_.silence_after;
  // A repair takes the repair period and a round trip, about the least report lag itself.
  return 2 * report_lags_.front().second + options_.repair_hold +
         std::chrono::microseconds(static_cast<int64_t>(stats_.report_period_ms * 1e3)) +
         options_.silence_margin;
}

double LinkRateController::OnFeedback(const std::vector<FrameArrival>& arrivals,
                                      const SentFrames& sent, SteadyTime now) {
  for (const FrameArrival& arrival : arrivals) {
    if (last_sequence_ && arrival.sequence <= *last_sequence_) continue;
    if (const std::optional<SteadyTime> at = sent.SendTime(arrival.sequence)) {
      AddReceived(arrival);
      if (held_) {
        if (arrival.arrival_ns - held_->first.arrival_ns >= kReleaseBatchNs) {
          AddDelay(held_->first, held_->second);
        } else {
          ++stats_.held_back;
        }
      }
      held_.emplace(arrival, *at);
      last_sent_ = *at;
      last_arrivals_ = now;
      silent_ = false;
    }
    ++reported_;
    if (last_sequence_) expected_ += arrival.sequence - *last_sequence_;
    last_sequence_ = arrival.sequence;
  }
  if (last_sent_ && last_arrivals_ == now) {
    AddReportLag(now - *last_sent_, now);
    // The report period, from intervals below a second (a silence is not a period).
    if (last_report_with_frames_ && now - *last_report_with_frames_ < std::chrono::seconds(1)) {
      const double interval_ms = ToSeconds(now - *last_report_with_frames_) * 1e3;
      double& period = stats_.report_period_ms;
      period = period > 0 ? 0.9 * period + 0.1 * interval_ms : interval_ms;
    }
    last_report_with_frames_ = now;
  }
  stats_.predicted_queue_ms = PredictedQueueMs(sent, now);
  const double q = stats_.predicted_queue_ms;
  stats_.usage = q > options_.overuse_queue_ms  ? LinkUsage::kOverusing
                 : q < options_.normal_queue_ms ? LinkUsage::kNormal
                                                : LinkUsage::kQueueing;
  UpdateRate(now);
  return stats_.target_bits_per_s;
}

double LinkRateController::PredictedQueueMs(const SentFrames& sent, SteadyTime now) const {
  const double rate = RecentThroughput();
  if (!last_sequence_ || !last_sent_ || rate <= 0) return stats_.queue_delay_ms;
  // The frames written since the last report drain at the link's rate, which the viewer measures
  // only while the link is the limit: then a queue shows. Without one (a link that is not full:
  // the viewer measures the encoder's rate) a big frame in flight would read as queueing.
  if (stats_.queue_delay_ms < 0.5 * options_.normal_queue_ms) return stats_.queue_delay_ms;
  const double added_ms = static_cast<double>(sent.BitsAfter(*last_sequence_)) / rate * 1e3;
  const double passed_ms = ToSeconds(now - *last_sent_) * 1e3;
  return std::max(0.0, stats_.queue_delay_ms + added_ms - passed_ms);
}

void LinkRateController::AddReportLag(Duration lag, SteadyTime now) {
  while (!report_lags_.empty() && report_lags_.back().second >= lag) report_lags_.pop_back();
  report_lags_.emplace_back(now, lag);
  while (now - report_lags_.front().first > options_.base_window) report_lags_.pop_front();
  stats_.report_lag_ms = ToSeconds(report_lags_.front().second) * 1e3;
}

void LinkRateController::AddReceived(const FrameArrival& arrival) {
  received_.emplace_back(arrival.arrival_ns, arrival.bytes);
  while (!received_.empty() && arrival.arrival_ns - received_.front().first > kThroughputWindowNs) {
    received_.pop_front();
  }
  const double throughput = RecentThroughput();
  if (throughput <= 0) return;
  while (!peak_rates_.empty() && peak_rates_.back().second <= throughput) peak_rates_.pop_back();
  peak_rates_.emplace_back(arrival.arrival_ns, throughput);
  while (arrival.arrival_ns - peak_rates_.front().first > kPeakRateWindowNs) {
    peak_rates_.pop_front();
  }
}

void LinkRateController::AddDelay(const FrameArrival& arrival, SteadyTime sent) {
  const int64_t send_ns = sent.time_since_epoch().count();
  // The base (the path without queueing) is the least one-way delay of a whole frame (its last
  // byte) over the window, the frame's own transmission time in. A frame's queueing delay is its
  // delay above the base, less the transmission time of the bytes it has beyond the base
  // frame's, at the rate the link delivered lately (its peak over 2 s): bigger frames at a
  // higher rate do not read as queueing. The base itself is never corrected: on a link that is
  // not full the delivery rate is the encoder's, far below the link's, and a big frame's
  // transmission time taken at it came out frame periods long; as the window's minimum that one
  // sample made every later frame read as queued (a still scene held the rate at its floor), as
  // did a dip of the rate after a repair. Too large a correction only makes that one frame read
  // as less queued. No sample before the delivery rate is measured.
  if (peak_rates_.empty()) return;
  const double rate = peak_rates_.front().second;
  const double raw_ms = static_cast<double>(arrival.arrival_ns - send_ns) / 1e6;
  const int64_t window_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(options_.base_window).count();
  while (!base_delays_.empty() && base_delays_.back().delay_ms >= raw_ms) base_delays_.pop_back();
  base_delays_.push_back({arrival.arrival_ns, raw_ms, arrival.bytes});
  while (arrival.arrival_ns - base_delays_.front().arrival_ns > window_ns) {
    base_delays_.pop_front();
  }
  const BaseDelay& base = base_delays_.front();
  const double extra_bits = 8.0 * (static_cast<double>(arrival.bytes) - base.bytes);
  stats_.queue_delay_ms = raw_ms - base.delay_ms - std::max(0.0, extra_bits / rate * 1e3);
}

double LinkRateController::RecentThroughput() const {
  if (received_.size() < 2) return 0;
  const double span_s = static_cast<double>(received_.back().first - received_.front().first) / 1e9;
  uint64_t bytes = 0;
  for (size_t i = 1; i < received_.size(); ++i) bytes += received_[i].second;
  return span_s >= 0.2 ? static_cast<double>(bytes) * 8 / span_s : 0;
}

void LinkRateController::UpdateRate(SteadyTime now) {
  // Throughput over the window the arrivals span (the viewer's clock).
  const double throughput = RecentThroughput();
  stats_.throughput_bits_per_s = throughput;
  if (static_cast<double>(expected_) >= kMinFramesForLoss) {
    stats_.loss_fraction =
        std::clamp(1.0 - static_cast<double>(reported_) / static_cast<double>(expected_), 0.0, 1.0);
    reported_ = 0;
    expected_ = 0;
  }
  const double dt_s = last_update_ ? std::min(ToSeconds(now - *last_update_), 1.0) : 0.0;
  last_update_ = now;
  double& target = stats_.target_bits_per_s;
  if (stats_.usage == LinkUsage::kOverusing) {
    ++stats_.overuse_reports;
    // Below the capacity, by enough to drain the queue within about half a second.
    const double drain = std::clamp(1.0 - stats_.predicted_queue_ms / 500.0, 0.25, 1.0);
    const double lower = options_.backoff * throughput * drain;
    if (throughput > 0 && (!last_decrease_ || now - *last_decrease_ >= options_.decrease_interval ||
                           lower < 0.7 * target)) {
      target = std::min(target, lower);
      capacity_bits_per_s_ = throughput;
      last_decrease_ = now;
      ++stats_.decreases;
    }
  } else if (stats_.usage == LinkUsage::kNormal && dt_s > 0) {
    // Near the capacity seen at a recent decrease, probe gently; once no decrease came for
    // `capacity_memory` the link may have grown: probe fast.
    const bool near_capacity = capacity_bits_per_s_ > 0 && last_decrease_ &&
                               now - *last_decrease_ < options_.capacity_memory &&
                               target > 0.5 * capacity_bits_per_s_ &&
                               target < 1.5 * capacity_bits_per_s_;
    target *=
        std::pow(near_capacity ? options_.near_increase_per_s : options_.increase_per_s, dt_s);
    if (throughput > 0) target = std::min(target, 1.5 * throughput + 10e3);
  }
  if (stats_.loss_fraction > 0.10) {
    target *= 1 - 0.5 * stats_.loss_fraction;
    stats_.loss_fraction = 0;  // once per measurement
  }
  target = std::clamp(target, options_.min_bits_per_s, options_.max_bits_per_s);
}

}  // namespace mostar::camera
