// keep_loaded_until_exit: a marked library survives its host's dlclose, an unmarked one does
// not (the control that shows the first assertion can fail). Uses OpenNI2's file-playback
// driver as the plug-in: a real dlopen-able object that nothing in this test binary links.
#include "drivers/platform/resident_libraries.hpp"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace probeless::platform {
namespace {

bool is_loaded(const std::string& path) {
  void* handle = ::dlopen(path.c_str(), RTLD_LAZY | RTLD_NOLOAD);
  if (handle == nullptr) return false;
  ::dlclose(handle);
  return true;
}

std::string openni_driver(const char* name) {
  for (const char* dir : {"/usr/lib/x86_64-linux-gnu", "/usr/lib/aarch64-linux-gnu"}) {
    const std::string path = std::string(dir) + "/OpenNI2/Drivers/" + name;
    if (std::filesystem::exists(path)) return path;
  }
  return {};
}

TEST(ResidentLibraries, FileNameIsWhatFollowsTheLastSlash) {
  EXPECT_EQ(file_name("/usr/lib/x/libfoo_dri.so"), "libfoo_dri.so");
  EXPECT_EQ(file_name("libbar.so"), "libbar.so");
  EXPECT_EQ(file_name("/dir/"), "");
}

TEST(ResidentLibraries, MarkedLibraryOutlivesTheLastDlcloseUnmarkedDoesNot) {
  const std::string marked = openni_driver("libOniFile.so");
  const std::string unmarked = openni_driver("libDummyDevice.so");
  if (marked.empty() || unmarked.empty())
    GTEST_SKIP() << "OpenNI2's drivers (libopenni2-0) are not installed";
  if (is_loaded(marked) || is_loaded(unmarked))
    GTEST_SKIP() << "an OpenNI2 driver is already loaded in this process";

  void* a = ::dlopen(marked.c_str(), RTLD_LAZY | RTLD_LOCAL);
  void* b = ::dlopen(unmarked.c_str(), RTLD_LAZY | RTLD_LOCAL);
  ASSERT_NE(a, nullptr) << ::dlerror();
  ASSERT_NE(b, nullptr) << ::dlerror();

  const int count = keep_loaded_until_exit([&](std::string_view path) { return path == marked; });
  EXPECT_EQ(count, 1);

  ::dlclose(a);
  ::dlclose(b);
  EXPECT_TRUE(is_loaded(marked));
  EXPECT_FALSE(is_loaded(unmarked));
}

TEST(ResidentLibraries, MarksNothingThatIsNotLoaded) {
  EXPECT_EQ(keep_loaded_until_exit([](std::string_view) { return false; }), 0);
  EXPECT_EQ(keep_loaded_until_exit(
                [](std::string_view path) { return file_name(path) == "libnot-there.so"; }),
            0);
}

}  // namespace
}  // namespace probeless::platform
