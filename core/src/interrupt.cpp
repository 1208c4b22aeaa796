#include "mapnav/core/interrupt.h"

#include <csignal>
#include <string>

namespace mapnav {

namespace {
volatile std::sig_atomic_t g_signal = 0;

extern "C" void recordSignal(int signal_number) { g_signal = signal_number; }
}  // namespace

Interrupted::Interrupted(int signal_number)
    : Error("interrupted by signal " + std::to_string(signal_number) + "; no output was changed"),
      signal_(signal_number) {}

void installInterruptHandlers() {
  struct sigaction action {};
  action.sa_handler = recordSignal;
  sigemptyset(&action.sa_mask);
  // SA_RESETHAND: a second signal takes the default action (the process ends); SA_RESTART: reads and
  // writes under way are not cut short by EINTR (they finish, then the next check throws).
  action.sa_flags = SA_RESETHAND | SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int interruptSignal() { return g_signal; }

void throwIfInterrupted() {
  if (const int s = g_signal; s != 0) throw Interrupted(s);
}

}  // namespace mapnav
