// SIGINT and SIGTERM: the handlers and what they leave to the fill.
#include "interrupt.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstring>

#include "foldfill/file.h"

namespace foldfill::cli {
namespace {

static_assert(std::atomic<int>::is_always_lock_free);
std::atomic<int> signal_number{0};  // the first signal that came, or 0
std::atomic<int> watched_fills{0};
std::atomic<int> writes{0};

void say(const char* text) {
  for (size_t left = std::strlen(text); left > 0;) {
    const ssize_t n = ::write(STDERR_FILENO, text, left);
    if (n <= 0) return;
    text += n;
    left -= static_cast<size_t>(n);
  }
}

// Async-signal-safe: atomics, unlinkat, write and _exit only. Each of the
// watched work and the writes checks signal_number after announcing itself
// in its counter, and the handler reads the counters after setting it, so
// either the handler sees the write and ends the process or the writer sees
// the signal and does not start.
void on_signal(int signo) {
  const int previous = signal_number.exchange(signo);
  if (previous == 0 && watched_fills.load() > 0 && writes.load() == 0) return;
  unlink_pending_temporaries();
  say(signo == SIGTERM ? "foldfill: error: interrupted (SIGTERM)\n"
                       : "foldfill: error: interrupted (SIGINT)\n");
  ::_exit(kInterruptedExitCode);
}

}  // namespace

void install_interrupt_handlers() {
  for (const int signo : {SIGINT, SIGTERM}) {
    struct sigaction old_action {};
    if (::sigaction(signo, nullptr, &old_action) == 0 && old_action.sa_handler == SIG_IGN) {
      continue;
    }
    struct sigaction action {};
    action.sa_handler = on_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    ::sigaction(signo, &action, nullptr);
  }
}

bool interrupted() { return signal_number.load() != 0; }

const char* Interrupted::what() const noexcept {
  return signal_number.load() == SIGTERM ? "interrupted (SIGTERM)" : "interrupted (SIGINT)";
}

void stop_if_interrupted() {
  if (interrupted()) throw Interrupted();
}

WatchedFill::WatchedFill() { ++watched_fills; }
WatchedFill::~WatchedFill() { --watched_fills; }

Writing::Writing() {
  ++writes;
  if (interrupted()) {
    --writes;
    throw Interrupted();
  }
}
Writing::~Writing() { --writes; }

}  // namespace foldfill::cli
