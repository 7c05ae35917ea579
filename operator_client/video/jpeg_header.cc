#include "operator_client/video/jpeg_header.h"

#include <csetjmp>

#include "common/jpeg/jpeg_error.h"

namespace mostar::client {
namespace {

// 0 on success, else -1 with the message in `manager`.
int ReadHeader(const uint8_t* data, size_t size, JpegErrorManager* manager, JpegHeader* out) {
  jpeg_decompress_struct cinfo{};  // zeroed: destroying it is safe whenever an error comes
  cinfo.err = InitJpegErrorManager(manager);  // warnings are ignored: the decoder judges the data
  if (setjmp(manager->jump) != 0) {
    jpeg_destroy_decompress(&cinfo);
    return -1;
  }
  jpeg_create_decompress(&cinfo);
  jpeg_mem_src(&cinfo, data, static_cast<unsigned long>(size));
  jpeg_read_header(&cinfo, TRUE);
  out->width_px = static_cast<int>(cinfo.image_width);
  out->height_px = static_cast<int>(cinfo.image_height);
  out->components = cinfo.num_components;
  jpeg_destroy_decompress(&cinfo);
  return 0;
}

}  // namespace

bool ReadJpegHeader(const uint8_t* data, size_t size, JpegHeader* out, std::string* error) {
  if (data == nullptr || size == 0) {
    if (error) *error = "empty image";
    return false;
  }
  JpegErrorManager manager;
  JpegHeader header;
  if (ReadHeader(data, size, &manager, &header) != 0) {
    if (error) *error = manager.message;
    return false;
  }
  *out = header;
  return true;
}

bool FitsExpectedSize(const JpegHeader& header, int max_width_px, int max_height_px,
                      std::string* why) {
  if (header.width_px <= 0 || header.height_px <= 0) {
    if (why) *why = "no pixels";
    return false;
  }
  if (header.width_px > max_width_px || header.height_px > max_height_px) {
    if (why) {
      *why = "declares " + std::to_string(header.width_px) + "x" +
             std::to_string(header.height_px) + ", more than the expected " +
             std::to_string(max_width_px) + "x" + std::to_string(max_height_px);
    }
    return false;
  }
  return true;
}

}  // namespace mostar::client
