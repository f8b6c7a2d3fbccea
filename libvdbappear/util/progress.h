#pragma once
// A progress bar on stderr for long work. Draws only when stderr is a terminal, so pipelines and
// logs stay clean. advance() may be called from any thread.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace vdbappear {

bool stderrIsTerminal();

class ProgressBar {
 public:
  ProgressBar(std::string label, std::uint64_t total, bool enabled = stderrIsTerminal());
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void setTotal(std::uint64_t total) { total_ = total; }  // before the first advance()
  void advance(std::uint64_t steps = 1);
  // Text shown after the bar (e.g. "iteration 3/30, E 0.0123"), drawn at the next advance().
  void setStatus(std::string status);
  void finish();  // draws the final state and ends the line, if anything was drawn

 private:
  void draw(std::uint64_t done);

  std::string label_;
  std::string status_;  // guarded by draw_mutex_
  std::atomic<std::uint64_t> total_;
  bool enabled_;
  bool finished_ = false;
  std::atomic<std::uint64_t> done_{0};
  std::uint64_t drawn_ = ~std::uint64_t(0);  // steps shown by the last draw
  std::mutex draw_mutex_;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace vdbappear
