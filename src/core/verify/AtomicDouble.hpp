// A double shared by the search's workers, updated lock-free (relaxed: a sum or a running maximum, read once the
// workers are done or for progress reports). Internal to the core.
#pragma once

#include <atomic>

namespace pkm_accuracy {
namespace verify {

class AtomicDouble {
 public:
  explicit AtomicDouble(double v = 0.0) : v_(v) {}
  double load() const { return v_.load(std::memory_order_relaxed); }
  void add(double x) {
    double cur = v_.load(std::memory_order_relaxed);
    while (!v_.compare_exchange_weak(cur, cur + x, std::memory_order_relaxed)) {
    }
  }
  /// Raises the value to x if x is larger; returns true if it did.
  bool raise(double x) {
    double cur = v_.load(std::memory_order_relaxed);
    while (x > cur) {
      if (v_.compare_exchange_weak(cur, x, std::memory_order_relaxed)) return true;
    }
    return false;
  }

 private:
  std::atomic<double> v_;
};

/// Raises `a` to v if v is larger (relaxed).
inline void raiseAtomic(std::atomic<int>& a, int v) {
  int cur = a.load(std::memory_order_relaxed);
  while (v > cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}

}  // namespace verify
}  // namespace pkm_accuracy
