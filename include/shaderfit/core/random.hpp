// Random numbers. Every random routine in shaderfit takes its generator explicitly, so a run is
// reproducible from its seed. The generator is std::mt19937_64 (its output is fixed by the C++
// standard); the conversions below are written here, not taken from <random>'s distributions,
// whose outputs differ between standard libraries.
//
//   Rng rng(seed);
//   double u = uniform(rng, 1.34, 1.7);
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <string_view>

namespace shaderfit {

using Rng = std::mt19937_64;

// Uniform in [0, 1), 53 random bits.
inline double uniform01(Rng& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// Uniform in [a, b).
inline double uniform(Rng& rng, double a, double b) { return a + (b - a) * uniform01(rng); }

// Uniform integer in [0, n), n > 0 (Lemire's multiply-shift; bias below 2^-64 * n).
inline std::uint64_t uniform_index(Rng& rng, std::uint64_t n) {
  __extension__ using u128 = unsigned __int128;  // GCC and Clang; __extension__ quiets -Wpedantic
  return static_cast<std::uint64_t>((static_cast<u128>(rng()) * n) >> 64);
}

// True with probability p.
inline bool bernoulli(Rng& rng, double p) { return uniform01(rng) < p; }

// The generator's whole state as text (operator<< in the classic locale), and back: how
// checkpoints and the ranks of a distributed search carry it. rng_from_text returns false, and
// leaves *rng as it was, for text that is not such a state.
std::string rng_text(const Rng& rng);
bool rng_from_text(std::string_view text, Rng* rng);

}  // namespace shaderfit
