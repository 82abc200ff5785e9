// The libusb parts that need no USB device: vendor lists and their agreement with the udev
// rules, the hotplug watcher's lifecycle, and the errors of listing and reset. Devices
// arriving and leaving are tested in a VM with QEMU's emulated USB (tests/vm/check_usb_hotplug.sh).
#include "drivers/usb/usb_hotplug.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace probeless::usb {
namespace {

using namespace std::chrono_literals;

TEST(UsbVendors, ParseHexListsAndRejectJunk) {
  EXPECT_EQ(parse_vendor_list("1d27"), (std::vector<std::uint16_t>{0x1d27}));
  EXPECT_EQ(parse_vendor_list("1d27:045E:2bc5"),
            (std::vector<std::uint16_t>{0x1d27, 0x045e, 0x2bc5}));
  for (const char* bad : {"", ":", "1d27:", "xyz", "12345", "1d27,045e", "0x1d27"})
    EXPECT_THROW(parse_vendor_list(bad), std::invalid_argument) << bad;
}

// The defaults are the vendors the packaged udev rules open to the service: a sensor the
// watcher waits for but the service may not open (or the reverse) is a silent failure.
TEST(UsbVendors, DefaultsMatchTheUdevRules) {
  const std::string rules_path = PROBELESS_TEST_SOURCE_DIR "/../../../systemd/60-probeless.rules";
  std::ifstream in(rules_path);
  ASSERT_TRUE(in) << rules_path;
  std::stringstream text;
  text << in.rdbuf();
  const std::string rules = text.str();
  std::set<std::uint16_t> in_rules;
  const std::regex vendor(R"(ATTR\{idVendor\}=="([0-9a-f]{4})\")");
  for (auto it = std::sregex_iterator(rules.begin(), rules.end(), vendor);
       it != std::sregex_iterator(); ++it)
    in_rules.insert(static_cast<std::uint16_t>(std::stoul((*it)[1], nullptr, 16)));
  const auto defaults = default_sensor_vendors();
  EXPECT_EQ(in_rules, std::set<std::uint16_t>(defaults.begin(), defaults.end()));
}

TEST(UsbDeviceId, DescribesVendorProductAndPort) {
  EXPECT_EQ(describe(UsbDeviceId{0x1d27, 0x0601, 3, 2}), "1d27:0601 on bus 3 address 2");
}

// Starting and stopping the watcher works without any device, and stopping is prompt (the
// event thread is woken, not left to time out).
TEST(UsbHotplugWatcher, StartsAndStopsPromptly) {
  int events = 0;
  std::unique_ptr<UsbHotplugWatcher> watcher;
  try {
    watcher = std::make_unique<UsbHotplugWatcher>(
        default_sensor_vendors(), [&](HotplugEvent, const UsbDeviceId&) { ++events; });
  } catch (const UsbError& e) {
    GTEST_SKIP() << "libusb cannot watch here: " << e.what();
  }
  EXPECT_EQ(watcher->vendors().size(), 3u);
  std::this_thread::sleep_for(50ms);
  const auto t0 = std::chrono::steady_clock::now();
  watcher.reset();
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 200ms);
  EXPECT_EQ(events, 0);  // no sensor came or went
}

TEST(UsbReset, AbsentDeviceIsAnErrorNamingIt) {
  try {
    usb_reset(0xdead, 0xbeef);
    FAIL() << "there is no dead:beef device";
  } catch (const UsbError& e) {
    const std::string what = e.what();
    // Either libusb could not start at all, or it looked and found nothing.
    EXPECT_TRUE(what.find("no USB device dead:beef") != std::string::npos ||
                what.find("libusb cannot start") != std::string::npos)
        << what;
  }
}

TEST(UsbList, FiltersByVendor) {
  std::vector<UsbDeviceId> all;
  try {
    all = list_usb_devices({});
  } catch (const UsbError& e) {
    GTEST_SKIP() << "libusb cannot list here: " << e.what();
  }
  const auto none = list_usb_devices({0xdead});
  EXPECT_TRUE(none.empty());
  for (const auto& id : all) {
    const auto same = list_usb_devices({id.vendor});
    EXPECT_FALSE(same.empty()) << describe(id);
  }
}

}  // namespace
}  // namespace probeless::usb
