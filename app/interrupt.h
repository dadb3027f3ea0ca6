// SIGINT and SIGTERM. While a fill runs, a signal cancels it through its
// progress callback (FillOptions::progress returning false) and the command
// exits with kInterruptedExitCode without writing anything more; at any other
// moment (reading, writing, a fill that is not watched) the process ends at
// once with that code, after removing the named temporary file of a write in
// progress: a file being written is left untouched, a file already written
// stays. A second signal ends the process at once too.
#pragma once

#include <exception>

namespace foldfill::cli {

constexpr int kInterruptedExitCode = 130;

// Installs the handlers (a signal ignored when the program started, as in a
// background job, stays ignored).
void install_interrupt_handlers();

// A signal came.
bool interrupted();

// Thrown where the work stops because a signal came; main exits with
// kInterruptedExitCode.
class Interrupted : public std::exception {
 public:
  const char* what() const noexcept override;  // "interrupted (SIGINT)"
};

// Throws Interrupted when a signal came.
void stop_if_interrupted();

// While one lives, a fill watches interrupted() in its progress callback, so
// a signal only marks the interruption and lets the fill cancel itself.
class WatchedFill {
 public:
  WatchedFill();
  ~WatchedFill();
  WatchedFill(const WatchedFill&) = delete;
  WatchedFill& operator=(const WatchedFill&) = delete;
};

// While one lives, files are being written: a signal ends the process at once.
// Throws Interrupted, writing nothing, when a signal came before.
class Writing {
 public:
  Writing();
  ~Writing();
  Writing(const Writing&) = delete;
  Writing& operator=(const Writing&) = delete;
};

}  // namespace foldfill::cli
