#include "common/h264/h264_encoder.h"

#include <algorithm>

#include "common/h264/annexb.h"
#include "common/h264/libav.h"

namespace mostar::h264 {

namespace {
constexpr int kMinBitrateBps = 50'000;
}  // namespace

struct Encoder::Codec : LibavState {
  int sws_input_format = AV_PIX_FMT_NONE;  // of the image `sws` was made for
};

bool EncoderSettings::IsValid(std::string* error) const {
  const auto fail = [error](const std::string& why) {
    if (error) *error = "h264 encoder: " + why;
    return false;
  };
  if (width_px < 16 || height_px < 16 || width_px % 2 != 0 || height_px % 2 != 0) {
    return fail("width_px and height_px must be even and >= 16");
  }
  if (frame_rate_hz < 1 || frame_rate_hz > 120) return fail("frame_rate_hz must be 1..120");
  if (bitrate_bps < kMinBitrateBps) return fail("bitrate_bps must be >= 50000");
  if (!(vbv_frames > 0 && vbv_frames <= 30)) return fail("vbv_frames must be in (0, 30]");
  if (keyint_frames < 1) return fail("keyint_frames must be >= 1");
  if (threads < 0 || threads > 16) return fail("threads must be 0..16");
  return true;
}

std::unique_ptr<Encoder> Encoder::Create(const EncoderSettings& settings, std::string* error) {
  if (!settings.IsValid(error)) return nullptr;
  QuietLibav();
  const AVCodec* codec = avcodec_find_encoder_by_name("libx264");
  if (codec == nullptr) {
    if (error) *error = "h264 encoder: libavcodec has no libx264 encoder";
    return nullptr;
  }
  auto c = std::make_unique<Codec>();
  if (!c->Allocate(codec, "h264 encoder", error)) return nullptr;
  AVCodecContext* ctx = c->context;
  ctx->width = settings.width_px;
  ctx->height = settings.height_px;
  ctx->pix_fmt = AV_PIX_FMT_YUV420P;
  ctx->time_base = AVRational{1, settings.frame_rate_hz};
  ctx->framerate = AVRational{settings.frame_rate_hz, 1};
  ctx->gop_size = settings.keyint_frames;
  ctx->max_b_frames = 0;
  ctx->thread_count = settings.threads;
  ctx->bit_rate = settings.bitrate_bps;
  ctx->rc_max_rate = settings.bitrate_bps;
  ctx->rc_buffer_size =
      static_cast<int>(settings.bitrate_bps * settings.vbv_frames / settings.frame_rate_hz);
  // Private options of libavcodec's libx264 wrapper. SPS/PPS stay in-band (no global header).
  const std::pair<const char*, const char*> options[] = {
      {"preset", settings.preset.c_str()},
      {"tune", "zerolatency"},
      {"forced-idr", "1"},
      {"intra-refresh", settings.intra_refresh ? "1" : "0"},
  };
  for (const auto& [name, value] : options) {
    const int rc = av_opt_set(ctx->priv_data, name, value, 0);
    if (rc < 0) {
      if (error)
        *error = std::string("h264 encoder: option ") + name + "=" + value + ": " + AvError(rc);
      return nullptr;
    }
  }
  if (const int rc = avcodec_open2(ctx, codec, nullptr); rc < 0) {
    if (error) *error = "h264 encoder: cannot open libx264: " + AvError(rc);
    return nullptr;
  }
  c->frame->format = AV_PIX_FMT_YUV420P;
  c->frame->width = settings.width_px;
  c->frame->height = settings.height_px;
  if (const int rc = av_frame_get_buffer(c->frame, 0); rc < 0) {
    if (error) *error = "h264 encoder: frame buffer: " + AvError(rc);
    return nullptr;
  }
  return std::unique_ptr<Encoder>(new Encoder(settings, std::move(c)));
}

Encoder::Encoder(const EncoderSettings& settings, std::unique_ptr<Codec> codec)
    : settings_(settings), codec_(std::move(codec)), bitrate_bps_(settings.bitrate_bps) {}

Encoder::~Encoder() = default;

void Encoder::SetBitrate(int bitrate_bps) {
  bitrate_bps_ = std::max(kMinBitrateBps, bitrate_bps);
  // All three together: libavcodec 5.1 reconfigures x264 when the VBV values change.
  AVCodecContext* ctx = codec_->context;
  ctx->bit_rate = bitrate_bps_;
  ctx->rc_max_rate = bitrate_bps_;
  ctx->rc_buffer_size =
      static_cast<int>(bitrate_bps_ * settings_.vbv_frames / settings_.frame_rate_hz);
}

bool Encoder::Encode(const cv::Mat& image, EncodedFrame* out, std::string* error) {
  const auto fail = [this, error](const std::string& why) {
    if (error) *error = "h264 encoder: " + why;
    force_idr_ = true;
    return false;
  };
  if (image.cols != settings_.width_px || image.rows != settings_.height_px) {
    return fail("image is " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                ", the stream " + std::to_string(settings_.width_px) + "x" +
                std::to_string(settings_.height_px));
  }
  int input_format = AV_PIX_FMT_NONE;
  if (image.type() == CV_8UC3) input_format = AV_PIX_FMT_BGR24;
  if (image.type() == CV_8UC1) input_format = AV_PIX_FMT_GRAY8;
  if (input_format == AV_PIX_FMT_NONE) return fail("image must be CV_8UC3 (BGR) or CV_8UC1");
  Codec& c = *codec_;
  if (c.sws == nullptr || c.sws_input_format != input_format) {
    sws_freeContext(c.sws);
    c.sws = sws_getContext(image.cols, image.rows, static_cast<AVPixelFormat>(input_format),
                           image.cols, image.rows, AV_PIX_FMT_YUV420P, SWS_FAST_BILINEAR, nullptr,
                           nullptr, nullptr);
    c.sws_input_format = input_format;
    if (c.sws == nullptr) return fail("no colour conversion to YUV 4:2:0");
  }
  if (const int rc = av_frame_make_writable(c.frame); rc < 0) return fail(AvError(rc));
  const uint8_t* src[1] = {image.data};
  const int src_stride[1] = {static_cast<int>(image.step[0])};
  sws_scale(c.sws, src, src_stride, 0, image.rows, c.frame->data, c.frame->linesize);
  c.frame->pts = next_index_;
  c.frame->pict_type = force_idr_ ? AV_PICTURE_TYPE_I : AV_PICTURE_TYPE_NONE;
  force_idr_ = false;
  if (const int rc = avcodec_send_frame(c.context, c.frame); rc < 0) {
    return fail("send_frame: " + AvError(rc));
  }
  out->data.clear();
  out->frame_index = next_index_++;
  // zerolatency: the frame's AU comes out of this call (x264 with slice threads emits one AU).
  for (;;) {
    const int rc = avcodec_receive_packet(c.context, c.packet);
    if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF) break;
    if (rc < 0) return fail("receive_packet: " + AvError(rc));
    out->data.insert(out->data.end(), c.packet->data, c.packet->data + c.packet->size);
    av_packet_unref(c.packet);
  }
  if (out->data.empty()) return fail("the encoder held the frame back (not zero latency)");
  out->idr = IsSelfContainedIdr(out->data);
  return true;
}

}  // namespace mostar::h264
