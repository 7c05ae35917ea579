#include "operator_client/video/jpeg_decoder.h"

// clang-format off
#include <cstdio>  // jpeglib.h needs FILE
#include <jpeglib.h>
// clang-format on

#include <algorithm>
#include <csetjmp>

#include "common/check/check.h"

namespace mostar::client {
namespace {

// libjpeg reports fatal errors through error_exit, which must not return: it longjmps back to
// the setjmp in Decode, which keeps only trivially destructible locals across libjpeg calls.
struct ErrorManager {
  jpeg_error_mgr base;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
  int warnings;
};

void ErrorExit(j_common_ptr cinfo) {
  auto* manager = reinterpret_cast<ErrorManager*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, manager->message);
  std::longjmp(manager->jump, 1);
}

// Warnings (level -1) are kept, not printed: Decode treats them as errors.
void EmitMessage(j_common_ptr cinfo, int level) {
  auto* manager = reinterpret_cast<ErrorManager*>(cinfo->err);
  if (level < 0) {
    if (manager->warnings == 0) (*cinfo->err->format_message)(cinfo, manager->message);
    ++manager->warnings;
  }
}

}  // namespace

struct JpegDecoder::State {
  jpeg_decompress_struct cinfo;
  ErrorManager error;
};

int DecodeScaleDenominator(int width_px, int height_px, int target_width_px, int target_height_px) {
  if (target_width_px <= 0 || target_height_px <= 0) return 1;
  int denominator = 1;
  while (denominator < 8 && ScaledJpegSize(width_px, denominator * 2) >= target_width_px &&
         ScaledJpegSize(height_px, denominator * 2) >= target_height_px) {
    denominator *= 2;
  }
  return denominator;
}

JpegDecoder::JpegDecoder() : state_(std::make_unique<State>()) {
  jpeg_std_error(&state_->error.base);
  state_->error.base.error_exit = ErrorExit;
  state_->error.base.emit_message = EmitMessage;
  state_->cinfo.err = &state_->error.base;
  jpeg_create_decompress(&state_->cinfo);
}

JpegDecoder::~JpegDecoder() { jpeg_destroy_decompress(&state_->cinfo); }

bool JpegDecoder::Decode(const uint8_t* data, size_t size, int denominator, cv::Mat* bgr,
                         std::string* error) {
  MOSTAR_CHECK(denominator == 1 || denominator == 2 || denominator == 4 || denominator == 8)
      << "scale 1/" << denominator;
  MOSTAR_CHECK(bgr != nullptr);
  if (data == nullptr || size < 4 || data[0] != 0xFF || data[1] != 0xD8) {
    if (error) *error = "no start-of-image marker (" + std::to_string(size) + " bytes)";
    return false;
  }
  jpeg_decompress_struct* cinfo = &state_->cinfo;
  state_->error.warnings = 0;
  state_->error.message[0] = '\0';
  if (setjmp(state_->error.jump)) {
    jpeg_abort_decompress(cinfo);
    if (error) *error = state_->error.message;
    return false;
  }
  jpeg_mem_src(cinfo, data, static_cast<unsigned long>(size));
  jpeg_read_header(cinfo, TRUE);
  cinfo->out_color_space = JCS_EXT_BGR;
  cinfo->scale_num = 1;
  cinfo->scale_denom = static_cast<unsigned int>(denominator);
  jpeg_start_decompress(cinfo);
  bgr->create(static_cast<int>(cinfo->output_height), static_cast<int>(cinfo->output_width),
              CV_8UC3);
  while (cinfo->output_scanline < cinfo->output_height) {
    JSAMPROW rows[4];
    const int first = static_cast<int>(cinfo->output_scanline);
    const int count = std::min(4, static_cast<int>(cinfo->output_height) - first);
    for (int i = 0; i < count; ++i) rows[i] = bgr->ptr<uint8_t>(first + i);
    jpeg_read_scanlines(cinfo, rows, static_cast<JDIMENSION>(count));
  }
  jpeg_finish_decompress(cinfo);
  if (state_->error.warnings > 0) {
    if (error) *error = state_->error.message;
    return false;
  }
  return true;
}

}  // namespace mostar::client
