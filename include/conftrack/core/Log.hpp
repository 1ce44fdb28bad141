#pragma once

/// @file Log.hpp
/// Minimal levelled logging to stderr, thread-safe, set once by the CLI.
/// Keep it out of hot loops: reconstruction reports through counters.

#include <sstream>
#include <string>

namespace conftrack::log {

enum class Level : int { eDebug = 0, eInfo = 1, eWarning = 2, eError = 3 };

/// Sets the global threshold (default eInfo).
void setLevel(Level level);
/// Current threshold.
Level level();
/// Writes one line "[level] message" to stderr if level >= threshold.
void write(Level level, const std::string& message);

}  // namespace conftrack::log

#define CONFTRACK_LOG(lvl, expr)                               \
  do {                                                         \
    if (static_cast<int>(lvl) >=                               \
        static_cast<int>(::conftrack::log::level())) {         \
      std::ostringstream conftrack_log_os_;                    \
      conftrack_log_os_ << expr;                               \
      ::conftrack::log::write((lvl), conftrack_log_os_.str()); \
    }                                                          \
  } while (false)
#define CONFTRACK_DEBUG(expr) \
  CONFTRACK_LOG(::conftrack::log::Level::eDebug, expr)
#define CONFTRACK_INFO(expr) CONFTRACK_LOG(::conftrack::log::Level::eInfo, expr)
#define CONFTRACK_WARNING(expr) \
  CONFTRACK_LOG(::conftrack::log::Level::eWarning, expr)
#define CONFTRACK_ERROR(expr) \
  CONFTRACK_LOG(::conftrack::log::Level::eError, expr)
