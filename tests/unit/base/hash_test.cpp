// fnv1a64 names cache files and checksums them (kernels/runtime/program_binary_cache.cpp,
// app/render/prt/prt_cache.cpp): a change to its output silently orphans every cache on
// disk. The values below were printed by the implementation in use before it moved to base/.
#include "base/hash.hpp"

#include <gtest/gtest.h>

#include <string>

namespace probeless {
namespace {

TEST(Fnv1a64, KnownValues) {
  EXPECT_EQ(fnv1a64(""), 0xcbf29ce484222325ULL);  // the offset basis
  EXPECT_EQ(fnv1a64("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(fnv1a64("foobar"), 0x85944171f73967e8ULL);
  EXPECT_EQ(fnv1a64("probeless"), 0x6a422b806c303fb4ULL);
  // Bytes above 0x7f are hashed as unsigned (a signed char would sign-extend).
  EXPECT_EQ(fnv1a64(std::string("\0\xff", 2)), 0x0831c907b4ea2b60ULL);
  EXPECT_EQ(fnv1a64("abc", 0), 0x47c3ec01db8517e0ULL);
}

TEST(Fnv1a64, SeedChainsCalls) {
  EXPECT_EQ(fnv1a64("bar", fnv1a64("foo")), fnv1a64("foobar"));
  EXPECT_NE(fnv1a64("bar"), fnv1a64("foobar"));
}

}  // namespace
}  // namespace probeless
