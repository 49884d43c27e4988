# Project-wide warnings and sanitizer flags, applied to every ccdlane target through
# ccdlane_target_options(), so third-party headers keep their own flags.
add_library(ccdlane_compile_options INTERFACE)
add_library(ccdlane::compile_options ALIAS ccdlane_compile_options)
target_compile_options(ccdlane_compile_options INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
  -Wnon-virtual-dtor -Wold-style-cast -Wcast-align -Woverloaded-virtual
  -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough)
if(CCDLANE_WERROR)
  target_compile_options(ccdlane_compile_options INTERFACE -Werror)
endif()
if(CCDLANE_SANITIZE)
  target_compile_options(ccdlane_compile_options INTERFACE
    -fsanitize=${CCDLANE_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  target_link_options(ccdlane_compile_options INTERFACE -fsanitize=${CCDLANE_SANITIZE})
endif()

function(ccdlane_target_options target)
  target_link_libraries(${target} PRIVATE ccdlane::compile_options)
endfunction()
