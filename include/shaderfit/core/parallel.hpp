// Parallel loops over index ranges, on a persistent pool of worker threads (std::thread).
//
//   shaderfit::parallel_for(rows, 4096, [&](std::size_t begin, std::size_t end) {
//     for (std::size_t i = begin; i < end; ++i) out[i] = f(in[i]);
//   });
//
// The body is called once per range (a task), never per index, through one indirect call, so
// the header stays light and the loop body is compiled where it is written.
#pragma once

#include <cstddef>
#include <memory>
#include <type_traits>

namespace shaderfit {

class RangeFunctionRef;

// A callable body(begin, end) other than a RangeFunctionRef itself.
template <typename F>
concept RangeBody = !std::is_same_v<std::remove_cvref_t<F>, RangeFunctionRef> &&
                    std::is_invocable_v<F&, std::size_t, std::size_t>;

// A non-owning reference to a callable `void(std::size_t begin, std::size_t end)`. It must not
// outlive the callable; passing a lambda straight to parallel_for is always safe.
class RangeFunctionRef {
 public:
  // Implicit, so that a lambda can be passed where a RangeFunctionRef is expected.
  template <RangeBody F>
  // NOLINTNEXTLINE(google-explicit-constructor,bugprone-forwarding-reference-overload)
  RangeFunctionRef(F&& f) noexcept
      : object_(const_cast<void*>(static_cast<const void*>(std::addressof(f)))),
        call_(&invoke<std::remove_reference_t<F>>) {}

  void operator()(std::size_t begin, std::size_t end) const { call_(object_, begin, end); }

 private:
  template <typename F>
  static void invoke(void* object, std::size_t begin, std::size_t end) {
    (*static_cast<F*>(object))(begin, end);
  }

  void* object_;
  void (*call_)(void*, std::size_t, std::size_t);
};

class ThreadPool {
 public:
  // `threads`: how many threads a loop uses by default, the calling thread included;
  // 0 means std::thread::hardware_concurrency() (at least 1). Workers start on first need.
  explicit ThreadPool(int threads = 0);
  // Joins the workers. No loop may still be running on the pool.
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  [[nodiscard]] int threads() const noexcept;

  // Calls body(begin, end) on consecutive ranges that cover [0, n) exactly once. With one
  // thread, or n <= grain, that is body(0, n) on the caller. Otherwise the ranges are `grain`
  // indices long (grain 0 counts as 1; the last may be shorter) and are handed out one at a
  // time to up to `max_threads` threads (0: threads()), the calling thread included; asking
  // for more threads than threads() starts more workers. Returns when every range is done.
  // If a body throws, ranges not yet started are skipped and the first exception is rethrown
  // here once the running ones have finished. Safe to call from several threads at once and
  // from inside a body: the caller always works on its own loop, so nested loops cannot
  // deadlock.
  void parallel_for(std::size_t n, std::size_t grain, RangeFunctionRef body, int max_threads = 0);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// The process-wide pool, created on first use with hardware_concurrency() threads.
ThreadPool& default_thread_pool();

// parallel_for on default_thread_pool(); `threads` as ThreadPool::parallel_for's max_threads.
inline void parallel_for(std::size_t n, std::size_t grain, RangeFunctionRef body, int threads = 0) {
  default_thread_pool().parallel_for(n, grain, body, threads);
}

}  // namespace shaderfit
