#pragma once

/// @file TextFields.hpp
/// Small helpers shared by the text readers of io and geometry.

#include <string_view>

namespace conftrack {

/// `s` without leading blanks (space, tab) and trailing blanks or '\r'
/// (a CRLF line end).
constexpr std::string_view trimField(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) {
    s.remove_prefix(1);
  }
  while (!s.empty() &&
         (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  return s;
}

}  // namespace conftrack
