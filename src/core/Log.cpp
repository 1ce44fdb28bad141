#include "conftrack/core/Log.hpp"

#include <atomic>
#include <iostream>
#include <mutex>

namespace conftrack::log {

namespace {
std::atomic<int> gLevel{static_cast<int>(Level::eInfo)};
std::mutex gMutex;

const char* label(Level level) {
  switch (level) {
    case Level::eDebug:
      return "debug";
    case Level::eInfo:
      return "info";
    case Level::eWarning:
      return "warning";
    case Level::eError:
      return "error";
  }
  return "?";
}
}  // namespace

void setLevel(Level level) { gLevel = static_cast<int>(level); }

Level level() { return static_cast<Level>(gLevel.load()); }

void write(Level lvl, const std::string& message) {
  if (static_cast<int>(lvl) < gLevel.load()) {
    return;
  }
  std::lock_guard<std::mutex> lock(gMutex);
  std::cerr << "conftrack " << label(lvl) << ": " << message << '\n';
}

}  // namespace conftrack::log
