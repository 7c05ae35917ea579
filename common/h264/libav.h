// libavcodec headers and process-wide setup shared by the encoder and the decoder
// (implementation detail of common/h264).
#pragma once

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/error.h>
#include <libavutil/frame.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <string>

namespace mostar::h264 {

// Quiets libav's own logging (once per process): errors reach the caller as return values, and
// expected loss ("non-existing PPS", concealment) must not flood stderr.
void QuietLibav();

// "Invalid data found when processing input" for an AVERROR code.
std::string AvError(int code);

// What the encoder and the decoder both hold: a codec context, a frame, a packet and a colour
// converter, freed together.
struct LibavState {
  AVCodecContext* context = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  SwsContext* sws = nullptr;

  LibavState() = default;
  LibavState(const LibavState&) = delete;
  LibavState& operator=(const LibavState&) = delete;
  ~LibavState();
  // Allocates the context for `codec`, the frame and the packet; false with "`who`: out of
  // memory" in `error`.
  bool Allocate(const AVCodec* codec, const char* who, std::string* error);
};

}  // namespace mostar::h264
