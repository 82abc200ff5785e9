#pragma once
// USB presence of the RGB-D sensor (docs/drivers.md "USB hotplug and reset"): a watcher that
// calls back when a device of a configured vendor arrives or leaves (libusb hotplug, one
// event thread), the devices present now, and a port reset for a sensor that has stopped
// streaming. The OpenNI2 source uses the watcher to reopen at once on replug rather than
// at its next periodic look.
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "drivers/usb/usb_handles.hpp"

namespace probeless::usb {

// PrimeSense / Asus Xtion, Microsoft Kinect, Orbbec: the vendors systemd/60-probeless.rules
// gives the service access to (a test keeps the two lists equal).
std::vector<std::uint16_t> default_sensor_vendors();

// "1d27:045e:2bc5" -> {0x1d27, 0x045e, 0x2bc5}. Throws std::invalid_argument.
std::vector<std::uint16_t> parse_vendor_list(std::string_view text);

struct UsbDeviceId {
  std::uint16_t vendor = 0, product = 0;
  int bus = 0, address = 0;
};
std::string describe(const UsbDeviceId& id);  // "1d27:0601 on bus 3 address 2"

enum class HotplugEvent { Arrived, Left };

class UsbHotplugWatcher {
 public:
  using Callback = std::function<void(HotplugEvent, const UsbDeviceId&)>;
  // Starts watching. `callback` runs on the watcher's event thread: keep it short (set a
  // flag). Throws UsbError when libusb cannot start or this platform has no hotplug support.
  UsbHotplugWatcher(std::vector<std::uint16_t> vendors, Callback callback);
  ~UsbHotplugWatcher();
  UsbHotplugWatcher(const UsbHotplugWatcher&) = delete;
  UsbHotplugWatcher& operator=(const UsbHotplugWatcher&) = delete;

  const std::vector<std::uint16_t>& vendors() const { return vendors_; }

 private:
  static int LIBUSB_CALL on_event(libusb_context*, libusb_device*, libusb_hotplug_event, void*);
  void run();

  std::vector<std::uint16_t> vendors_;
  Callback callback_;
  UniqueContext context_;
  std::vector<libusb_hotplug_callback_handle> registrations_;
  std::atomic<bool> stop_{false};
  std::thread thread_;  // last: starts once everything above is ready
};

// The devices present now whose vendor is in `vendors` (all devices when it is empty).
// Throws UsbError when libusb cannot start.
std::vector<UsbDeviceId> list_usb_devices(const std::vector<std::uint16_t>& vendors);

// Resets the first device with this vendor and product (libusb_reset_device): the hub port
// re-enumerates it, as an unplug and replug would. Throws UsbError naming the device when
// none is present or the reset fails.
void usb_reset(std::uint16_t vendor, std::uint16_t product);

}  // namespace probeless::usb
