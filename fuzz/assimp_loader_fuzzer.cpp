// libFuzzer target: the first byte picks the format Assimp reads the rest as
// (OBJ, PLY, STL, Collada, FBX, 3DS, OFF), given to the loader as it is. A
// LoadError (mbao::Error) or std::invalid_argument is the loader's answer to
// bad input; any other exception escaping, a crash, a sanitizer report, a
// hang or running out of memory is a finding. Assimp itself is Debian's
// build, uninstrumented: coverage feedback comes from mbao's side only.
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "core/error.h"
#include "scene/assimp_loader.h"

namespace {
const char* const kExtensions[] = {"obj", "ply", "stl", "dae", "fbx", "3ds", "off"};
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  try {
    const char* extension = kExtensions[data[0] % (sizeof kExtensions / sizeof *kExtensions)];
    mbao::LoadOptions options;
    options.import_seconds = 2.0;  // the limit's own error, well within the run's 10 s per input
    options.texcoords = true;      // the UV sets and materials too, which texture bakes read
    mbao::load_with_assimp_from_memory(data + 1, size - 1, "fuzz-input", extension, options);
  } catch (const mbao::Error&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
