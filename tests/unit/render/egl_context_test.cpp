// EglContext's process-level effects: the GL driver it loads outlives the last display.
#include "app/render/egl_context.hpp"

#include <gtest/gtest.h>
#include <link.h>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace probeless::render {
namespace {

// The Mesa driver objects in the process, by path (the names egl_context.cpp pins).
std::vector<std::string> loaded_mesa_drivers() {
  std::vector<std::string> found;
  ::dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* data) {
        const std::string_view path = info->dlpi_name != nullptr ? info->dlpi_name : "";
        const std::string_view file = path.substr(path.rfind('/') + 1);
        if (file.ends_with("_dri.so") || file.starts_with("libgallium"))
          static_cast<std::vector<std::string>*>(data)->emplace_back(path);
        return 0;
      },
      &found);
  return found;
}

// Mesa keeps process-lifetime state in the driver's globals; had the last eglTerminate()
// unloaded it, that state would be stranded (LeakSanitizer's "<unknown module>" reports) and
// the next context would load and strand another copy. ctest runs each test in its own
// process, so this context is the only one and its destruction terminates the display.
TEST(EglContext, GlDriverStaysLoadedAfterTheLastContextIsGone) {
  std::vector<std::string> while_open;
  {
    std::optional<EglContext> context;
    try {
      context.emplace();
    } catch (const EglError& e) {
      GTEST_SKIP() << "no headless EGL/GLES 3 context: " << e.what();
    }
    while_open = loaded_mesa_drivers();
  }
  if (while_open.empty()) GTEST_SKIP() << "the EGL stack loaded no Mesa driver";
  EXPECT_EQ(loaded_mesa_drivers(), while_open);
}

}  // namespace
}  // namespace probeless::render
