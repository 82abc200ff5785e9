#pragma once
// Runs a reader on a hostile file with little memory to spare: in a forked child whose data
// limit (RLIMIT_DATA, which covers malloc's mmaps) is what the process uses now plus
// `headroom`. A reader that allocates what a header claims before checking it fails there
// with std::bad_alloc instead of taking the machine's memory. Under AddressSanitizer (whose
// allocator aborts at the limit) the body runs uncapped.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstddef>
#include <fstream>
#include <functional>
#include <new>
#include <string>

namespace probeless::testing {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kMemoryCapWorks = false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kMemoryCapWorks = false;
#else
inline constexpr bool kMemoryCapWorks = true;
#endif
#else
inline constexpr bool kMemoryCapWorks = true;
#endif

// "what()" of the exception `body` threw, "bad_alloc" when it ran out of memory, "" when it
// returned, "crashed" when the child died.
inline std::string what_with_memory_cap(std::size_t headroom, const std::function<void()>& body) {
  auto run = [&]() -> std::string {
    try {
      body();
      return "";
    } catch (const std::bad_alloc&) {
      return "bad_alloc";
    } catch (const std::exception& e) {
      return e.what();
    }
  };
  if (!kMemoryCapWorks) return run();
  int fds[2];
  if (pipe(fds) != 0) return "pipe failed";
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    std::size_t data_kb = 0;
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
      if (line.rfind("VmData:", 0) == 0) data_kb = std::stoul(line.substr(7));
    const rlim_t cap = static_cast<rlim_t>(data_kb) * 1024 + headroom;
    const rlimit limit{cap, cap};
    setrlimit(RLIMIT_DATA, &limit);
    const std::string what = run();
    (void)!write(fds[1], what.data(), what.size());
    _exit(0);
  }
  close(fds[1]);
  std::string out;
  char buf[512];
  for (ssize_t n; (n = read(fds[0], buf, sizeof buf)) > 0;)
    out.append(buf, static_cast<std::size_t>(n));
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? out : "crashed";
}

}  // namespace probeless::testing
