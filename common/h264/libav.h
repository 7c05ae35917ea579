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

}  // namespace mostar::h264
