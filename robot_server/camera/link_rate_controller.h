// The H.264 target bitrate that one viewer's link carries, from what the viewer reports (in the
// spirit of WebRTC's Google Congestion Control, draft-ietf-rmcat-gcc-02 and libwebrtc goog_cc;
// constants from ../shared/reference/video-notes.md section 4).
//
// Inputs: when the robot wrote each frame and how big it was (OnFrameSent, robot's monotonic
// clock) and when the viewer received it (OnFeedback: FrameArrival on the viewer's clock; only
// differences of arrival times are used, so the two clocks need no common origin).
//
// Delay-based part: the one-way delay of each whole frame, (arrival - send), against its minimum
// over the last `base_window` (the path without queueing, whatever the clocks' offset; the window
// follows clock drift) gives the queueing delay q of the last frame reported, less the
// transmission time of the bytes the frame has beyond the base frame's (at the peak delivery
// rate of the last 2 s). The base itself is never corrected by a rate: on a link that is not full
// the delivery rate is the encoder's. Its report comes a round trip late, so while q shows a
// queue the decision uses q plus what the frames written since then add: their bits at the
// delivery rate,
// less the time that passed. Above `overuse_queue_ms` is over-use, below `normal_queue_ms`
// normal, between them hold; above `skip_queue_ms` frames are skipped at the source. (GCC fits a
// trendline to the delay variation of 5 ms packet groups; with one point per frame at 30 Hz its
// 20-point window spans 0.7 s and, with its adaptive threshold, let a simulated 8 Mbit/s link queue
// for seconds: see link_rate_controller_test.cc. The queueing delay itself answers within a report
// period.) Rate (AIMD): over-use -> 0.85 x the throughput the viewer measured over the last 500 ms,
// less what drains the queue in a second (at most once per `decrease_interval`); hold; normal ->
// increase, by `near_increase_per_s` per second near the capacity seen at a decrease in the last
// `capacity_memory`, by `increase_per_s` otherwise (libwebrtc's 8 %/s is slower than a robot's
// uplink changes: a step 2 -> 8 Mbit/s must be followed within seconds); never above 1.5 x
// throughput + 10 kbit/s (an encoder that produces less than its target does not make the
// estimate run away).
// Loss-based part: frames missing from the reports (AU numbers skipped) above 10 % cut the
// target by half the loss fraction; below 2 % they do not hold it back.
// Silence (OnSilence): a viewer reports only while frames reach it, so when a link loses so much
// capacity that every frame loses a packet, or the frames wait behind one that cannot be
// repaired, the reports stop and neither part above hears anything. Frames written longer ago
// than a report normally takes plus a repair, and still not reported, then halve the target
// (the first time from what the viewer last received, if that is lower), again every
// `silence_interval` while it lasts (libwebrtc likewise lowers its estimate when feedback stops
// coming). "A report normally takes": the least report lag L (robot time from writing the
// newest frame of a report to taking the report: both one-way delays and the transmission) over
// `base_window`; "a repair": `repair_hold`, the writers' repair period, and a round trip (L
// again); plus the viewer's report period (measured: the mean interval between its reports) and
// `silence_margin` (jitter). Until a lag is measured, `silence_after`.
// Not thread-safe: VideoRateControl serialises.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "common/time/time.h"
#include "common/types/stereo_frame.h"

namespace mostar::camera {

// One frame as a viewer received it (AU number, arrival on the viewer's clock, bytes).
using FrameArrival = VideoFrameArrival;

struct LinkRateOptions {
  double min_bits_per_s = 300e3;
  double max_bits_per_s = 8e6;        // the configured class target; SetMaxBitsPerSecond changes it
  double start_fraction = 0.5;        // of max, before any feedback
  double increase_per_s = 2.0;        // increase factor per second, away from the capacity
  double near_increase_per_s = 1.15;  // ... within capacity_memory of a decrease, below 1.5 x it
  double backoff = 0.85;              // x throughput on over-use
  Duration decrease_interval = std::chrono::milliseconds(300);
  Duration capacity_memory = std::chrono::seconds(1);
  double overuse_queue_ms = 40;  // queueing delay that means over-use
  double normal_queue_ms = 20;   // below it the rate may grow
  double skip_queue_ms = 150;    // frames are skipped at the source above it
  Duration base_window = std::chrono::seconds(10);
  // Silence (see the top of this file) once the first unreported frame is older than twice the
  // least report lag + repair_hold + the report period + silence_margin: a repaired loss holds
  // frames for about a repair period and a round trip, and must not read as silence.
  // repair_hold is the video writers' repair (heartbeat) period, dds.video_repair_period_ms.
  // Before a lag is measured: silence_after.
  Duration repair_hold = std::chrono::milliseconds(50);
  Duration silence_margin = std::chrono::milliseconds(30);
  Duration silence_after = std::chrono::milliseconds(500);
  double silence_backoff = 0.5;  // x target per silence_interval of silence
  // Shorter than decrease_interval: a link too full to deliver a whole frame is also full of
  // repairs (every lost fragment is sent again each repair period until the deadline), so the
  // rate must fall far below the link before anything gets through again (the step bench:
  // to a third of it).
  Duration silence_interval = std::chrono::milliseconds(150);
  bool IsValid(std::string* error) const;
};

// kNormal: q below normal_queue_ms; kQueueing: between (hold); kOverusing: above overuse_queue_ms.
enum class LinkUsage { kNormal, kQueueing, kOverusing };
const char* LinkUsageName(LinkUsage usage);

struct LinkRateStats {
  double target_bits_per_s = 0;
  double throughput_bits_per_s = 0;  // received, last 500 ms (0 until measured)
  double queue_delay_ms = 0;         // last frame reported: one-way delay above its minimum
  double predicted_queue_ms = 0;     // for a frame written now (decisions use it)
  double loss_fraction = 0;          // of the frames the last reports should have held
  LinkUsage usage = LinkUsage::kNormal;
  uint64_t overuse_reports = 0;
  uint64_t decreases = 0;
  uint64_t held_back = 0;          // frames released together with a later one: no delay sample
  uint64_t silence_decreases = 0;  // of `decreases`, made because no frame was reported
  double report_lag_ms = 0;        // least report lag over base_window (0: not measured yet)
  double report_period_ms = 0;     // mean interval between reports with frames (0: not yet)
};

// The robot's record of the frames it wrote: AU number -> (send time, bytes), the newest
// `capacity`. Not thread-safe.
class SentFrames {
 public:
  explicit SentFrames(size_t capacity = 600) : capacity_(capacity) {}
  void Add(uint64_t sequence, SteadyTime sent, uint32_t bytes);
  std::optional<SteadyTime> SendTime(uint64_t sequence) const;
  // Bits of the frames written after `sequence`.
  uint64_t BitsAfter(uint64_t sequence) const;
  // When the first frame after `sequence` was written; nullopt when none was.
  std::optional<SteadyTime> FirstSentAfter(uint64_t sequence) const;

 private:
  const size_t capacity_;
  std::deque<std::tuple<uint64_t, SteadyTime, uint32_t>> frames_;  // increasing AU numbers
};

class LinkRateController {
 public:
  explicit LinkRateController(const LinkRateOptions& options = {});

  // The class target changed (0: unlimited, the options' max stays).
  void SetMaxBitsPerSecond(double bits_per_s);
  // A viewer's report. `sent` has the robot's send time and size of the frames (frames it no
  // longer has count for loss only). Arrivals must be in increasing AU order within and across
  // reports (older ones are ignored). `now`: the robot's monotonic time, the clock of `sent`.
  // Returns the new target, bit/s.
  double OnFeedback(const std::vector<FrameArrival>& arrivals, const SentFrames& sent,
                    SteadyTime now);
  // Called for every frame the encoder is about to write, reports or not: the silence rule
  // (see the top of this file). Returns the target, bit/s.
  double OnSilence(const SentFrames& sent, SteadyTime now);
  // How old the first unreported frame may get before the silence rule applies.
  Duration SilenceAfter() const;
  const LinkRateStats& stats() const { return stats_; }
  // Whether the encoder should skip the frame it would write at `now`: the queue it would meet
  // is over `skip_queue_ms` (after a drop in capacity the frames already queued are late
  // enough; more would only wait behind them) and the last frame seen met a queue too. Without
  // a measured queue the encoder, not the link, limits the throughput, and an IDR written at a
  // low rate would read as seconds of queue at that throughput.
  bool ShouldSkipFrame(const SentFrames& sent, SteadyTime now) const {
    return stats_.queue_delay_ms >= options_.normal_queue_ms &&
           PredictedQueueMs(sent, now) > options_.skip_queue_ms;
  }

 private:
  // A reliable, in-order stream turns a loss into a wait: the frames after a lost one are held
  // at the viewer until the repair arrives, then released together. Their delays measure the
  // repair (a round trip and a heartbeat), not a queue, so a frame that arrived within
  // kReleaseBatch of the next one gives no delay sample; the last of a batch, sent just before
  // the release, does. (WebRTC's GCC groups packets that arrive within 5 ms alike.) The newest
  // frame of each report is therefore judged with the next report.
  static constexpr int64_t kReleaseBatchNs = 5'000'000;
  void AddReceived(const FrameArrival& arrival);
  void AddDelay(const FrameArrival& arrival, SteadyTime sent);
  // A report whose newest frame was written `lag` before `now` (robot clock).
  void AddReportLag(Duration lag, SteadyTime now);
  // The queueing delay a frame written at `now` meets: the last one seen, plus, while a queue
  // shows, what the frames written since then add (their bits at the delivery rate) less the
  // time that passed.
  double PredictedQueueMs(const SentFrames& sent, SteadyTime now) const;
  void UpdateRate(SteadyTime now);
  // Bits per second the viewer received over the last 500 ms of arrivals; 0 below 200 ms.
  double RecentThroughput() const;

  LinkRateOptions options_;
  LinkRateStats stats_;
  // One-way delays of whole frames, a monotonic deque: its front is the window's minimum.
  struct BaseDelay {
    int64_t arrival_ns = 0;
    double delay_ms = 0;
    uint32_t bytes = 0;  // the frame's
  };
  std::deque<BaseDelay> base_delays_;
  // (robot time of the report, report lag), a monotonic deque over base_window: its front is the
  // least lag.
  std::deque<std::pair<SteadyTime, Duration>> report_lags_;
  bool silent_ = false;  // a silence decrease was made and no frame was reported since
  std::optional<SteadyTime> last_report_with_frames_;
  // Throughput (viewer clock) and loss.
  std::deque<std::pair<int64_t, uint32_t>> received_;  // (arrival ns, bytes), last 500 ms
  // (arrival ns, throughput), a monotonic deque over 2 s: its front is the peak delivery rate.
  std::deque<std::pair<int64_t, double>> peak_rates_;
  std::optional<uint64_t> last_sequence_;
  std::optional<SteadyTime> last_sent_;      // send time of the last frame reported
  std::optional<SteadyTime> last_arrivals_;  // robot time of the last report with a new frame
  std::optional<std::pair<FrameArrival, SteadyTime>> held_;  // newest frame, its delay not used yet
  uint64_t reported_ = 0;
  uint64_t expected_ = 0;
  // Rate.
  std::optional<SteadyTime> last_update_;
  std::optional<SteadyTime> last_decrease_;
  double capacity_bits_per_s_ = 0;  // throughput at the last decrease; 0 = unknown
};

}  // namespace mostar::camera
