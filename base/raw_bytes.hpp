#pragma once
// Fixed-size values as their raw bytes in host order: the fields of the cache files
// (kernels/runtime/program_binary_cache.cpp, app/render/prt/prt_cache.cpp). Fine for files
// that never leave the machine that wrote them; not for anything exchanged.
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

namespace probeless {

template <typename T>
void put_raw(std::string& out, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// Reads one value from the front of `in` and drops it; false (nothing read) when `in` is
// shorter.
template <typename T>
bool get_raw(std::string_view& in, T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  if (in.size() < sizeof v) return false;
  std::memcpy(&v, in.data(), sizeof v);
  in.remove_prefix(sizeof v);
  return true;
}

}  // namespace probeless
