#include "drivers/usb/usb_hotplug.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <stdexcept>

namespace probeless::usb {

std::vector<std::uint16_t> default_sensor_vendors() {
  return {0x1d27, 0x045e, 0x2bc5};
}

std::vector<std::uint16_t> parse_vendor_list(std::string_view text) {
  std::vector<std::uint16_t> out;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t end = std::min(text.find(':', pos), text.size());
    const std::string_view item = text.substr(pos, end - pos);
    unsigned value = 0;
    const auto [p, ec] = std::from_chars(item.data(), item.data() + item.size(), value, 16);
    if (item.empty() || item.size() > 4 || ec != std::errc() || p != item.data() + item.size()) {
      throw std::invalid_argument("USB vendor list '" + std::string(text) +
                                  "': expected hexadecimal IDs joined by ':' (1d27:045e:2bc5)");
    }
    out.push_back(static_cast<std::uint16_t>(value));
    pos = end + 1;
  }
  return out;
}

std::string describe(const UsbDeviceId& id) {
  char text[64];
  std::snprintf(text, sizeof text, "%04x:%04x on bus %d address %d", id.vendor, id.product, id.bus,
                id.address);
  return text;
}

namespace {

UsbDeviceId identify(libusb_device* device) {
  libusb_device_descriptor descriptor{};
  UsbDeviceId id;
  // Cached by libusb since 1.0.16: no I/O, works in the hotplug callback too.
  if (libusb_get_device_descriptor(device, &descriptor) == 0) {
    id.vendor = descriptor.idVendor;
    id.product = descriptor.idProduct;
  }
  id.bus = libusb_get_bus_number(device);
  id.address = libusb_get_device_address(device);
  return id;
}

}  // namespace

UsbHotplugWatcher::UsbHotplugWatcher(std::vector<std::uint16_t> vendors, Callback callback)
    : vendors_(std::move(vendors)), callback_(std::move(callback)), context_(make_context()) {
  if (!libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG))
    throw UsbError("this libusb has no hotplug support");
  try {
    for (const std::uint16_t vendor : vendors_) {
      libusb_hotplug_callback_handle handle{};
      const int rc = libusb_hotplug_register_callback(
          context_.get(),
          static_cast<libusb_hotplug_event>(LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED |
                                            LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT),
          LIBUSB_HOTPLUG_NO_FLAGS, vendor, LIBUSB_HOTPLUG_MATCH_ANY, LIBUSB_HOTPLUG_MATCH_ANY,
          &UsbHotplugWatcher::on_event, this, &handle);
      if (rc != LIBUSB_SUCCESS) {
        char hex[8];
        std::snprintf(hex, sizeof hex, "%04x", vendor);
        throw UsbError(std::string("cannot watch USB vendor ") + hex + ": " + usb_error_text(rc));
      }
      registrations_.push_back(handle);
    }
  } catch (...) {
    for (auto handle : registrations_) libusb_hotplug_deregister_callback(context_.get(), handle);
    throw;
  }
  thread_ = std::thread([this] { run(); });
}

UsbHotplugWatcher::~UsbHotplugWatcher() {
  stop_ = true;
  // Deregistering wakes the event thread too; the interrupt covers a watcher of no vendors.
  for (auto handle : registrations_) libusb_hotplug_deregister_callback(context_.get(), handle);
  libusb_interrupt_event_handler(context_.get());
  thread_.join();
}

void UsbHotplugWatcher::run() {
  while (!stop_) {
    timeval tick{0, 250'000};  // bounds how long a missed interrupt could delay shutdown
    libusb_handle_events_timeout_completed(context_.get(), &tick, nullptr);
  }
}

int LIBUSB_CALL UsbHotplugWatcher::on_event(libusb_context*, libusb_device* device,
                                            libusb_hotplug_event event, void* self) {
  auto* watcher = static_cast<UsbHotplugWatcher*>(self);
  if (!watcher->stop_) {
    watcher->callback_(
        event == LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED ? HotplugEvent::Arrived : HotplugEvent::Left,
        identify(device));
  }
  return 0;  // stay registered
}

std::vector<UsbDeviceId> list_usb_devices(const std::vector<std::uint16_t>& vendors) {
  const UniqueContext context = make_context();
  const DeviceList list(context.get());
  std::vector<UsbDeviceId> out;
  for (libusb_device* device : list) {
    const UsbDeviceId id = identify(device);
    if (vendors.empty() || std::find(vendors.begin(), vendors.end(), id.vendor) != vendors.end())
      out.push_back(id);
  }
  return out;
}

void usb_reset(std::uint16_t vendor, std::uint16_t product) {
  const UniqueContext context = make_context();
  const DeviceList list(context.get());
  char name[16];
  std::snprintf(name, sizeof name, "%04x:%04x", vendor, product);
  for (libusb_device* device : list) {
    const UsbDeviceId id = identify(device);
    if (id.vendor != vendor || id.product != product) continue;
    libusb_device_handle* raw = nullptr;
    if (const int rc = libusb_open(device, &raw); rc != 0)
      throw UsbError(std::string("cannot open USB device ") + describe(id) + ": " +
                     usb_error_text(rc));
    const UniqueDeviceHandle handle(raw);
    // NOT_FOUND after a reset means the device re-enumerated as a new one: that is success.
    const int rc = libusb_reset_device(handle.get());
    if (rc != 0 && rc != LIBUSB_ERROR_NOT_FOUND)
      throw UsbError(std::string("USB reset of ") + describe(id) +
                     " failed: " + usb_error_text(rc));
    return;
  }
  throw UsbError(std::string("no USB device ") + name + " to reset");
}

}  // namespace probeless::usb
