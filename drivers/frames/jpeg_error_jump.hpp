// libjpeg's errors as a jump back to the caller's setjmp, with its message kept. Its
// default error handler ends the process; a frame reader or a tool must go on. The code
// between the setjmp and libjpeg's calls must hold nothing with a destructor.
#pragma once

// clang-format off
#include <cstdio>  // jpeglib.h needs FILE declared first
#include <jpeglib.h>
// clang-format on

#include <csetjmp>

namespace ccdlane {

struct JpegErrorJump {
  jpeg_error_mgr manager;  // first: libjpeg's err pointer is this struct's address
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

// libjpeg's error_exit for a JpegErrorJump: keeps the message and jumps.
inline void jpeg_error_jump(j_common_ptr info) {
  auto* e = reinterpret_cast<JpegErrorJump*>(info->err);
  (*info->err->format_message)(info, e->message);
  std::longjmp(e->jump, 1);
}

// libjpeg's standard error manager in `e`, failing by a jump: what a jpeg_*_struct's err takes.
inline jpeg_error_mgr* jpeg_jumping_errors(JpegErrorJump& e) {
  jpeg_error_mgr* manager = jpeg_std_error(&e.manager);
  manager->error_exit = jpeg_error_jump;
  e.message[0] = '\0';
  return manager;
}

}  // namespace ccdlane
