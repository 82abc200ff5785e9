// keep_loaded_until_exit: a marked library survives its last dlclose, an unmarked one does not
// (the control that shows the first assertion can fail). The plug-ins are libattr and libacl:
// Essential in Debian, linked by nothing here, and plain C that allocates nothing when loaded
// (an OpenNI driver's static constructors do, and the unmarked one's would leak under ASan).
#include "drivers/platform/resident_libraries.hpp"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <string>

namespace probeless::platform {
namespace {

bool is_loaded(const char* soname) {
  void* handle = ::dlopen(soname, RTLD_LAZY | RTLD_NOLOAD);
  if (handle == nullptr) return false;
  ::dlclose(handle);
  return true;
}

TEST(ResidentLibraries, FileNameIsWhatFollowsTheLastSlash) {
  EXPECT_EQ(file_name("/usr/lib/x/libfoo_dri.so"), "libfoo_dri.so");
  EXPECT_EQ(file_name("libbar.so"), "libbar.so");
  EXPECT_EQ(file_name("/dir/"), "");
}

TEST(ResidentLibraries, MarkedLibraryOutlivesTheLastDlcloseUnmarkedDoesNot) {
  constexpr const char* kMarked = "libattr.so.1";
  constexpr const char* kUnmarked = "libacl.so.1";
  if (is_loaded(kMarked) || is_loaded(kUnmarked))
    GTEST_SKIP() << "libattr or libacl is already loaded in this process";

  void* a = ::dlopen(kMarked, RTLD_LAZY | RTLD_LOCAL);
  void* b = ::dlopen(kUnmarked, RTLD_LAZY | RTLD_LOCAL);
  if (a == nullptr || b == nullptr) GTEST_SKIP() << "libattr1/libacl1 missing: " << ::dlerror();

  const int count =
      keep_loaded_until_exit([&](std::string_view path) { return file_name(path) == kMarked; });
  EXPECT_EQ(count, 1);

  ::dlclose(a);
  ::dlclose(b);
  EXPECT_TRUE(is_loaded(kMarked));
  EXPECT_FALSE(is_loaded(kUnmarked));
}

TEST(ResidentLibraries, MarksNothingThatIsNotLoaded) {
  EXPECT_EQ(keep_loaded_until_exit([](std::string_view) { return false; }), 0);
  EXPECT_EQ(keep_loaded_until_exit(
                [](std::string_view path) { return file_name(path) == "libnot-there.so"; }),
            0);
}

}  // namespace
}  // namespace probeless::platform
