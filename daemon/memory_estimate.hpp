// What a configuration makes ccdlaned allocate at start, estimated at --check-config, so
// that 8192x8192 colour frames with queue_depth 62 are refused with the sizes that make
// them too many, not met with a bare std::bad_alloc at start.
#pragma once

#include <cstdint>
#include <string>

#include "app/config.hpp"

namespace ccdlane {

// Bytes held from start: the frame pool (queue_depth + 2 frames at the largest pixel the
// source may deliver: 3 bytes where colour is possible, 2 for a grey camera that may be
// 16-bit), the estimator's per-pixel workspaces, and a synthetic source's rendered drive.
std::uint64_t estimated_start_bytes(const Config& c);

// "" when the estimate fits in `available_bytes`, else the problem with the figures.
std::string memory_problem(const Config& c, std::uint64_t available_bytes);

// The machine's physical memory, bounded by the address-space limit (RLIMIT_AS) if one is set.
std::uint64_t available_memory_bytes();

}  // namespace ccdlane
