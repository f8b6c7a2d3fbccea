#include "libvdbappear/util/progress.h"

#include <fmt/format.h>

#include <cstdio>
#include <unistd.h>

namespace vdbappear {

bool stderrIsTerminal() { return isatty(STDERR_FILENO) == 1; }

ProgressBar::ProgressBar(std::string label, std::uint64_t total, bool enabled)
    : label_(std::move(label)), total_(total), enabled_(enabled), start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::advance(std::uint64_t steps) {
  const std::uint64_t done = done_.fetch_add(steps) + steps;
  if (!enabled_) return;
  std::unique_lock lock(draw_mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100) && done < total_) return;
  last_draw_ = now;
  draw(done);
}

void ProgressBar::setStatus(std::string status) {
  std::lock_guard lock(draw_mutex_);
  status_ = std::move(status);
}

void ProgressBar::finish() {
  if (!enabled_ || finished_) return;
  std::lock_guard lock(draw_mutex_);
  if (drawn_ == ~std::uint64_t(0)) return;  // nothing shown (work failed before it started): no line
  if (drawn_ != done_.load()) draw(done_.load());
  std::fputc('\n', stderr);
  finished_ = true;
}

void ProgressBar::draw(std::uint64_t done) {
  constexpr int kWidth = 30;
  drawn_ = done;
  const double fraction = total_ ? std::min(1.0, double(done) / double(total_)) : 1.0;
  const int filled = int(fraction * kWidth);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::string left = fraction > 0 && fraction < 1 ? fmt::format(", {:.0f}s left", seconds * (1 - fraction) / fraction) : "";
  // \x1b[K clears what a longer earlier line left behind (the bar is drawn on terminals only).
  fmt::print(stderr, "\r{} [{}{}] {:3.0f}% {:.1f}s{}{}{}\x1b[K", label_, std::string(filled, '#'),
             std::string(kWidth - filled, '.'), 100 * fraction, seconds, left, status_.empty() ? "" : "  ", status_);
  std::fflush(stderr);
}

}  // namespace vdbappear
