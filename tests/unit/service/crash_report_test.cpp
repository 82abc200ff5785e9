// install_crash_report (app/service/crash_report.hpp): a fatal signal is named on stderr with
// its address, thread and a backtrace, and the process still dies of that signal. Each case
// crashes a forked child and reads what it wrote.
#include "app/service/crash_report.hpp"

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <regex>
#include <string>

namespace probeless {
namespace {

struct Crash {
  std::string report;
  int status = 0;
};

// Runs `crash` in a child whose stderr is a pipe; returns what it wrote and how it ended.
Crash crash_child(const std::function<void()>& crash) {
  int out[2];
  if (::pipe(out) != 0) throw std::runtime_error("pipe");
  const pid_t child = ::fork();
  if (child == 0) {
    ::dup2(out[1], STDERR_FILENO);
    ::close(out[0]);
    ::prctl(PR_SET_NAME, "crashtest", 0, 0, 0);
    install_crash_report("crashtest");
    crash();
    ::_exit(0);  // the crash did not happen: the test sees exit 0
  }
  ::close(out[1]);
  Crash result;
  char buffer[4096];
  for (ssize_t n; (n = ::read(out[0], buffer, sizeof buffer)) > 0;) result.report.append(buffer, n);
  ::close(out[0]);
  ::waitpid(child, &result.status, 0);
  return result;
}

int frames_in(const std::string& report) {
  const std::regex frame(R"(\[0x[0-9a-f]+\])");
  return static_cast<int>(std::distance(std::sregex_iterator(report.begin(), report.end(), frame),
                                        std::sregex_iterator()));
}

TEST(CrashReport, ASegfaultIsNamedWithItsAddressAndABacktraceAndStillKills) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "ASan reports segfaults itself";
#endif
  void* page = ::mmap(nullptr, 4096, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(page, MAP_FAILED);
  const Crash crash = crash_child([page] { *static_cast<volatile int*>(page) = 1; });
  ::munmap(page, 4096);
  ASSERT_TRUE(WIFSIGNALED(crash.status)) << "exited instead: " << crash.report;
  EXPECT_EQ(WTERMSIG(crash.status), SIGSEGV);
  char address[32];
  std::snprintf(address, sizeof address, "%p", page);
  EXPECT_NE(crash.report.find(std::string("<2>crashtest: fatal signal SEGV at address ") + address),
            std::string::npos)
      << crash.report;
  EXPECT_NE(crash.report.find("in thread \"crashtest\""), std::string::npos) << crash.report;
  EXPECT_GE(frames_in(crash.report), 3) << crash.report;
}

// Recursion without end: the fault happens with the stack used up, so only the alternate
// signal stack lets the report run at all.
volatile long g_depth_limit = 1L << 40;  // never reached: the stack runs out first
[[gnu::noinline]] long recurse(long depth) {
  volatile char frame[1024];
  frame[0] = static_cast<char>(depth);
  if (depth >= g_depth_limit) return depth;
  return recurse(depth + 1) + frame[0];
}

TEST(CrashReport, AStackOverflowIsStillReported) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "ASan reports stack overflows itself";
#endif
  const Crash crash = crash_child([] { std::printf("%ld", recurse(0)); });
  ASSERT_TRUE(WIFSIGNALED(crash.status)) << crash.report;
  EXPECT_EQ(WTERMSIG(crash.status), SIGSEGV);
  EXPECT_NE(crash.report.find("fatal signal SEGV"), std::string::npos) << crash.report;
  EXPECT_GE(frames_in(crash.report), 3) << crash.report;
}

TEST(CrashReport, AnAbortIsReportedAndEndsAsAnAbort) {
  const Crash crash = crash_child([] { std::abort(); });
  ASSERT_TRUE(WIFSIGNALED(crash.status)) << crash.report;
  EXPECT_EQ(WTERMSIG(crash.status), SIGABRT);
  EXPECT_NE(crash.report.find("<2>crashtest: fatal signal ABRT sent by pid "), std::string::npos)
      << crash.report;
}

TEST(CrashReport, WithoutACrashNothingIsWritten) {
  const Crash crash = crash_child([] {});
  ASSERT_TRUE(WIFEXITED(crash.status));
  EXPECT_EQ(WEXITSTATUS(crash.status), 0);
  EXPECT_EQ(crash.report, "");
}

}  // namespace
}  // namespace probeless
