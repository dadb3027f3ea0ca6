// What a piece of work may still spend: a deadline and a cancel flag. The
// stages that iterate (ARAP, the minimisation and its line search) look at it
// between their steps and stop early, keeping what they have.
#pragma once

#include <atomic>
#include <chrono>
#include <optional>

namespace foldfill {

class Budget {
 public:
  using Clock = std::chrono::steady_clock;

  Budget() = default;  // no deadline, never cancelled
  // A deadline `seconds` from now (none when not positive; a NaN is none too),
  // and a flag that cancels the work once set (none when null).
  explicit Budget(double seconds, const std::atomic<bool>* cancel = nullptr) : cancel_(cancel) {
    if (seconds > 0) deadline_ = Clock::now() + to_duration(seconds);
  }

  // The earlier of this deadline and `seconds` from now.
  Budget at_most(double seconds) const {
    Budget budget = *this;
    if (seconds > 0) {
      const Clock::time_point limit = Clock::now() + to_duration(seconds);
      if (!deadline_ || limit < *deadline_) budget.deadline_ = limit;
    }
    return budget;
  }

  bool out_of_time() const { return deadline_ && Clock::now() >= *deadline_; }
  bool cancelled() const { return cancel_ && cancel_->load(std::memory_order_relaxed); }
  bool spent() const { return cancelled() || out_of_time(); }

 private:
  // Seconds as a clock duration, capped so that the deadline cannot overflow.
  static Clock::duration to_duration(double seconds) {
    constexpr double kLongest = 1e9;  // about 30 years
    return std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(seconds < kLongest ? seconds : kLongest));
  }

  std::optional<Clock::time_point> deadline_;
  const std::atomic<bool>* cancel_ = nullptr;
};

}  // namespace foldfill
