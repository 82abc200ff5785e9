#include "support/test_data.hpp"

#include <atomic>
#include <cstdlib>
#include <unistd.h>

namespace probeless::testing {
namespace {

// Where tests find the shared data, cache their OpenCL programs and find the CLI, unless the
// environment says otherwise. Runs before main(), so before any OpenCL platform is loaded.
struct TestEnvironmentDefaults {
  TestEnvironmentDefaults() {
    ::setenv("PROBELESS_DATA", PROBELESS_TEST_DATA, 0);
    ::setenv("POCL_CACHE_DIR", PROBELESS_TEST_BUILD_DIR "/pocl-cache", 0);
    ::setenv("PROBELESS_CACHE_DIR", PROBELESS_TEST_BUILD_DIR "/test-cache", 0);
    ::setenv("PROBELESS_BINARY", PROBELESS_TEST_BINARY, 0);
  }
} const defaults;

}  // namespace

std::filesystem::path shared_data_dir() {
  const char* env = std::getenv("PROBELESS_DATA");
  std::filesystem::path dir = env && *env ? env : "";
  if (dir.empty() || !std::filesystem::exists(dir)) return {};
  return std::filesystem::canonical(dir);
}

std::filesystem::path scratch_dir() {
  static std::atomic<int> counter{0};
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "test";
  for (auto& ch : name)
    if (ch == '/') ch = '_';
  const char* base = std::getenv("PROBELESS_CACHE_DIR");
  auto dir = std::filesystem::path(base && *base ? base : "/tmp") / "scratch" /
             (name + "." + std::to_string(::getpid()) + "." + std::to_string(counter++));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace probeless::testing
