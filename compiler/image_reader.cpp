#include "compiler/image_reader.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace pbrtc {

namespace {

// The module's file name and where the build wrote it (compile definitions from CMake).
#ifndef PBRTC_IMAGE_MODULE_NAME
#error "PBRTC_IMAGE_MODULE_NAME must name the image module's file"
#endif

// The directory of the running program, with a trailing slash; "" if it cannot be told.
std::string program_dir() {
  std::string buf(4096, '\0');
  const ssize_t n = readlink("/proc/self/exe", buf.data(), buf.size());
  if (n <= 0 || size_t(n) >= buf.size()) return "";
  buf.resize(size_t(n));
  return buf.substr(0, buf.rfind('/') + 1);
}

std::vector<std::string> module_candidates() {
  if (const char* env = std::getenv("PBRTC_IMAGE_MODULE"); env && *env) {
    // A bare file name would make dlopen search the library path; the user means this folder.
    const std::string path = env;
    return {path.find('/') == std::string::npos ? "./" + path : path};
  }
  std::vector<std::string> places;
  if (std::string dir = program_dir(); !dir.empty())
    places.push_back(dir + PBRTC_IMAGE_MODULE_NAME);
#ifdef PBRTC_IMAGE_MODULE_BUILT
  if (places.empty() || places.back() != PBRTC_IMAGE_MODULE_BUILT)
    places.push_back(PBRTC_IMAGE_MODULE_BUILT);
#endif
  return places;
}

struct Module {
  ReadImageRgbFn read = nullptr;
  std::string error;  // why it could not be loaded, when read is null
};

Module load_module() {
  Module m;
  std::string tried;
  for (const std::string& path : module_candidates()) {
    // RTLD_NOW: an unresolvable symbol fails here, with a message, not at a later call (binding
    // lazily saved nothing measurable: 0.30-0.37 s either way). Not RTLD_GLOBAL: OpenImageIO's
    // symbols stay out of the program's namespace.
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    std::string why;
    if (handle) {
      m.read = reinterpret_cast<ReadImageRgbFn>(dlsym(handle, kReadImageRgbSymbol));
      if (m.read) return m;  // kept loaded for the life of the process
      why = path + ": no " + kReadImageRgbSymbol + " in it (a module from another pbrtc?)";
      dlclose(handle);
    } else {
      // dlerror names the module only when the module itself is missing; a library it needs
      // that is missing is named alone.
      const char* reason = dlerror();
      why = reason ? reason : "cannot be loaded";
      if (why.compare(0, path.size(), path) != 0) why = path + ": " + why;
    }
    tried += (tried.empty() ? "" : "; ") + why;
  }
  m.error = "cannot load pbrtc's image reader module (" + tried +
            "); set PBRTC_IMAGE_MODULE to the path of " + PBRTC_IMAGE_MODULE_NAME;
  return m;
}

}  // namespace

std::string image_module_file() {
  for (const std::string& path : module_candidates())
    if (access(path.c_str(), R_OK) == 0) return path;
  return "";
}

bool read_image_rgb(const std::string& path, RgbImage* out, std::string* error) {
  // A function-local static: loaded once, on the first image, even when several threads
  // decode images at once.
  static const Module module = load_module();
  if (!module.read) {
    *error = module.error;
    return false;
  }
  return module.read(path, out, error);
}

}  // namespace pbrtc
