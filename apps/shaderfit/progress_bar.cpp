#include "progress_bar.hpp"

#include <fmt/format.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "cli.hpp"

namespace shaderfit::cli {

namespace {

constexpr double kInterval = 0.1;      // seconds between draws
constexpr std::size_t kBarWidth = 20;  // characters of the bar itself
constexpr char kClearLine[] = "\r\033[K";

double seconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

// Columns of the terminal on stderr, 80 when it does not say.
std::size_t terminal_width() {
  winsize w{};
  if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &w) == 0 && w.ws_col > 0) return w.ws_col;
  return 80;
}

}  // namespace

std::string format_progress_line(std::string_view label, double fraction, std::string_view detail,
                                 double elapsed_s, std::size_t width) {
  std::string head(label);
  if (fraction >= 0) {
    const double f = std::clamp(fraction, 0.0, 1.0);
    const auto filled = static_cast<std::size_t>(std::floor(f * kBarWidth + 1e-9));
    head += fmt::format(" [{}{}] {:3.0f}%", std::string(filled, '#'),
                        std::string(kBarWidth - filled, '-'), std::floor(f * 100));
  }
  const std::string tail = fmt::format("  {:.1f} s", elapsed_s);
  const std::size_t room = width > 0 ? width - 1 : 0;
  std::string line = head;
  if (!detail.empty()) {
    const std::size_t fixed = head.size() + 2 + tail.size();
    if (fixed < room) line += "  " + std::string(detail.substr(0, room - fixed));
  }
  line += tail;
  if (line.size() > room) line.resize(room);
  return line;
}

ProgressBar::ProgressBar(const Context& ctx, std::string label, double delay_s)
    : err_(ctx.progress ? &ctx.err : nullptr),
      label_(std::move(label)),
      start_(std::chrono::steady_clock::now()),
      delay_s_(delay_s) {
  if (err_ != nullptr) width_ = terminal_width();
}

ProgressBar::~ProgressBar() { clear(); }

void ProgressBar::update(double fraction, std::string_view detail) {
  if (err_ == nullptr) return;
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  const auto now = std::chrono::steady_clock::now();
  if (seconds(now - start_) < delay_s_) return;
  if (seconds(now - last_draw_) < kInterval) return;
  last_draw_ = now;
  *err_ << '\r' << format_progress_line(label_, fraction, detail, seconds(now - start_), width_)
        << "\033[K" << std::flush;
  shown_ = true;
}

void ProgressBar::update(const Progress& p) {
  if (err_ == nullptr) return;
  update(p.total > 0 ? static_cast<double>(p.done) / static_cast<double>(p.total) : -1.0,
         fmt::format("{}/{} {}", p.done, p.total, p.unit));
}

ProgressCallback ProgressBar::callback() {
  if (err_ == nullptr) return {};
  return [this](const Progress& p) { update(p); };
}

void ProgressBar::clear() {
  if (err_ == nullptr) return;
  std::lock_guard lock(mutex_);
  if (shown_) *err_ << kClearLine << std::flush;
  shown_ = false;
}

}  // namespace shaderfit::cli
