#include "common/jpeg/jpeg_error.h"

namespace mostar {
namespace {

void ErrorExit(j_common_ptr cinfo) {
  auto* manager = reinterpret_cast<JpegErrorManager*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, manager->message);
  std::longjmp(manager->jump, 1);
}

// Level -1 is a warning; higher levels are trace messages, ignored.
void EmitMessage(j_common_ptr cinfo, int level) {
  auto* manager = reinterpret_cast<JpegErrorManager*>(cinfo->err);
  if (level < 0) {
    if (manager->warnings == 0) (*cinfo->err->format_message)(cinfo, manager->message);
    ++manager->warnings;
  }
}

}  // namespace

jpeg_error_mgr* InitJpegErrorManager(JpegErrorManager* manager) {
  jpeg_std_error(&manager->base);
  manager->base.error_exit = ErrorExit;
  manager->base.emit_message = EmitMessage;
  manager->message[0] = '\0';
  manager->warnings = 0;
  return &manager->base;
}

}  // namespace mostar
