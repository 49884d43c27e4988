// Which LCM bus URLs ccdlane opens: the providers that work, refused at --check-config
// (and by the tools' --lcm) rather than failing at run time.
#pragma once

#include <string>
#include <string_view>

namespace ccdlane {

// "" for udpm://, memq:// and file:// URLs; else why not. tcpq:// is refused: LCM's
// client select()s on a descriptor past FD_SETSIZE when its server is unreachable and
// aborts the process about 2 s after start ("bit out of range 0 - FD_SETSIZE").
std::string lcm_url_problem(std::string_view url);

}  // namespace ccdlane
