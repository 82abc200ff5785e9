#pragma once
// What the fuzz targets share (docs/security.md "Fuzzing"). Most readers take a path, so the
// input is written to a file in a private directory made once per process and read back
// through the reader's real entry point. A reader may refuse an input only with the errors it
// documents (all std::runtime_error: ParseError, ImageFileError, toml::parse_error, ...);
// anything else escapes LLVMFuzzerTestOneInput and libFuzzer reports it as a crash
// (std::bad_alloc from an unchecked size, std::out_of_range from an unchecked index).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace probeless::fuzz {

// A directory of this process's own under $TMPDIR, removed at exit.
inline const std::filesystem::path& scratch_dir() {
  struct Dir {
    std::filesystem::path path;
    Dir() {
      const char* tmp = std::getenv("TMPDIR");
      std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/probeless-fuzz-XXXXXX";
      if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
      path = pattern;
    }
    ~Dir() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static const Dir dir;
  return dir.path;
}

inline std::filesystem::path write_scratch(const std::string& name, std::string_view bytes) {
  const std::filesystem::path path = scratch_dir() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::logic_error("cannot write " + path.string());
  return path;
}

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Runs `read`; the reader's own refusals (std::runtime_error and its subclasses) are the
// expected outcome of most inputs and end the run quietly.
template <typename Read>
void expect_accept_or_refuse(Read&& read) {
  try {
    read();
  } catch (const std::runtime_error&) {
  }
}

}  // namespace probeless::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace probeless::fuzz {

// Inputs made of several files (a config and its board file, a recording's manifest and
// indexes) are the files' texts joined by this line; the seeds show the layout.
inline constexpr std::string_view kPartSeparator = "\n#~~next-file~~\n";

inline std::vector<std::string_view> split_parts(std::string_view text, std::size_t max_parts) {
  std::vector<std::string_view> parts;
  while (parts.size() + 1 < max_parts) {
    const std::size_t at = text.find(kPartSeparator);
    if (at == std::string_view::npos) break;
    parts.push_back(text.substr(0, at));
    text.remove_prefix(at + kPartSeparator.size());
  }
  parts.push_back(text);
  return parts;
}

// Writes parts[i] as names[i] in the scratch directory and removes the files of the names
// the input has no part for (so that no file is left over from the previous input).
inline void write_parts(std::string_view text, const std::vector<std::string>& names) {
  const auto parts = split_parts(text, names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i < parts.size()) {
      write_scratch(names[i], parts[i]);
    } else {
      std::error_code ec;
      std::filesystem::remove(scratch_dir() / names[i], ec);
    }
  }
}

}  // namespace probeless::fuzz
