#include "app/service/crash_report.hpp"

#include <execinfo.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>

namespace probeless {
namespace {

constexpr std::array kFatalSignals{SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT};
constexpr int kMaxFrames = 64;

const char* g_program = "probeless";
std::atomic<bool> g_installed{false};
std::atomic<bool> g_reporting{false};  // a second fault inside the handler: die at once

// Async-signal-safe formatting: no printf, no allocation.
struct Line {
  std::array<char, 256> text{};
  std::size_t size = 0;
  Line& add(const char* s) {
    while (*s != '\0' && size < text.size()) text[size++] = *s++;
    return *this;
  }
  Line& add_hex(std::uintptr_t value) {
    char digits[2 * sizeof value + 1];
    int n = 0;
    do {
      digits[n++] = "0123456789abcdef"[value & 0xf];
      value >>= 4;
    } while (value != 0);
    add("0x");
    while (n > 0 && size < text.size()) text[size++] = digits[--n];
    return *this;
  }
  Line& add_decimal(unsigned long value) {
    char digits[24];
    int n = 0;
    do {
      digits[n++] = static_cast<char>('0' + value % 10);
      value /= 10;
    } while (value != 0);
    while (n > 0 && size < text.size()) text[size++] = digits[--n];
    return *this;
  }
  void write_to(int fd) const {
    std::size_t done = 0;
    while (done < size) {
      const ssize_t n = ::write(fd, text.data() + done, size - done);
      if (n <= 0) return;
      done += static_cast<std::size_t>(n);
    }
  }
};

void on_fatal_signal(int signal_number, siginfo_t* info, void*) {
  if (!g_reporting.exchange(true)) {
    // sd-daemon priority prefix: journald files it as crit; a terminal shows "<2>" plainly.
    char thread[17] = {};
    ::prctl(PR_GET_NAME, thread, 0, 0, 0);
    Line head;
    head.add("<2>").add(g_program).add(": fatal signal ").add(sigabbrev_np(signal_number));
    if (info->si_code == SI_USER || info->si_code == SI_TKILL)  // kill(), raise(), abort()
      head.add(" sent by pid ").add_decimal(static_cast<unsigned long>(info->si_pid));
    else
      head.add(" at address ").add_hex(reinterpret_cast<std::uintptr_t>(info->si_addr));
    head.add(" in thread \"").add(thread).add("\"; backtrace (addr2line -fCe BINARY +OFFSET):\n");
    head.write_to(STDERR_FILENO);
    void* frames[kMaxFrames];
    const int depth = ::backtrace(frames, kMaxFrames);
    ::backtrace_symbols_fd(frames, depth, STDERR_FILENO);
  }
  // SA_RESETHAND already put the default action back: returning re-runs the faulting
  // instruction (SIGSEGV, SIGBUS, ...) and dies of it; raise() covers abort() and kill().
  ::raise(signal_number);
}

}  // namespace

void install_crash_report(const char* program) {
  if (g_installed.exchange(true)) return;
  g_program = program;
  void* warm[1];
  ::backtrace(warm, 1);  // loads libgcc's unwinder now, not inside the handler
  // The alternate stack: SIGSEGV from a stack overflow cannot run on the overflowed stack.
  // Per thread in principle; the main thread's covers its own overflows, and other threads'
  // faults that are not overflows run on their own stacks.
  static std::array<char, 64 * 1024> alternate_stack;
  stack_t stack{};
  stack.ss_sp = alternate_stack.data();
  stack.ss_size = alternate_stack.size();
  ::sigaltstack(&stack, nullptr);
  struct sigaction action {};
  action.sa_sigaction = on_fatal_signal;
  action.sa_flags = SA_SIGINFO | SA_ONSTACK | SA_RESETHAND;
  sigemptyset(&action.sa_mask);
  for (const int signal_number : kFatalSignals) ::sigaction(signal_number, &action, nullptr);
}

}  // namespace probeless
