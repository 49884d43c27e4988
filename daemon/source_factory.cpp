// One row per source kind: adding a driver is one make_* function and one row.
#include "daemon/source_factory.hpp"

#include <stdexcept>

#include "daemon/test_pattern.hpp"

namespace ccdlane {
namespace {

std::unique_ptr<FrameSource> make_test_pattern(const Config& c) {
  TestPatternOptions o;
  o.width = c.camera.Nu;
  o.height = c.camera.Nv;
  o.rate_hz = c.source.rate_hz;
  return std::make_unique<TestPatternSource>(o);
}

struct SourceKindRow {
  SourceKind kind;
  const char* name;
  std::unique_ptr<FrameSource> (*make)(const Config&);  // null: not in this build
};

constexpr SourceKindRow kSourceKinds[] = {
    {SourceKind::synth, "synth", make_test_pattern},
    {SourceKind::frames, "frames", nullptr},
    {SourceKind::v4l2, "v4l2", nullptr},
    {SourceKind::aravis, "aravis", nullptr},
};

const SourceKindRow* row_of(SourceKind kind) {
  for (const SourceKindRow& row : kSourceKinds)
    if (row.kind == kind) return &row;
  return nullptr;
}

}  // namespace

std::string frame_source_unavailable(const Config& config) {
  const SourceKindRow* row = row_of(config.source.kind);
  if (row && row->make) return "";
  return std::string("source.kind: \"") + (row ? row->name : "?") + "\" is not available in this build of ccdlaned";
}

std::unique_ptr<FrameSource> make_frame_source(const Config& config) {
  const SourceKindRow* row = row_of(config.source.kind);
  if (!row || !row->make) throw std::runtime_error(frame_source_unavailable(config));
  return row->make(config);
}

}  // namespace ccdlane
