// `probeless devices` and the ICD loader with no driver at all: run in a child process,
// because the loader reads its vendor list once per process (OCL_ICD_VENDORS points it at
// an empty place, as on a board whose OpenCL driver is not installed).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace {

struct Result {
  int status = -1;
  std::string output;
};

Result run(const std::string& env, const std::string& args) {
  const char* bin = std::getenv("PROBELESS_BINARY");
  if (!bin) return {};
  const std::string cmd = env + " '" + bin + "' " + args + " 2>&1";
  Result r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), pipe)) r.output += buf.data();
  const int status = ::pclose(pipe);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

TEST(DevicesCommand, ListsAndMarksTheSelectedDevice) {
  if (!std::getenv("PROBELESS_BINARY")) GTEST_SKIP() << "PROBELESS_BINARY not set (run via ctest)";
  const auto r = run("env -u PROBELESS_CL_PLATFORM -u PROBELESS_CL_DEVICE", "devices");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("OpenCL\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("platform 0:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("* device 0.0"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("compute units"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("selected: device"), std::string::npos) << r.output;
}

TEST(DevicesCommand, SaysWhenNothingMatches) {
  if (!std::getenv("PROBELESS_BINARY")) GTEST_SKIP() << "PROBELESS_BINARY not set (run via ctest)";
  const auto r = run("env PROBELESS_CL_PLATFORM=no-such-platform", "devices");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("PROBELESS_CL_PLATFORM"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("selected: none"), std::string::npos) << r.output;
}

// The GPIO section (docs/gpio.md): the chips, or why there is none, and the configured lines.
TEST(DevicesCommand, ListsGpioChipsAndTheConfiguredLines) {
  if (!std::getenv("PROBELESS_BINARY")) GTEST_SKIP() << "PROBELESS_BINARY not set (run via ctest)";
  const std::string cfg = ::testing::TempDir() + "probeless-devices-gpio.toml";
  std::FILE* f = std::fopen(cfg.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs(
      "[bracket]\ngpio_chip = \"gpiochip0\"\ngpio_line = 17\n"
      "strobe_chip = \"pinctrl-rp1\"\nstrobe_line = 27\n",
      f);
  std::fclose(f);
  const auto r = run("", "devices --config " + cfg);
  std::remove(cfg.c_str());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("\nGPIO\n"), std::string::npos) << r.output;
  const bool has_chips = std::filesystem::exists("/dev/gpiochip0");
  EXPECT_NE(r.output.find(has_chips ? "  gpiochip0" : "  no chip: no /dev/gpiochip*"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("trigger: 'gpiochip0' line 17, strobe: 'pinctrl-rp1' line 27"),
            std::string::npos)
      << r.output;
}

TEST(NoOpenClDriver, DevicesExplainsAndContextFailsClearly) {
  if (!std::getenv("PROBELESS_BINARY")) GTEST_SKIP() << "PROBELESS_BINARY not set (run via ctest)";
  const std::string no_icd = "env OCL_ICD_VENDORS=/nonexistent-probeless-vendors";
  const auto list = run(no_icd, "devices");
  EXPECT_EQ(list.status, 0) << list.output;
  EXPECT_NE(list.output.find("no platform"), std::string::npos) << list.output;

  const auto bench = run(no_icd, "bench composite --frames 1 --warmup 0");
  EXPECT_EQ(bench.status, 1) << bench.output;
  EXPECT_NE(bench.output.find("no OpenCL platform found"), std::string::npos) << bench.output;
}

}  // namespace
