// The size a JPEG declares, read from its header (libjpeg-turbo, markers up to the first scan;
// no pixel is decoded and no image memory is allocated), so that an image is checked against
// the size it may have before it is decoded.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace mostar::client {

struct JpegHeader {
  int width_px = 0;
  int height_px = 0;
  int components = 0;  // 1 grey, 3 colour, 4 CMYK
};

// False with libjpeg's message when the data is not a readable JPEG header.
bool ReadJpegHeader(const uint8_t* data, size_t size, JpegHeader* out, std::string* error);

// The largest image one eye may carry: its CameraInfo size (the robot scales images down,
// never up) when known, else the receiver's fixed limit. False with the reason when `header`
// exceeds it (or declares no pixels).
bool FitsExpectedSize(const JpegHeader& header, int max_width_px, int max_height_px,
                      std::string* why);

}  // namespace mostar::client
