#include "oni_fixture.hpp"

#include <OpenNI.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <thread>
#include <vector>

#include "drivers/openni2/openni2_runtime.hpp"

using probeless::openni2::openni_error_text;
using probeless::openni2::OpenniRuntime;

namespace probeless::testing {
namespace {

// An .oni record header (OpenNI 1.x/2.x file format, little-endian, packed): magic "NIR\0",
// type, node id, size of header plus fields, payload size, undo position.
constexpr std::size_t kFileHeader = 24;
constexpr std::size_t kRecordHeader = 28;
constexpr std::uint32_t kIntProperty = 3, kGeneralProperty = 6, kEnd = 0x0b;

std::uint32_t u32(const std::vector<char>& d, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, d.data() + at, 4);
  return v;
}

template <typename T>
void put(std::vector<char>& out, T v) {
  const char* p = reinterpret_cast<const char*>(&v);
  out.insert(out.end(), p, p + sizeof v);
}

}  // namespace

int add_cropping_records(const std::filesystem::path& path) {
  std::vector<char> d(std::filesystem::file_size(path));
  std::ifstream(path, std::ios::binary).read(d.data(), static_cast<std::streamsize>(d.size()));
  int rewritten = 0;
  std::size_t pos = kFileHeader;
  while (pos + kRecordHeader <= d.size() && std::memcmp(d.data() + pos, "NIR", 4) == 0) {
    const std::uint32_t type = u32(d, pos + 4), node = u32(d, pos + 8);
    const std::size_t size = std::size_t{u32(d, pos + 12)} + u32(d, pos + 16);
    if (type == kEnd || size < kRecordHeader) break;
    const std::uint32_t name_len = u32(d, pos + kRecordHeader);
    if (type == kIntProperty && name_len == 15 &&
        std::memcmp(d.data() + pos + kRecordHeader + 4, "xnIsGenerating", 15) == 0) {
      std::vector<char> rec;
      rec.insert(rec.end(), {'N', 'I', 'R', '\0'});
      put<std::uint32_t>(rec, kGeneralProperty);
      put<std::uint32_t>(rec, node);
      put<std::uint32_t>(rec, 59);  // header 28 + name 4+11 + size 4 + XnCropping 12
      put<std::uint32_t>(rec, 0);
      put<std::uint64_t>(rec, 0);  // no earlier record of this property
      put<std::uint32_t>(rec, 11);
      rec.insert(rec.end(), {'x', 'n', 'C', 'r', 'o', 'p', 'p', 'i', 'n', 'g', '\0'});
      put<std::uint32_t>(rec, 12);
      put<std::int32_t>(rec, 0);  // XnCropping: bEnabled = FALSE, offsets and size unused
      for (int i = 0; i < 4; ++i) put<std::uint16_t>(rec, 0);
      if (rec.size() == size) {
        std::memcpy(d.data() + pos, rec.data(), rec.size());
        ++rewritten;
      }
    }
    pos += size;
  }
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(d.data(), static_cast<std::streamsize>(d.size()));
  return rewritten;
}

std::string record_dummy_oni(const std::filesystem::path& path, int frames) {
  const auto runtime = OpenniRuntime::acquire();
  openni::Device device;
  if (device.open("Dummy") != openni::STATUS_OK)
    return "OpenNI2's Dummy device does not open: " + openni_error_text();
  openni::VideoStream colour, depth;
  if (colour.create(device, openni::SENSOR_COLOR) != openni::STATUS_OK ||
      depth.create(device, openni::SENSOR_DEPTH) != openni::STATUS_OK)
    return "the Dummy device has no colour/depth stream: " + openni_error_text();
  std::string failure;
  {
    openni::Recorder recorder;
    if (recorder.create(path.c_str()) != openni::STATUS_OK ||
        recorder.attach(colour) != openni::STATUS_OK || recorder.attach(depth) != openni::STATUS_OK)
      return "openni::Recorder cannot record to " + path.string() + ": " + openni_error_text();
    colour.start();
    depth.start();
    recorder.start();
    int seen = 0;
    openni::VideoStream* streams[] = {&colour, &depth};
    while (seen < 2 * frames) {
      int ready = -1;
      if (openni::OpenNI::waitForAnyStream(streams, 2, &ready, 2000) != openni::STATUS_OK) {
        failure = "the Dummy device sent no frames: " + openni_error_text();
        break;
      }
      openni::VideoFrameRef frame;
      streams[ready]->readFrame(&frame);
      ++seen;
    }
    recorder.stop();
  }  // ~Recorder finishes the file
  colour.stop();
  depth.stop();
  // The Dummy driver's stream threads outlive stop() by up to one 33 ms period.
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  colour.destroy();
  depth.destroy();
  device.close();
  if (!failure.empty()) return failure;
  if (add_cropping_records(path) != 2) return "the recording's layout is not the one expected";
  return {};
}

}  // namespace probeless::testing
