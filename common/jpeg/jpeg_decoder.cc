#include "common/jpeg/jpeg_decoder.h"

#include <algorithm>
#include <csetjmp>

#include "common/check/check.h"
#include "common/jpeg/jpeg_error.h"

namespace mostar {

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

bool JpegDecoder::Fail(const std::string& message, std::string* error) {
  ++broken_;
  if (error) *error = "broken jpeg: " + message;
  return false;
}

bool JpegDecoder::Decode(const uint8_t* data, size_t size, int denominator, cv::Mat* image,
                         std::string* error, JpegPixels pixels) {
  MOSTAR_CHECK(denominator == 1 || denominator == 2 || denominator == 4 || denominator == 8)
      << "scale 1/" << denominator;
  MOSTAR_CHECK(image != nullptr);
  // Cheap structural check first: the start-of-image marker.
  if (data == nullptr || size < 4 || data[0] != 0xFF || data[1] != 0xD8) {
    return Fail("no start-of-image marker (" + std::to_string(size) + " bytes)", error);
  }
  jpeg_decompress_struct* cinfo = &state_->cinfo;
  state_->error.warnings = 0;
  state_->error.message[0] = '\0';
  if (setjmp(state_->error.jump)) {
    jpeg_abort_decompress(cinfo);
    return Fail(state_->error.message, error);
  }
  jpeg_mem_src(cinfo, data, static_cast<unsigned long>(size));
  jpeg_read_header(cinfo, TRUE);
  const bool grey = pixels == JpegPixels::kGrey;
  cinfo->out_color_space = grey ? JCS_GRAYSCALE : JCS_EXT_BGR;
  cinfo->scale_num = 1;
  cinfo->scale_denom = static_cast<unsigned int>(denominator);
  jpeg_start_decompress(cinfo);
  image->create(static_cast<int>(cinfo->output_height), static_cast<int>(cinfo->output_width),
                grey ? CV_8UC1 : CV_8UC3);
  while (cinfo->output_scanline < cinfo->output_height) {
    JSAMPROW rows[4];
    const int first = static_cast<int>(cinfo->output_scanline);
    const int count = std::min(4, static_cast<int>(cinfo->output_height) - first);
    for (int i = 0; i < count; ++i) rows[i] = image->ptr<uint8_t>(first + i);
    jpeg_read_scanlines(cinfo, rows, static_cast<JDIMENSION>(count));
  }
  jpeg_finish_decompress(cinfo);
  if (state_->error.warnings > 0) return Fail(state_->error.message, error);
  ++decoded_;
  return true;
}

}  // namespace mostar
