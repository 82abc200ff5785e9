#include "drivers/usb/usb_handles.hpp"

namespace probeless::usb {

std::string usb_error_text(int code) {
  return std::string(libusb_error_name(code)) + " (" + libusb_strerror(code) + ")";
}

DeviceList::DeviceList(libusb_context* context) {
  count_ = libusb_get_device_list(context, &devices_);
  if (count_ < 0) {
    const int code = static_cast<int>(count_);
    count_ = 0;
    devices_ = nullptr;
    throw UsbError("cannot list USB devices: " + usb_error_text(code));
  }
}

UniqueContext make_context() {
  libusb_context* context = nullptr;
  if (const int rc = libusb_init(&context); rc != 0)
    throw UsbError("libusb cannot start: " + usb_error_text(rc));
  return UniqueContext(context);
}

}  // namespace probeless::usb
