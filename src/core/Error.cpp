#include "conftrack/core/Error.hpp"

namespace conftrack {

namespace {
std::string join(std::string_view where, std::string_view what) {
  std::string s(where);
  if (!s.empty()) {
    s += ": ";
  }
  s += what;
  return s;
}
}  // namespace

InputError::InputError(std::string_view where, std::string_view what)
    : std::runtime_error(join(where, what)) {}

std::string location(std::string_view file, std::size_t line) {
  std::string s(file);
  if (line > 0) {
    s += ':';
    s += std::to_string(line);
  }
  return s;
}

}  // namespace conftrack
