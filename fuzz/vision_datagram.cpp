// Vision datagrams (perception/vision_message): never throws; errors come back as a code.
#include "harness.hpp"
#include "perception/vision_message.hpp"

MG_FUZZ_TARGET({
  (void)mg::perception::parse_vision_message(mg::fuzz::as_text(data, size),
                                             mg::perception::VisionLimits{});
})
