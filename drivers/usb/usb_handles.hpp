#pragma once
// RAII for libusb's C handles: the context, an open device, a device list. Each releases
// exactly what it holds; none copies.
#include <libusb.h>

#include <memory>
#include <stdexcept>
#include <string>

namespace probeless::usb {

class UsbError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "LIBUSB_ERROR_NO_DEVICE (No such device (it may have been disconnected))"
std::string usb_error_text(int code);

struct ContextDeleter {
  void operator()(libusb_context* c) const { libusb_exit(c); }
};
using UniqueContext = std::unique_ptr<libusb_context, ContextDeleter>;

struct HandleDeleter {
  void operator()(libusb_device_handle* h) const { libusb_close(h); }
};
using UniqueDeviceHandle = std::unique_ptr<libusb_device_handle, HandleDeleter>;

// libusb_get_device_list's array, freed with one reference dropped per device.
class DeviceList {
 public:
  explicit DeviceList(libusb_context* context);
  ~DeviceList() { libusb_free_device_list(devices_, 1); }
  DeviceList(const DeviceList&) = delete;
  DeviceList& operator=(const DeviceList&) = delete;
  libusb_device* const* begin() const { return devices_; }
  libusb_device* const* end() const { return devices_ + count_; }

 private:
  libusb_device** devices_ = nullptr;
  ssize_t count_ = 0;
};

// libusb_init, throwing UsbError with libusb's reason.
UniqueContext make_context();

}  // namespace probeless::usb
