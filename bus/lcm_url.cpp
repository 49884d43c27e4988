// By the URL's provider prefix, as lcm_create chooses its provider.
#include "bus/lcm_url.hpp"

namespace ccdlane {

std::string lcm_url_problem(std::string_view url) {
  if (url.starts_with("udpm://") || url.starts_with("memq://") || url.starts_with("file://")) return "";
  if (url.starts_with("tcpq://"))
    return "tcpq:// is not supported (LCM's tcpq client aborts the process when its server is unreachable); use "
           "udpm://, memq:// or file://";
  return "must name an LCM bus (udpm://, memq:// or file://), e.g. \"udpm://239.255.76.67:7667?ttl=0\"";
}

}  // namespace ccdlane
