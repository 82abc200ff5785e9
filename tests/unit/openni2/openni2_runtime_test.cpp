// OpenNI2's drivers stay loaded after the last OpenniRuntime shuts OpenNI down: OpenNI
// dlcloses them, and their process-lifetime globals would be stranded (LeakSanitizer's
// "<unknown module>" leaks; docs/sanitizers.md).
#include "drivers/openni2/openni2_runtime.hpp"

#include <dlfcn.h>
#include <gtest/gtest.h>
#include <link.h>

#include <string>
#include <string_view>
#include <vector>

namespace probeless::openni2 {
namespace {

std::vector<std::string> loaded_openni_drivers() {
  std::vector<std::string> found;
  ::dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* data) {
        const std::string_view path = info->dlpi_name != nullptr ? info->dlpi_name : "";
        if (path.find("/OpenNI2/Drivers/") != std::string_view::npos)
          static_cast<std::vector<std::string>*>(data)->emplace_back(path);
        return 0;
      },
      &found);
  return found;
}

TEST(OpenniRuntime, DriversStayLoadedAfterShutdown) {
  if (!loaded_openni_drivers().empty()) GTEST_SKIP() << "OpenNI2 drivers already loaded";
  std::vector<std::string> while_running;
  {
    std::shared_ptr<OpenniRuntime> runtime;
    try {
      runtime = OpenniRuntime::acquire();
    } catch (const OpenniError& e) {
      GTEST_SKIP() << e.what();
    }
    while_running = loaded_openni_drivers();
  }
  ASSERT_FALSE(while_running.empty()) << "OpenNI2 initialised without loading a driver";
  EXPECT_EQ(loaded_openni_drivers(), while_running);
}

}  // namespace
}  // namespace probeless::openni2
