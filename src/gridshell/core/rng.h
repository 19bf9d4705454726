#pragma once
/// \file rng.h
/// The project's random generator. Randomness enters only through an explicit `Rng` passed in,
/// so that a `--seed` makes every run reproducible on any platform: we use our own uniform
/// mapping because `std::uniform_real_distribution` differs between standard libraries.

#include <cstdint>
#include <random>

namespace gridshell {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  /// Uniform in [0, 1).
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  /// Uniform in [a, b).
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  /// Uniform integer in [0, n).
  std::uint64_t index(std::uint64_t n) { return n == 0 ? 0 : engine_() % n; }
  std::uint64_t raw() { return engine_(); }

 private:
  std::mt19937_64 engine_;
};

}  // namespace gridshell
