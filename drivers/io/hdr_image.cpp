#include "drivers/io/hdr_image.hpp"

#include <Imath/half.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <openexr.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>

#include "core/read_limits.hpp"

namespace probeless {
namespace {

enum class HdrFormat { Radiance, OpenExr };

HdrFormat format_of(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  if (ext == ".hdr" || ext == ".pic") return HdrFormat::Radiance;
  if (ext == ".exr") return HdrFormat::OpenExr;
  throw ImageFileError(path, "unknown HDR image extension (expected .hdr, .pic or .exr)");
}

// Writes through "<path>.tmp" and renames, so readers never see half a file.
void write_atomically(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path&)>& write) {
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  try {
    write(tmp);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw ImageFileError(path, "cannot rename " + tmp.string() + ": " + ec.message());
  }
}

ImageRGBF read_radiance(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ImageFileError(path, std::string("cannot open: ") + std::strerror(errno));
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size > static_cast<std::uintmax_t>(read_limits::kMaxImageFileBytes))
    throw ImageFileError(path, std::to_string(size) + " bytes, over the limit of " +
                                   std::to_string(read_limits::kMaxImageFileBytes));
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                        std::istreambuf_iterator<char>());
  if (in.bad()) throw ImageFileError(path, "read error");
  return decode_radiance_hdr(bytes, path);
}

void write_radiance(const std::filesystem::path& path, const ImageRGBF& image) {
  const std::vector<std::uint8_t> bytes = encode_radiance_hdr(image);
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw ImageFileError(tmp, std::string("cannot create: ") + std::strerror(errno));
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw ImageFileError(tmp, "cannot write");
  });
}

// OpenEXR checks every header it reads against these (process-wide) maxima before it sizes
// its own tables from the data window; set once, before the first file is opened.
void limit_openexr_sizes() {
  static const bool once = [] {
    const int side = static_cast<int>(read_limits::kMaxImageSide);
    Imf::Header::setMaxImageSize(side, side);
    Imf::Header::setMaxTileSize(side, side);
    return true;
  }();
  (void)once;
}

// OpenEXR's C++ reader (3.1) allocates each header attribute at the size the file claims for
// it before reading the value (an opaque attribute of 1.6 GB from a 297-byte file, and one of
// 1.9 GB behind a channel list that its own parser reads past the declared size: found by
// tests/fuzz exr). The headers are therefore parsed first by OpenEXR's C core, which checks
// every attribute's size against its type (so the C++ reader's parse keeps in step with the
// declared sizes), with an allocator that refuses any one block larger than the file.
thread_local std::size_t openexr_header_alloc_cap = 0;

void* capped_alloc(std::size_t bytes) {
  return bytes > openexr_header_alloc_cap ? nullptr : std::malloc(bytes);
}

void no_error_printing(exr_const_context_t, exr_result_t, const char*) {}

void check_openexr_headers(const std::filesystem::path& path) {
  std::error_code ec;
  const auto file_size = std::filesystem::file_size(path, ec);
  if (ec) throw ImageFileError(path, "cannot read its size: " + ec.message());
  // The core's own bookkeeping (contexts, part tables) is a few KB whatever the file.
  openexr_header_alloc_cap = static_cast<std::size_t>(file_size) + (std::size_t{64} << 10);
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.alloc_fn = capped_alloc;
  init.free_fn = std::free;
  init.error_handler_fn = no_error_printing;
  init.max_image_width = init.max_image_height = static_cast<int>(read_limits::kMaxImageSide);
  init.max_tile_width = init.max_tile_height = static_cast<int>(read_limits::kMaxImageSide);
  // Strict: without it the core reports a size that does not fit the type and goes on.
  init.flags = EXR_CONTEXT_FLAG_STRICT_HEADER | EXR_CONTEXT_FLAG_SILENT_HEADER_PARSE;
  exr_context_t context = nullptr;
  const exr_result_t result = exr_start_read(&context, path.c_str(), &init);
  exr_finish(&context);
  if (result != EXR_ERR_SUCCESS)
    throw ImageFileError(
        path, std::string("OpenEXR: bad header (") + exr_get_default_error_message(result) + ")");
}

// Then every attribute's size against what is left of the file: each header is
// "name\0 type\0 int32-size value" repeated, ended by an empty name; a multi-part file has
// several headers and an empty one after the last.
void check_openexr_attribute_sizes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ImageFileError(path, std::string("cannot open: ") + std::strerror(errno));
  std::error_code ec;
  const auto file_size = std::filesystem::file_size(path, ec);
  if (ec) throw ImageFileError(path, "cannot read its size: " + ec.message());
  char start[8];
  if (!in.read(start, sizeof start)) throw ImageFileError(path, "not an OpenEXR file (too short)");
  const bool multi_part = (static_cast<unsigned char>(start[5]) & 0x10) != 0;  // version bit 12
  // A name or type string: at most 255 characters (long names) and its terminator.
  auto read_string = [&](const char* what) {
    std::string text;
    for (int c; (c = in.get()) != 0;) {
      if (c == std::char_traits<char>::eof() || text.size() == 255)
        throw ImageFileError(path, std::string("OpenEXR: bad header (") + what + ")");
      text.push_back(static_cast<char>(c));
    }
    return text;
  };
  for (;;) {
    for (;;) {
      const std::string name = read_string("attribute name");
      if (name.empty()) break;
      read_string("attribute type");
      unsigned char le[4];
      if (!in.read(reinterpret_cast<char*>(le), 4))
        throw ImageFileError(path, "OpenEXR: bad header (attribute size)");
      const std::int32_t size =
          static_cast<std::int32_t>(std::uint32_t{le[0]} | std::uint32_t{le[1]} << 8 |
                                    std::uint32_t{le[2]} << 16 | std::uint32_t{le[3]} << 24);
      const std::streamoff here = in.tellg();
      if (size < 0 || here < 0 ||
          static_cast<std::uintmax_t>(here) + static_cast<std::uint32_t>(size) > file_size)
        throw ImageFileError(
            path, "OpenEXR: attribute '" + name + "' of " + std::to_string(size) + " bytes, but " +
                      std::to_string(file_size - static_cast<std::uintmax_t>(
                                                     std::max<std::streamoff>(here, 0))) +
                      " bytes are left in the file");
      in.seekg(size, std::ios::cur);
    }
    if (!multi_part) return;
    if (in.peek() == 0) return;  // the empty header after the last
    if (in.peek() == std::char_traits<char>::eof())
      throw ImageFileError(path, "OpenEXR: bad header (the file ends in the headers)");
  }
}

ImageRGBF read_openexr(const std::filesystem::path& path) {
  limit_openexr_sizes();
  check_openexr_headers(path);
  check_openexr_attribute_sizes(path);
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const long w = static_cast<long>(dw.max.x) - dw.min.x + 1;
    const long h = static_cast<long>(dw.max.y) - dw.min.y + 1;
    if (!read_limits::image_size_ok(w, h))
      throw ImageFileError(path, "bad data window " + std::to_string(w) + "x" + std::to_string(h) +
                                     " (limits: " + std::to_string(read_limits::kMaxImageSide) +
                                     " a side, " + std::to_string(read_limits::kMaxImagePixels) +
                                     " pixels)");
    // The file must at least hold the chunks of so many scanlines (tiles are no smaller).
    const auto chunks =
        (h + read_limits::kMaxExrScanlinesPerChunk - 1) / read_limits::kMaxExrScanlinesPerChunk;
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec || size < static_cast<std::uintmax_t>(chunks * read_limits::kMinExrBytesPerChunk))
      throw ImageFileError(path, "truncated: " + std::to_string(h) + " scanlines need at least " +
                                     std::to_string(chunks * read_limits::kMinExrBytesPerChunk) +
                                     " bytes, the file has " + std::to_string(ec ? 0 : size));
    // Every chunk of the data window in the offset table (OpenEXR finds the ones a truncated
    // table lost): a file that ends early is refused before its pixels are allocated.
    if (!file.isComplete())
      throw ImageFileError(path, "truncated: chunks of the image are missing");
    ImageRGBF image(static_cast<int>(w), static_cast<int>(h));
    const Imf::ChannelList& channels = file.header().channels();
    const bool rgb =
        channels.findChannel("R") && channels.findChannel("G") && channels.findChannel("B");
    if (!rgb && !channels.findChannel("Y")) throw ImageFileError(path, "no R, G, B or Y channels");
    constexpr std::size_t kPixel = 3 * sizeof(float);
    const std::size_t row_bytes = kPixel * static_cast<std::size_t>(w);
    Imf::FrameBuffer fb;
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < (rgb ? 3 : 1); ++c)
      fb.insert(rgb ? names[c] : "Y",
                Imf::Slice::Make(Imf::FLOAT, image.data() + c, dw, kPixel, row_bytes));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    if (!rgb)
      for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
          image.at(x, y, 1) = image.at(x, y, 2) = image.at(x, y, 0);
    return image;
  } catch (const ImageFileError&) {
    throw;
  } catch (const std::exception& e) {  // Iex::BaseExc and std::bad_alloc
    throw ImageFileError(path, std::string("OpenEXR: ") + e.what());
  }
}

void write_openexr(const std::filesystem::path& path, const ImageRGBF& image, bool half) {
  // Output files do not convert pixel types, so half channels are written from a half copy.
  std::vector<Imath::half> halves;
  if (half) halves.assign(image.elements().begin(), image.elements().end());
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    try {
      Imf::Header header(image.width(), image.height());
      header.compression() = Imf::ZIP_COMPRESSION;
      const Imf::PixelType type = half ? Imf::HALF : Imf::FLOAT;
      const std::size_t sample = half ? sizeof(Imath::half) : sizeof(float);
      // OpenEXR's slices take a non-const pointer for reading and writing alike.
      char* base = half ? reinterpret_cast<char*>(halves.data())
                        : reinterpret_cast<char*>(const_cast<float*>(image.data()));
      const std::size_t row_bytes = 3 * sample * static_cast<std::size_t>(image.width());
      Imf::FrameBuffer fb;
      const char* names[3] = {"R", "G", "B"};
      for (int c = 0; c < 3; ++c) {
        header.channels().insert(names[c], Imf::Channel(type));
        fb.insert(names[c], Imf::Slice(type, base + c * sample, 3 * sample, row_bytes));
      }
      Imf::OutputFile file(tmp.c_str(), header);
      file.setFrameBuffer(fb);
      file.writePixels(image.height());
    } catch (const std::exception& e) {
      throw ImageFileError(tmp, std::string("OpenEXR: ") + e.what());
    }
  });
}

}  // namespace

ImageRGBF read_hdr_image(const std::filesystem::path& path) {
  return format_of(path) == HdrFormat::Radiance ? read_radiance(path) : read_openexr(path);
}

void write_hdr_image(const std::filesystem::path& path, const ImageRGBF& image,
                     HdrWriteOptions options) {
  const HdrFormat format = format_of(path);
  if (image.empty()) throw ImageFileError(path, "cannot write an empty image");
  if (format == HdrFormat::Radiance)
    write_radiance(path, image);
  else
    write_openexr(path, image, options.exr_half);
}

}  // namespace probeless
