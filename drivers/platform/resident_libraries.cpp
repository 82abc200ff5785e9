#include "drivers/platform/resident_libraries.hpp"

#include <dlfcn.h>
#include <link.h>

#include <string>
#include <vector>

namespace probeless::platform {

int keep_loaded_until_exit(const std::function<bool(std::string_view path)>& matches) {
  struct Search {
    const std::function<bool(std::string_view)>* matches;
    std::vector<std::string> paths;
  } search{&matches, {}};
  // Only collect in the callback: dl_iterate_phdr holds the loader's lock, and dlopen takes it.
  ::dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* data) {
        auto* s = static_cast<Search*>(data);
        const std::string_view path = info->dlpi_name != nullptr ? info->dlpi_name : "";
        if (path.empty()) return 0;  // the executable itself
        if ((*s->matches)(path)) s->paths.emplace_back(path);
        return 0;
      },
      &search);
  int marked = 0;
  for (const auto& path : search.paths) {
    // RTLD_NOLOAD on a loaded object only adds a reference and, with RTLD_NODELETE, the mark;
    // closing the handle drops the reference and keeps the mark.
    if (void* handle = ::dlopen(path.c_str(), RTLD_LAZY | RTLD_NOLOAD | RTLD_NODELETE)) {
      ::dlclose(handle);
      ++marked;
    }
  }
  return marked;
}

}  // namespace probeless::platform
