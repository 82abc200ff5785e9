#pragma once
// Libraries that must stay loaded until the process exits.
//
// Some plug-in hosts (Mesa's EGL loading its gallium driver, OpenNI2 loading its device
// drivers) dlclose() what they loaded on shutdown, although the plug-in keeps process-lifetime
// state in its own globals. The state is then stranded: LeakSanitizer reports it from
// "<unknown module>" (nothing can symbolise or suppress it), and the next initialise loads a
// fresh copy and strands it again. Marking the loaded object RTLD_NODELETE keeps it resident,
// as its globals assume.

#include <functional>
#include <string_view>

namespace probeless::platform {

// Marks every loaded shared object whose path (as the loader holds it) satisfies `matches` as
// never to be unloaded. Loads nothing that is not loaded yet. Returns how many were marked.
int keep_loaded_until_exit(const std::function<bool(std::string_view path)>& matches);

// The file name of a path: what follows its last '/'.
constexpr std::string_view file_name(std::string_view path) {
  return path.substr(path.rfind('/') + 1);
}

}  // namespace probeless::platform
