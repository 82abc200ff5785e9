// The device methods by config name (kernels/occlusion/method_registry.hpp): what the service's
// [occlusion] method chooses from.
#include "kernels/occlusion/method_registry.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace probeless::occlusion {
namespace {

TEST(MethodRegistry, MakesEveryListedMethodUnderItsName) {
  ComputeContext ctx;
  const std::vector<std::string> expected = {"cvf",     "cvf_thesis",  "direct1",
                                             "direct2", "guided",      "bilateral",
                                             "crabb",   "arcore_soft", "meta_soft"};
  EXPECT_EQ(method_names(), expected);
  for (const std::string& name : method_names()) {
    const auto method = make_method(ctx, name);
    ASSERT_NE(method, nullptr);
    EXPECT_EQ(method->name(), name);
  }
}

// "cvf_local" was the evaluation-only name of the method that ships as "cvf" now.
TEST(MethodRegistry, UnknownNamesThrowListingTheKnownOnes) {
  ComputeContext ctx;
  try {
    (void)make_method(ctx, "cvf_local");
    FAIL() << "cvf_local is not a method name";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("known: cvf cvf_thesis direct1"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW((void)make_method(ctx, "nope"), std::invalid_argument);
}

}  // namespace
}  // namespace probeless::occlusion
