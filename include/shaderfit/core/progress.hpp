// Progress of long computations (a bake of tables, fits per cell, a sweep), reported to whoever
// shows it: the library only counts and reports; the command-line tool draws the bar.
//
//   FvLutOptions o;
//   o.on_progress = [](const Progress& p) { std::cerr << p.done << " of " << p.total << '\n'; };
//   bake_fv_luts(o, kAllFvVariants);  // reports cells fitted so far
//
// A callback may be called from any of the computation's threads, one call at a time, often
// (once per unit of work): it should return quickly and draw at a rate of its own.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <mutex>
#include <string_view>

namespace shaderfit {

struct Progress {
  std::size_t done = 0;   // units finished so far, <= total
  std::size_t total = 0;  // units in the whole computation
  std::string_view unit;  // what is counted, plural: "cells", "forms"
};

using ProgressCallback = std::function<void(const Progress&)>;

// Counts finished units from any thread and passes each new count to a callback (none: counts
// only), one call at a time; a report that would wait for another call is skipped, the next one
// carries the count.
class ProgressCounter {
 public:
  ProgressCounter(const ProgressCallback& callback, std::size_t total, std::string_view unit)
      : callback_(callback), total_(total), unit_(unit) {}
  ProgressCounter(const ProgressCounter&) = delete;
  ProgressCounter& operator=(const ProgressCounter&) = delete;

  void add(std::size_t units = 1);

 private:
  const ProgressCallback& callback_;
  std::size_t total_;
  std::string_view unit_;
  std::atomic<std::size_t> done_{0};
  std::mutex mutex_;
};

}  // namespace shaderfit
