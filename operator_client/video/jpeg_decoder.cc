#include "operator_client/video/jpeg_decoder.h"

#include <algorithm>
#include <csetjmp>

#include "common/check/check.h"
#include "common/jpeg/jpeg_error.h"

namespace mostar::client {

struct JpegDecoder::State {
  jpeg_decompress_struct cinfo;
  JpegErrorManager error;
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
  state_->cinfo.err = InitJpegErrorManager(&state_->error);
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
