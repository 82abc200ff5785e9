// The owned descriptor under drivers/v4l2 and app/outputs/display: closes exactly once, and
// release() hands the descriptor over without closing it.
#include "base/unique_fd.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <utility>

namespace probeless {
namespace {

bool is_open(int fd) {
  return ::fcntl(fd, F_GETFD) != -1;
}

int open_null() {
  const int fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  EXPECT_GE(fd, 0);
  return fd;
}

TEST(UniqueFd, ClosesOnDestruction) {
  const int raw = open_null();
  {
    UniqueFd fd(raw);
    EXPECT_TRUE(fd);
    EXPECT_EQ(fd.get(), raw);
    EXPECT_TRUE(is_open(raw));
  }
  EXPECT_FALSE(is_open(raw));
  EXPECT_FALSE(UniqueFd());
  EXPECT_EQ(UniqueFd().get(), -1);
}

TEST(UniqueFd, ReleaseHandsOverWithoutClosing) {
  const int raw = open_null();
  int released = -1;
  {
    UniqueFd fd(raw);
    released = fd.release();
    EXPECT_FALSE(fd);
    EXPECT_EQ(fd.get(), -1);
  }
  EXPECT_EQ(released, raw);
  EXPECT_TRUE(is_open(raw));
  ::close(raw);
}

TEST(UniqueFd, ResetClosesTheOldAndTakesTheNew) {
  const int first = open_null();
  const int second = open_null();
  UniqueFd fd(first);
  fd.reset(second);
  EXPECT_FALSE(is_open(first));
  EXPECT_EQ(fd.get(), second);
  fd.reset(second);  // the same descriptor again: kept open, not closed under us
  EXPECT_TRUE(is_open(second));
  fd.reset();
  EXPECT_FALSE(fd);
  EXPECT_FALSE(is_open(second));
}

TEST(UniqueFd, MoveTransfersOwnership) {
  const int a = open_null();
  const int b = open_null();
  UniqueFd from(a);
  UniqueFd to(std::move(from));
  EXPECT_FALSE(from);  // NOLINT(bugprone-use-after-move): moved-from is defined to be empty
  EXPECT_EQ(to.get(), a);

  UniqueFd other(b);
  other = std::move(to);  // closes b, takes a
  EXPECT_FALSE(is_open(b));
  EXPECT_TRUE(is_open(a));
  EXPECT_EQ(other.get(), a);
  EXPECT_FALSE(to);  // NOLINT(bugprone-use-after-move)

  auto& self = other;
  other = std::move(self);  // self-move keeps it
  EXPECT_EQ(other.get(), a);
  EXPECT_TRUE(is_open(a));
}

}  // namespace
}  // namespace probeless
