// openni2_record_dummy PATH FRAMES: records the Dummy device into PATH (oni_fixture.hpp).
// Exit 0 on success, 1 with the reason on stdout.
#include <cstdio>
#include <cstdlib>

#include "oni_fixture.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::printf("usage: %s PATH FRAMES\n", argv[0]);
    return 2;
  }
  const std::string why = probeless::testing::record_dummy_oni(argv[1], std::atoi(argv[2]));
  if (!why.empty()) std::printf("%s\n", why.c_str());
  return why.empty() ? 0 : 1;
}
