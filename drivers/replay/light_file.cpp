#include "drivers/replay/light_file.hpp"

#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include "drivers/io/png.hpp"

namespace probeless::replay {
namespace {

constexpr int kMaxFaceSize = 4096;

std::uint32_t byte_swap(std::uint32_t v) {
  return (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
}

}  // namespace

void write_light_cubemap(const std::filesystem::path& path, const Cubemap& cubemap) {
  const int n = cubemap.face_size;
  if (n <= 0) throw ImageFileError(path, "cannot write an empty cubemap");
  for (const auto& face : cubemap.faces) {
    if (face.width() != n || face.height() != n) {
      throw ImageFileError(path,
                           "cubemap faces are not " + std::to_string(n) + "x" + std::to_string(n));
    }
  }
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw ImageFileError(tmp, "cannot create");
    // Negative scale: little-endian samples. PFM rows run bottom to top.
    out << "PF\n" << n << ' ' << 6 * n << "\n-1.0\n";
    std::vector<std::uint32_t> row(static_cast<std::size_t>(n) * 3);
    for (int face = 5; face >= 0; --face) {
      for (int y = n - 1; y >= 0; --y) {
        std::memcpy(row.data(), cubemap.faces[static_cast<std::size_t>(face)].row(y),
                    row.size() * sizeof(float));
        if constexpr (std::endian::native == std::endian::big) {
          for (auto& v : row) v = byte_swap(v);
        }
        out.write(reinterpret_cast<const char*>(row.data()),
                  static_cast<std::streamsize>(row.size() * sizeof(float)));
      }
    }
    out.close();
    if (!out) {
      std::filesystem::remove(tmp);
      throw ImageFileError(tmp, "cannot write");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw ImageFileError(path, "cannot rename " + tmp.string() + ": " + ec.message());
}

Cubemap read_light_cubemap(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ImageFileError(path, "cannot open");
  std::string magic;
  long long width = 0, height = 0;
  double scale = 0;
  in >> magic >> width >> height >> scale;
  if (!in || magic != "PF") throw ImageFileError(path, "not a colour PFM file (bad header)");
  if (in.get() != '\n') throw ImageFileError(path, "bad PFM header (no newline after scale)");
  if (width <= 0 || width > kMaxFaceSize || height != 6 * width || scale == 0) {
    throw ImageFileError(path, "not a light cubemap: " + std::to_string(width) + "x" +
                                   std::to_string(height) +
                                   " (expected N x 6N, N <= " + std::to_string(kMaxFaceSize) + ")");
  }
  const bool file_little = scale < 0;
  const bool swap = file_little != (std::endian::native == std::endian::little);
  const int n = static_cast<int>(width);
  // The faces (up to 1.2 GB at the largest N) are allocated only once the file is seen to
  // hold their data: a 20-byte header claiming N = 4096 took 1.2 GB before "truncated"
  // (found by tests/fuzz light_cubemap).
  const std::int64_t bytes = std::int64_t{6} * n * n * 3 * static_cast<std::int64_t>(sizeof(float));
  const std::streamoff data_start = in.tellg();
  if (data_start >= 0 && in.seekg(0, std::ios::end)) {
    const std::streamoff left = in.tellg() - data_start;
    in.seekg(data_start);
    if (left < bytes)
      throw ImageFileError(path, "truncated PFM (" + std::to_string(left) + " of " +
                                     std::to_string(bytes) + " bytes of image data)");
  }
  in.clear();
  Cubemap cubemap(n);
  std::vector<std::uint32_t> row(static_cast<std::size_t>(n) * 3);
  for (int face = 5; face >= 0; --face) {
    for (int y = n - 1; y >= 0; --y) {
      in.read(reinterpret_cast<char*>(row.data()),
              static_cast<std::streamsize>(row.size() * sizeof(float)));
      if (!in) throw ImageFileError(path, "truncated PFM (image data ends early)");
      if (swap) {
        for (auto& v : row) v = byte_swap(v);
      }
      std::memcpy(cubemap.faces[static_cast<std::size_t>(face)].row(y), row.data(),
                  row.size() * sizeof(float));
    }
  }
  if (in.peek() != std::char_traits<char>::eof()) {
    throw ImageFileError(path, "trailing bytes after the PFM image data");
  }
  return cubemap;
}

}  // namespace probeless::replay
