#include "common/h264/libav.h"

#include <mutex>

namespace mostar::h264 {

void QuietLibav() {
  static std::once_flag once;
  std::call_once(once, [] { av_log_set_level(AV_LOG_QUIET); });
}

std::string AvError(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof(text));
  return text;
}

LibavState::~LibavState() {
  sws_freeContext(sws);
  av_packet_free(&packet);
  av_frame_free(&frame);
  avcodec_free_context(&context);
}

bool LibavState::Allocate(const AVCodec* codec, const char* who, std::string* error) {
  context = avcodec_alloc_context3(codec);
  frame = av_frame_alloc();
  packet = av_packet_alloc();
  if (context != nullptr && frame != nullptr && packet != nullptr) return true;
  if (error) *error = std::string(who) + ": out of memory";
  return false;
}

}  // namespace mostar::h264
