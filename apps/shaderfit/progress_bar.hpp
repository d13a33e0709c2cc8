// The command-line tool's one progress bar: a line on stderr for the commands that can take more
// than a second (search, lut, fit per block, rational sweeps), drawn only when stderr is a
// terminal (Context::progress), redrawn at most ten times a second and cleared when the work
// ends. The library only reports progress (callbacks in its options); this draws it.
//
//   ProgressBar bar(ctx, "lut");
//   options.on_progress = bar.callback();
//   bake_fv_luts(options, variants);  // lut [#####---------------]  25%  16384/65536 cells  0.8 s
//   bar.clear();                      // before printing the results
#pragma once

#include <chrono>
#include <cstddef>
#include <mutex>
#include <ostream>
#include <string>
#include <string_view>

#include "shaderfit/core/progress.hpp"

namespace shaderfit::cli {

struct Context;

// The bar's text, at most `width - 1` columns (a full-width line would wrap on some terminals):
// the label, a bar of '#' and '-' and the percentage for `fraction` in [0, 1] (none when it is
// negative: unknown), the detail, and the seconds elapsed. A detail too long is cut.
//   "lut [#####---------------]  25%  16384/65536 cells  0.8 s"
std::string format_progress_line(std::string_view label, double fraction, std::string_view detail,
                                 double elapsed_s, std::size_t width);

class ProgressBar {
 public:
  // Draws on ctx.err when ctx.progress is set, not before `delay_s` seconds (a command that ends
  // sooner shows no bar); otherwise every call does nothing.
  ProgressBar(const Context& ctx, std::string label, double delay_s = 0.5);
  ~ProgressBar();  // clears the line
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // Whether this bar draws at all.
  [[nodiscard]] bool active() const { return err_ != nullptr; }

  // Shows `fraction` done (negative: unknown) and `detail`; at most every 0.1 s, from any thread
  // (a call while another draws is skipped).
  void update(double fraction, std::string_view detail);
  // The library's count: "done/total unit".
  void update(const Progress& p);
  // A callback for a library's options that updates this bar, which must outlive the computation;
  // empty when the bar is not active, so that the library does not count for nothing.
  ProgressCallback callback();

  // Erases the line, before other output to the terminal; the next update draws it again.
  void clear();

 private:
  std::ostream* err_ = nullptr;  // null: not drawing
  std::string label_;
  std::size_t width_ = 80;
  std::chrono::steady_clock::time_point start_, last_draw_{};
  double delay_s_;
  bool shown_ = false;
  std::mutex mutex_;
};

}  // namespace shaderfit::cli
