#include "Progress.hpp"

#include "conftrack/core/Log.hpp"

#include <cstdio>
#include <unistd.h>

namespace conftrack::cli {

namespace {
using Clock = std::chrono::steady_clock;
/// Redraw interval of the bar, and of plain lines when not a terminal.
constexpr auto kBarInterval = std::chrono::milliseconds(100);
constexpr auto kLineInterval = std::chrono::seconds(10);
}  // namespace

Progress::Progress(std::string label, std::size_t total)
    : m_label(std::move(label)),
      m_total(total),
      m_terminal(isatty(STDERR_FILENO) != 0),
      m_enabled(log::level() <= log::Level::eInfo && total > 0),
      m_start(Clock::now()),
      m_lastPrint(m_start) {}

Progress::~Progress() { finish(); }

void Progress::advance() {
  std::size_t done = ++m_done;
  if (!m_enabled) {
    return;
  }
  auto now = Clock::now();
  std::unique_lock<std::mutex> lock(m_mutex, std::try_to_lock);
  if (!lock.owns_lock() || m_finished) {
    return;
  }
  if (now - m_lastPrint >= (m_terminal ? kBarInterval : kLineInterval)) {
    m_lastPrint = now;
    print(done, false);
  }
}

void Progress::finish() {
  std::lock_guard<std::mutex> lock(m_mutex);
  if (m_finished) {
    return;
  }
  m_finished = true;
  if (m_enabled) {
    print(m_done.load(), true);
  }
}

void Progress::print(std::size_t done, bool final) {
  double seconds =
      std::chrono::duration<double>(Clock::now() - m_start).count();
  double fraction = m_total > 0 ? double(done) / double(m_total) : 1.0;
  if (m_terminal) {
    constexpr int kWidth = 30;
    int filled = static_cast<int>(fraction * kWidth);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r%s [%s] %zu/%zu events, %.1f s%s", m_label.c_str(),
                 bar.c_str(), done, m_total, seconds, final ? "\n" : "");
  } else {
    std::fprintf(stderr, "conftrack %s: %zu/%zu events (%.0f%%), %.1f s\n",
                 m_label.c_str(), done, m_total, 100.0 * fraction, seconds);
  }
  std::fflush(stderr);
}

}  // namespace conftrack::cli
