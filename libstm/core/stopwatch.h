#pragma once
/// Wall-clock timing for the per-stage figures that commands report and `sdm bench` tabulates.
#include <chrono>

namespace sdm {

/// Starts on construction; seconds() is the wall-clock time since then (or since restart()).
class Stopwatch {
 public:
  Stopwatch() : start_(Clock::now()) {}
  void restart() { start_ = Clock::now(); }
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  /// seconds(), then restart(): the time of one stage in a sequence of stages.
  double lap() {
    const double s = seconds();
    restart();
    return s;
  }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_;
};

}  // namespace sdm
