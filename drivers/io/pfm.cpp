#include "drivers/io/pfm.hpp"

#include <bit>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/read_limits.hpp"

namespace probeless {
namespace {

// One whitespace-delimited header token; PFM allows any whitespace between them.
std::string token(std::istream& in, const std::filesystem::path& path, const char* what) {
  std::string t;
  if (!(in >> t)) throw ImageFileError(path, std::string("truncated PFM header (no ") + what + ")");
  return t;
}

}  // namespace

ImageF read_pfm(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ImageFileError(path, "cannot open");
  const std::string magic = token(in, path, "magic");
  if (magic == "PF") throw ImageFileError(path, "colour PFM (PF) where a gray one (Pf) is needed");
  if (magic != "Pf") throw ImageFileError(path, "not a PFM file (magic '" + magic + "')");
  int w = 0, h = 0;
  double scale = 0;
  try {
    w = std::stoi(token(in, path, "width"));
    h = std::stoi(token(in, path, "height"));
    scale = std::stod(token(in, path, "scale"));
  } catch (const std::logic_error&) {
    throw ImageFileError(path, "bad PFM header (width, height or scale is not a number)");
  }
  if (!read_limits::image_size_ok(w, h))
    throw ImageFileError(path, "bad PFM size " + std::to_string(w) + "x" + std::to_string(h) +
                                   " (limits: " + std::to_string(read_limits::kMaxImageSide) +
                                   " a side, " + std::to_string(read_limits::kMaxImagePixels) +
                                   " pixels)");
  if (scale == 0) throw ImageFileError(path, "bad PFM scale 0");
  const bool little = scale < 0;
  // The data is uncompressed: the file must hold all of it before any of it is allocated
  // (a pipe, whose size is not known, is only bounded by the limits).
  const std::size_t bytes = static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4;
  if (in.get() == std::ifstream::traits_type::eof())  // the whitespace after the scale
    throw ImageFileError(path, "truncated PFM data (0 of " + std::to_string(bytes) + " bytes)");
  const std::streamoff data_start = in.tellg();
  if (data_start >= 0 && in.seekg(0, std::ios::end)) {
    const std::streamoff left = in.tellg() - data_start;
    in.seekg(data_start);
    if (left < static_cast<std::streamoff>(bytes))
      throw ImageFileError(path, "truncated PFM data (" + std::to_string(left) + " of " +
                                     std::to_string(bytes) + " bytes)");
  }
  in.clear();
  std::vector<std::uint32_t> raw(bytes / 4);
  in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(bytes));
  if (in.gcount() != static_cast<std::streamsize>(bytes))
    throw ImageFileError(path, "truncated PFM data (" + std::to_string(in.gcount()) + " of " +
                                   std::to_string(bytes) + " bytes)");
  const bool swap = little != (std::endian::native == std::endian::little);
  ImageF out(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint32_t v = raw[static_cast<std::size_t>(h - 1 - y) * w + x];
      if (swap) v = __builtin_bswap32(v);
      float f;
      std::memcpy(&f, &v, 4);
      out.at(x, y) = f;
    }
  return out;
}

void write_pfm(const std::filesystem::path& path, const ImageF& image) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw ImageFileError(path, "cannot create");
  out << "Pf\n" << image.width() << " " << image.height() << "\n-1.0\n";
  for (int y = image.height() - 1; y >= 0; --y) {
    for (int x = 0; x < image.width(); ++x) {
      float f = image.at(x, y);
      std::uint32_t v;
      std::memcpy(&v, &f, 4);
      if (std::endian::native != std::endian::little) v = __builtin_bswap32(v);
      out.write(reinterpret_cast<const char*>(&v), 4);
    }
  }
  if (!out) throw ImageFileError(path, "write failed");
}

}  // namespace probeless
