#pragma once

/// @file Progress.hpp
/// Progress report for loops over events: a bar on stderr when stderr is a
/// terminal, periodic plain lines otherwise (logs, CI). Thread-safe.

#include <atomic>
#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace conftrack::cli {

class Progress {
 public:
  /// `label` e.g. "simulate"; `total` number of items.
  Progress(std::string label, std::size_t total);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// One more item done (any thread).
  void advance();
  /// Final line; called by the destructor if not called before.
  void finish();

 private:
  void print(std::size_t done, bool final);

  std::string m_label;
  std::size_t m_total;
  std::atomic<std::size_t> m_done{0};
  bool m_terminal;
  bool m_enabled;
  bool m_finished = false;
  std::mutex m_mutex;
  std::chrono::steady_clock::time_point m_start;
  std::chrono::steady_clock::time_point m_lastPrint;
};

}  // namespace conftrack::cli
