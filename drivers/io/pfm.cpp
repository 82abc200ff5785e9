#include "drivers/io/pfm.hpp"

#include <bit>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

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
  if (w <= 0 || h <= 0 || w > 1 << 15 || h > 1 << 15)
    throw ImageFileError(path, "bad PFM size " + std::to_string(w) + "x" + std::to_string(h));
  if (scale == 0) throw ImageFileError(path, "bad PFM scale 0");
  in.get();  // the single whitespace character after the scale
  const bool little = scale < 0;
  std::vector<std::uint32_t> raw(static_cast<std::size_t>(w) * h);
  in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(raw.size() * 4));
  if (in.gcount() != static_cast<std::streamsize>(raw.size() * 4))
    throw ImageFileError(path, "truncated PFM data (" + std::to_string(in.gcount()) + " of " +
                                   std::to_string(raw.size() * 4) + " bytes)");
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
