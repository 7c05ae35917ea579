// libjpeg's error handling for every JPEG coder of mostar (the robot's compressor and decoder,
// the client's decoder and header reader). libjpeg reports a fatal error through error_exit,
// which must not return: it keeps the message and longjmps back to the caller's
// setjmp(manager.jump). A function that calls setjmp must keep only trivially destructible
// locals between it and any libjpeg call, so that no destructor is skipped. Warnings (corrupt
// or truncated data) are counted and the first one's message kept, never printed: each caller
// decides what a warning means.
#pragma once

// clang-format off
#include <cstdio>  // jpeglib.h needs FILE and size_t first
#include <jpeglib.h>
// clang-format on

#include <csetjmp>

namespace mostar {

struct JpegErrorManager {
  jpeg_error_mgr base;  // what cinfo.err points to
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
  int warnings;
};

// Installs the handlers and clears the message and the warning count; returns &manager->base
// for cinfo.err.
jpeg_error_mgr* InitJpegErrorManager(JpegErrorManager* manager);

}  // namespace mostar
