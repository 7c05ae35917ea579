#include "common/h264/h264_decoder.h"

#include <vector>

#include "common/h264/annexb.h"
#include "common/h264/libav.h"

namespace mostar::h264 {

const char* DecodeStatusName(DecodeStatus status) {
  switch (status) {
    case DecodeStatus::kPicture:
      return "picture";
    case DecodeStatus::kWaitingForIdr:
      return "waiting for an IDR";
    case DecodeStatus::kError:
      return "error";
  }
  return "?";
}

struct Decoder::Codec : LibavState {
  std::vector<uint8_t> padded;  // the AU with AV_INPUT_BUFFER_PADDING_SIZE zero bytes after it
};

std::unique_ptr<Decoder> Decoder::Create(std::string* error) {
  QuietLibav();
  const AVCodec* codec = avcodec_find_decoder(AV_CODEC_ID_H264);
  if (codec == nullptr) {
    if (error) *error = "h264 decoder: libavcodec has no H.264 decoder";
    return nullptr;
  }
  auto c = std::make_unique<Codec>();
  if (!c->Allocate(codec, "h264 decoder", error)) return nullptr;
  // One thread: frame threads would hold one picture back per extra thread.
  c->context->thread_count = 1;
  c->context->flags |= AV_CODEC_FLAG_LOW_DELAY;
  if (const int rc = avcodec_open2(c->context, codec, nullptr); rc < 0) {
    if (error) *error = "h264 decoder: " + AvError(rc);
    return nullptr;
  }
  return std::unique_ptr<Decoder>(new Decoder(std::move(c)));
}

Decoder::Decoder(std::unique_ptr<Codec> codec) : codec_(std::move(codec)) {}
Decoder::~Decoder() = default;

DecodeStatus Decoder::Fail(const std::string& message, std::string* error) {
  if (error) *error = "h264 decoder: " + message;
  waiting_ = true;
  ++counters_.errors;
  return DecodeStatus::kError;
}

DecodeStatus Decoder::Decode(const uint8_t* data, size_t size, uint64_t sequence, cv::Mat* image,
                             std::string* error, Pixels pixels) {
  // An empty packet would put libavcodec into draining (end of stream).
  if (data == nullptr || size == 0) return Fail("empty access unit", error);
  if (size > kMaxAccessUnitBytes) {
    return Fail("access unit of " + std::to_string(size) + " bytes (at most " +
                    std::to_string(kMaxAccessUnitBytes) + ")",
                error);
  }
  if (have_sequence_ && sequence != last_sequence_ + 1) {
    ++counters_.gaps;
    waiting_ = true;
  }
  have_sequence_ = true;
  last_sequence_ = sequence;
  const bool idr = IsSelfContainedIdr(data, size);
  if (waiting_ && !idr) {
    ++counters_.skipped_waiting;
    return DecodeStatus::kWaitingForIdr;
  }
  if (idr && waiting_) avcodec_flush_buffers(codec_->context);
  Codec& c = *codec_;
  c.padded.assign(data, data + size);
  c.padded.resize(size + AV_INPUT_BUFFER_PADDING_SIZE, 0);
  c.packet->data = c.padded.data();
  c.packet->size = static_cast<int>(size);
  const int sent = avcodec_send_packet(c.context, c.packet);
  c.packet->data = nullptr;
  c.packet->size = 0;
  if (sent < 0) return Fail("send_packet: " + AvError(sent), error);
  const int received = avcodec_receive_frame(c.context, c.frame);
  if (received == AVERROR(EAGAIN)) return Fail("the access unit gave no picture", error);
  if (received < 0) return Fail("receive_frame: " + AvError(received), error);
  struct Unref {
    AVFrame* f;
    ~Unref() { av_frame_unref(f); }
  } unref{c.frame};
  if (c.frame->decode_error_flags != 0 || (c.frame->flags & AV_FRAME_FLAG_CORRUPT) != 0) {
    return Fail(
        "the picture has errors (flags " + std::to_string(c.frame->decode_error_flags) + ")",
        error);
  }
  const int width = c.frame->width;
  const int height = c.frame->height;
  // swscale also expands the stream's limited-range luma to full range for grey.
  const AVPixelFormat out_format = pixels == Pixels::kGrey ? AV_PIX_FMT_GRAY8 : AV_PIX_FMT_BGR24;
  c.sws =
      sws_getCachedContext(c.sws, width, height, static_cast<AVPixelFormat>(c.frame->format), width,
                           height, out_format, SWS_FAST_BILINEAR, nullptr, nullptr, nullptr);
  if (c.sws == nullptr) return Fail("no colour conversion of the picture", error);
  image->create(height, width, pixels == Pixels::kGrey ? CV_8UC1 : CV_8UC3);
  uint8_t* dst[1] = {image->data};
  const int dst_stride[1] = {static_cast<int>(image->step[0])};
  sws_scale(c.sws, c.frame->data, c.frame->linesize, 0, height, dst, dst_stride);
  waiting_ = false;
  ++counters_.pictures;
  return DecodeStatus::kPicture;
}

}  // namespace mostar::h264
