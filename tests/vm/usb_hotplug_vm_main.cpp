// Inside the VM of check_usb_hotplug.sh: watches USB vendor 0627 (QEMU's emulated devices)
// with the real UsbHotplugWatcher while the host hot-adds and removes a usb-kbd through the
// QEMU monitor. Prints marker lines the host script waits for; exit 0 when both the arrival
// and the departure were seen and an OpenNI2 source watching the same vendor looked for its
// device at once on the arrival (not at its next periodic look, a minute away), 1 otherwise.
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <thread>

#include "drivers/openni2/openni2_rgbd_source.hpp"
#include "drivers/usb/usb_hotplug.hpp"

using namespace probeless::usb;
using namespace std::chrono_literals;

int main() {
  std::mutex mutex;
  std::condition_variable changed;
  int arrived = 0, left = 0;
  std::unique_ptr<UsbHotplugWatcher> watcher;
  try {
    watcher = std::make_unique<UsbHotplugWatcher>(
        std::vector<std::uint16_t>{0x0627}, [&](HotplugEvent event, const UsbDeviceId& id) {
          std::lock_guard lock(mutex);
          ++(event == HotplugEvent::Arrived ? arrived : left);
          std::printf("PROBELESS_USB_%s %s\n", event == HotplugEvent::Arrived ? "ARRIVED" : "LEFT",
                      describe(id).c_str());
          std::fflush(stdout);
          changed.notify_all();
        });
  } catch (const UsbError& e) {
    std::printf("FAIL: %s\n", e.what());
    return 1;
  }
  // A source whose device never comes: only a USB arrival ends its minute-long wait early.
  probeless::openni2::Openni2RgbdSource source(probeless::openni2::parse_openni2_options(
      "probeless-absent?reopen_ms=60000&usb_vendors=0627"));
  if (!source.watching_usb()) {
    std::printf("FAIL: the OpenNI2 source has no USB watcher\n");
    return 1;
  }
  probeless::RgbdFrame frame;
  source.read(frame, 10ms);  // the first look happened in the constructor; now it waits
  std::chrono::steady_clock::time_point looked;
  std::thread reader([&] {
    source.read(frame, 60s);
    looked = std::chrono::steady_clock::now();
  });
  std::printf("PROBELESS_USB_READY\n");
  std::fflush(stdout);
  std::unique_lock lock(mutex);
  const auto t0 = std::chrono::steady_clock::now();
  if (!changed.wait_for(lock, 120s, [&] { return arrived > 0; })) {
    std::printf("FAIL: no arrival of a 0627 device within 120 s\n");
    return 1;
  }
  const auto t1 = std::chrono::steady_clock::now();
  lock.unlock();
  reader.join();
  const double source_s = std::chrono::duration<double>(looked - t1).count();
  std::printf("PROBELESS_USB_SOURCE looked again %.2f s after the arrival\n", source_s);
  if (source_s < -0.5) {
    std::printf("FAIL: the OpenNI2 source stopped waiting before any arrival\n");
    return 1;
  }
  if (source_s > 2.0) {
    std::printf("FAIL: the OpenNI2 source did not look again on the USB arrival\n");
    return 1;
  }
  lock.lock();
  if (!changed.wait_for(lock, 120s, [&] { return left > 0; })) {
    std::printf("FAIL: the 0627 device did not leave within 120 s\n");
    return 1;
  }
  std::printf("PASS: arrival %.2f s after ready, departure %.2f s after arrival\n",
              std::chrono::duration<double>(t1 - t0).count(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count());
  return 0;
}
