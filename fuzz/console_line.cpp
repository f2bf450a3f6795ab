// Console lines (control/console_command): never throws; errors come back as text.
#include <string_view>

#include "control/console_command.hpp"
#include "harness.hpp"

MG_FUZZ_TARGET({
  std::string_view text = mg::fuzz::as_text(data, size);
  while (!text.empty()) {
    const auto nl = text.find('\n');
    (void)mg::control::parse_console_line(text.substr(0, nl));
    if (nl == std::string_view::npos) break;
    text.remove_prefix(nl + 1);
  }
})
