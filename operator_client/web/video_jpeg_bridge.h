// Turns the robot's H.264 stream into JPEG stereo pairs for the browsers (which keep receiving
// JPEG). Frames are decoded in order by a StereoReceiver (never a broken picture: after a loss
// nothing new comes until the next IDR); each new decoded pair is JPEG-encoded at `quality`
// on the bridge's thread and handed to `sink`, stamped with its capture time. mostar_web writes
// nothing to DDS, so it cannot ask for IDRs: it starts at the IDR the robot sends when a reader
// matches, and resumes after a loss at the next IDR another viewer asked for or the periodic one.
#pragma once

#include <atomic>
#include <functional>
#include <thread>

#include "common/types/stereo_frame.h"
#include "operator_client/video/stereo_receiver.h"

namespace mostar::web {

struct VideoJpegBridgeStats {
  uint64_t pairs_encoded = 0;  // JPEG pairs handed to the sink
  client::ReceiverStats decoder;
};

class VideoJpegBridge {
 public:
  using Sink = std::function<void(CompressedStereoPair pair)>;
  // `sink` runs on the bridge's thread. quality: 1..100.
  VideoJpegBridge(Sink sink, int quality = 85, const Clock* clock = &SystemClock::Instance());
  ~VideoJpegBridge();  // stops the thread: no sink call after it returns
  VideoJpegBridge(const VideoJpegBridge&) = delete;
  VideoJpegBridge& operator=(const VideoJpegBridge&) = delete;

  // DDS thread: one StereoVideoFrame.
  void Push(const StereoVideoFrame& frame) { receiver_.PushVideo(frame); }
  VideoJpegBridgeStats Stats() const;

 private:
  void Loop();

  const Sink sink_;
  const int quality_;
  client::StereoReceiver receiver_;
  std::atomic<bool> stop_{false};
  std::atomic<uint64_t> encoded_{0};
  std::thread thread_;
};

}  // namespace mostar::web
